// rcsim — the register set-ups WorstClocks (worst_clocks.h) tries an instruction with: the
// alignments of its operands and the operand values MUL/IMUL/DIV/IDIV's time depends on.
#pragma once

#include "comm_cpu/i8086/cpu.h"

#include <cstdint>
#include <vector>

namespace rcsim::i8086::worst_setups {

// Alignment set-ups: the base and index registers and SP even and odd, so that every ModR/M
// form's effective address, both string pointers (alone and mixed) and the stack take both
// parities; every other general register follows the same parity (a jump through one).
std::vector<Registers> alignments(std::uint16_t cx);

// Operand values for MUL/IMUL/DIV/IDIV (accumulator, DX, the r/m operand): CORX costs a clock
// per one bit of the multiplier and IMUL more for negative operands; CORD a clock more per
// quotient bit found by a trial subtraction, IDIV more for negative operands. So: many one
// bits, every sign combination, quotients of all ones from small divisors, and a fixed
// pseudo-random spread for what the structure misses.
struct Values {
    std::uint16_t ax, dx, operand;
};

std::vector<Values> muldiv_values(bool word);

} // namespace rcsim::i8086::worst_setups
