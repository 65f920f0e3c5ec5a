// rcsim — the DP-RAM layout and mailbox words of docs/system.md §4: the interface the two boards
// share (the main CPU, the measurement probes and the demo use it; the firmware restates it in C,
// comm_cpu/firmware/fw.h, and tests/comm_cpu/firmware checks the two agree).
//
//   p*340 + 0 .. p*340 + 338   data[p]   chunk of frame bytes for port p (p = 0, 1, 2)
//   p*340 + 339                pflag[p]  0 free, 1 EXT_USE (comm CPU), 2 RBT_USE (main CPU)
//   0x3FE                      int2ext   main CPU -> comm CPU mailbox (raises INT_L)
//   0x3FF                      int2rbt   comm CPU -> main CPU mailbox (raises INT_R)
//
// Mailbox word: low nibble = port, high nibble = kind (1 new chunk, 2 chunk consumed, 3 reset;
// comm CPU -> main CPU only: 4 a response given up unsent, 5 given up after it left whole).
#pragma once

#include <cstdint>

namespace rcsim::dpram_layout {

constexpr unsigned ports = 3;
constexpr unsigned area_size = 340;
constexpr unsigned chunk_size = 339;
constexpr std::uint16_t int2ext = 0x3FE;
constexpr std::uint16_t int2rbt = 0x3FF;

constexpr std::uint8_t pflag_free = 0;
constexpr std::uint8_t pflag_ext_use = 1;
constexpr std::uint8_t pflag_rbt_use = 2;

constexpr std::uint8_t kind_chunk = 0x1;
constexpr std::uint8_t kind_ack = 0x2;
constexpr std::uint8_t kind_reset = 0x3;
// The comm CPU gave up on the oldest response frame of the port after its retries and dropped it
// (only that one: the port is not reset). 0x4p: it never left whole, the host cannot have it;
// 0x5p: it left whole at least once but no EOT came, the host may have it.
constexpr std::uint8_t kind_gave_up = 0x4;
constexpr std::uint8_t kind_gave_up_sent = 0x5;

constexpr std::uint16_t data_addr(unsigned port) { return static_cast<std::uint16_t>(port * area_size); }
constexpr std::uint16_t pflag_addr(unsigned port) {
    return static_cast<std::uint16_t>(port * area_size + chunk_size);
}
constexpr std::uint8_t word(std::uint8_t kind, unsigned port) {
    return static_cast<std::uint8_t>((kind << 4) | (port & 0xF));
}
constexpr std::uint8_t word_kind(std::uint8_t w) { return w >> 4; }
constexpr unsigned word_port(std::uint8_t w) { return w & 0xF; }

} // namespace rcsim::dpram_layout
