// rcsim — the dynamic half of coverage: per address of a code region, how often an instruction
// started there, and for the conditional jumps (Jcc, JCXZ, LOOP, LOOPZ, LOOPNZ) how often each
// way was taken.
//
// Fed at every instruction boundary (i8086::StepHook: the instruction at cpu.pc() is about to
// execute, so it counts as executed, never one that was only prefetched). Whether a conditional
// jump is taken is decided there from the flags and CX the instruction is about to test (the
// 8086 manual's conditions, Intel 8086 Family User's Manual, table 2-21): the same answer as
// "the next executed instruction is its target", and still right when an interrupt is
// recognised at the jump's end and the next boundary is the handler's.
#pragma once

#include "comm_cpu/i8086/cpu.h"
#include "scenarios/coverage/code_map.h"
#include "scenarios/coverage/tracefile.h"

#include <cstdint>
#include <vector>

namespace rcsim::coverage {

class Counters {
public:
    /// The region [base, base + code.size()): `code` is its bytes (the opcodes are read from it).
    Counters(std::uint32_t base, std::vector<std::uint8_t> code);

    void step(const i8086::Cpu& cpu) { count(cpu.pc(), cpu.regs(), 1); }
    /// Boundaries the core's fast-forward went past (i8086::SkipHook), each `times` times.
    void skipped(const i8086::Boundary* b, std::size_t n, std::uint64_t times) {
        for (std::size_t i = 0; i < n; ++i) count(b[i].pc, b[i].regs, times);
    }

    std::uint32_t base() const { return base_; }
    std::uint64_t executed(std::uint32_t linear) const { return at(executed_, linear); }
    std::uint64_t taken(std::uint32_t linear) const { return at(taken_, linear); }
    std::uint64_t not_taken(std::uint32_t linear) const { return at(not_taken_, linear); }
    /// The conditional jump's opcode at `linear` (after prefixes), 0 when it holds none.
    std::uint8_t jump_opcode(std::uint32_t linear) const {
        const std::uint32_t off = linear - base_;
        return off < jump_.size() ? jump_[off] : 0;
    }

    /// The tracefile of `map` from these counts.
    Tracefile tracefile(const CodeMap& map) const;

private:
    void count(std::uint32_t pc, const i8086::Registers& r, std::uint64_t times) {
        const std::uint32_t off = pc - base_;
        if (off >= executed_.size()) return; // outside the region (code in RAM)
        executed_[off] += times;
        if (const std::uint8_t op = jump_[off]) (taken(op, r) ? taken_ : not_taken_)[off] += times;
    }
    static bool taken(std::uint8_t opcode, const i8086::Registers& r);
    std::uint64_t at(const std::vector<std::uint64_t>& v, std::uint32_t linear) const {
        const std::uint32_t off = linear - base_;
        return off < v.size() ? v[off] : 0;
    }

    std::uint32_t base_;
    std::vector<std::uint8_t> jump_; // per address: the conditional jump's opcode, or 0
    std::vector<std::uint64_t> executed_, taken_, not_taken_;
};

} // namespace rcsim::coverage
