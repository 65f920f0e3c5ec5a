// rcsim — the worst-case clocks of one 8086 instruction, measured on the core. See worst_clocks.h.
#include "comm_cpu/i8086/worst_clocks.h"

namespace rcsim::i8086 {

struct WorstClocks::Harness {};

WorstClocks::WorstClocks(const WaitBounds& waits) : waits_(waits), harness_(std::make_unique<Harness>()) {}
WorstClocks::~WorstClocks() = default;

// Placeholder until the measurement lands: a rough over-estimate.
unsigned WorstClocks::instruction(const std::uint8_t* bytes, unsigned length, std::uint16_t ip, std::uint32_t cx_max) {
    return measure(std::vector<std::uint8_t>(bytes, bytes + length), ip, cx_max);
}

unsigned WorstClocks::measure(const std::vector<std::uint8_t>& bytes, std::uint16_t, std::uint32_t cx_max) {
    unsigned c = 30 + 8 * unsigned(bytes.size());
    if (!bytes.empty() && (bytes[0] == 0xF3 || bytes[0] == 0xF2)) c += 20 * (cx_max & 0xFFFF);
    return c;
}

unsigned WorstClocks::interrupt_entry() { return 61 + 2 * waits_.data * 5; }

} // namespace rcsim::i8086
