// rcsim — the communication board: 8086-2, 64 KB ROM, 64 KB RAM, three 82510s, one 8259A, and the
// left port of the IDT7130 (docs/system.md §2.1; the paper's Table 1).
//
// Memory map (defaults, all configurable): RAM 00000-0FFFF, DP-RAM D0000-D03FF, ROM F0000-FFFFF.
// I/O map: 82510 #n register r at 0x80 + 0x10n + 2r; 8259A at 0xC0 (A0=0) and 0xC2 (A0=1).
// Wait states: RAM 0, ROM 1, DP-RAM 0 (+ BUSY), I/O 1. IR0..IR2 = 82510 #0..#2, IR3 = DP-RAM INT_L.
#pragma once

#include "comm_cpu/cpu8086.h"
#include "models/clock.h"
#include "models/irq.h"
#include "models/rom_image.h"
#include "models/router.h"
#include "pic8259/pic8259.h"
#include "uart82510/uart82510.h"

#include <systemc>

#include <cstdint>
#include <string>
#include <vector>

namespace rcsim {

class Idt7130;

struct CommBoardConfig {
    std::uint64_t cpu_hz = 8'000'000;
    std::uint64_t uart_clock_hz = 18'432'000;
    std::uint32_t ram_base = 0x00000, ram_size = 0x10000;
    std::uint32_t rom_base = 0xF0000, rom_size = 0x10000;
    std::uint32_t dpram_base = 0xD0000;
    std::uint16_t uart_io_base = 0x80, uart_io_stride = 0x10;
    std::uint16_t pic_io_base = 0xC0;
    unsigned ram_wait = 0, rom_wait = 1, dpram_wait = 0, io_wait = 1;
    sc_core::sc_time quantum = us(Cpu8086::kDefaultQuantumUs); // upper bound of one decoupled CPU slice
    bool lookahead = true;             // bound slices by the next pending kernel event
    bool fast_sync = true;             // a TLM access ends the slice only when it left activity now
    bool fast_forward = true;          // the core's exact idle fast-forward (docs/performance.md)
    bool stable_reads = true;          // reads a target declares stable skip the kernel sync
    bool slice_chain = true;           // slices ending before the next event follow inside the core
};

class CommBoard : public sc_core::sc_module {
public:
    static constexpr unsigned kPorts = 3;
    static constexpr unsigned kDpramIr = 3;

    const CommBoardConfig config;
    Cpu8086 cpu;
    Router io;  // I/O space decoder
    Router mem; // memory outside the direct map (the DP-RAM window)
    Pic8259 pic;
    sc_core::sc_vector<Uart82510> uart;

    IrqLine intr{"intr"};
    IrqLine nmi{"nmi"};
    sc_core::sc_vector<IrqLine> uart_int;
    IrqLine unused_ir{"unused_ir"}; // IR4..IR7: no request

    CommBoard(sc_core::sc_module_name name, const CommBoardConfig& config = CommBoardConfig());

    /// Connects the DP-RAM's left port and its INT_L line (8259A IR3). Call once, before sc_start.
    void connect_dpram(Idt7130& dpram, IrqLine& int_l);

    /// Loads a ROM image in any format models/rom_image.h reads (raw, mirrored when smaller,
    /// Intel HEX, an even/odd EPROM pair). Throws ConfigError naming the file.
    void load_rom(const RomSource& source);
    void load_rom(const std::string& path) { load_rom(RomSource{path, {}}); }
    /// Loads raw bytes; they must be exactly rom_size bytes.
    void load_rom(const std::vector<std::uint8_t>& image, const std::string& what = "ROM image");
    /// What the last load_rom(source) read, e.g. "raw 64 KB" or "Intel HEX, 12288 bytes".
    const std::string& rom_format() const { return rom_format_; }

    std::vector<std::uint8_t>& ram() { return ram_; }
    std::vector<std::uint8_t>& rom() { return rom_; }
    std::uint16_t uart_io_address(unsigned port, unsigned reg) const {
        return static_cast<std::uint16_t>(config.uart_io_base + config.uart_io_stride * port + 2 * reg);
    }

private:
    std::vector<std::uint8_t> ram_, rom_;
    std::string rom_format_ = "raw";
};

} // namespace rcsim
