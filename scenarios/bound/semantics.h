// rcsim — what an instruction states about the registers, the stack, IF and the EOI: the abstract
// values the control flow of scenarios/bound/flow.h carries along its edges. Intervals of the
// general registers (and of their bytes), the words on the stack and who wrote each register;
// joins where paths meet, widening where they keep changing.
#pragma once

#include "scenarios/bound/flow.h"

#include <cstdint>

namespace rcsim::bound {

Interval join(const Interval& a, const Interval& b);
IfState join_if(IfState a, IfState b);
/// The state where two paths meet: each value as wide as both ways give it.
State join(const State& a, const State& b);
/// After repeated updates: every interval that still moves goes to the top.
void widen(State& s, const State& before);

Interval get_reg(const State& s, unsigned r, unsigned width);
/// Writes register r (0..7 of `width` bytes: AX..DI or AL..BH), the writer being s.now.
void set_reg(State& s, unsigned r, unsigned width, const Interval& v);
void push(State& s, const StackWord& w);
StackWord pop(State& s);

/// The interval a jump's condition leaves the compared register on one edge (false: the edge
/// cannot be taken). `cc` is the condition's low nibble (70-7F numbering).
bool refine(State& s, unsigned cc, bool taken);
/// What an instruction that is not a transfer of control does to the state. `pic_port`: the
/// 8259A's A0 = 0 port, where an OCW2 with the EOI bit is the source's EOI.
void execute(const Insn& n, State& s, std::uint8_t pic_port);

} // namespace rcsim::bound
