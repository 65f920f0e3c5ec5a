// rcsim — the worst-case clocks of one 8086 instruction, measured on the core itself.
//
// The static bound (scenarios/bound/, docs/tools.md "Bound") adds up instruction times along a
// firmware's paths. It takes them from here, and here they come from running the instruction on
// this folder's bus-cycle-exact core (Cpu) under every condition the instruction can meet at
// run time that changes its time: the prefetch queue and the BIU's phase at its boundary (set up
// by preambles of other instructions before it), the alignment of its memory and stack operands,
// the operand values its microcode's time depends on (MUL/DIV, shifts by CL, REP counts), the
// flags a conditional transfer tests (taken and not taken), and the board's wait states per kind
// of bus cycle. The worst of those runs is the bound, so the bound and the simulation cannot
// disagree on what an instruction costs: a test runs every SingleStepTests vector and every
// instruction of the shipped scenarios against it (tests/comm_cpu/i8086/worst_clocks_test.cpp,
// tests/scenarios/bound/).
//
// An instruction's time is measured boundary to boundary as Cpu::step() spends it: from the
// clock after the opcode byte was read to the clock after the next instruction's opcode byte was
// read (for a transfer, the target's). The sum over a path is the path's time.
//
// That sum assumes every instruction's worst BIU state, most often an empty queue refilled
// through the ROM's wait state, at every boundary; along a straight line the queue fills while
// slow instructions run, so the sum of ten instructions is about twice what they ever take.
// sequence() measures a whole straight-line run at once: the worst BIU state at its first
// boundary only, the later ones as the run itself leaves them. branch() does the same for a run
// that ends in a conditional transfer, each outcome apart (a compare chain's fall-through edges
// cost about half the taken ones).
#pragma once

#include "comm_cpu/i8086/cpu.h"

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

namespace rcsim::i8086 {

/// The wait states an instruction's bus cycles can meet on the board, per kind of cycle: each the
/// worst of every region that kind can reach (the analysis does not know segment values).
struct WaitBounds {
    unsigned code = 1; ///< code fetches (the region the code runs from: the ROM)
    unsigned data = 1; ///< memory reads and writes, stack included (the worst data region, DP-RAM BUSY included)
    unsigned io = 1;   ///< IN / OUT
    unsigned inta = 0; ///< the two INTA cycles of an interrupt entry
    bool operator<(const WaitBounds& o) const {
        return std::tie(code, data, io, inta) < std::tie(o.code, o.data, o.io, o.inta);
    }
};

/// One instruction of a straight-line run given to WorstClocks::sequence(): `bytes[0 .. length)`
/// hold it (more may follow: only the instruction decode() finds at `bytes` is taken) and it
/// starts at offset `ip` of its code segment.
struct Piece {
    const std::uint8_t* bytes;
    unsigned length;
    std::uint16_t ip;
};

/// The worst clocks of a line that ends in a conditional transfer, each outcome apart
/// (WorstClocks::branch()).
struct Outcomes {
    unsigned taken = 0;     ///< to the target's opcode read
    unsigned not_taken = 0; ///< to the next instruction's opcode read
};

class WorstClocks {
public:
    explicit WorstClocks(const WaitBounds& waits);
    ~WorstClocks();
    WorstClocks(const WorstClocks&) = delete;
    WorstClocks& operator=(const WorstClocks&) = delete;

    /// The worst clocks of the instruction `bytes[0 .. length)` (prefixes included) at offset
    /// `ip` of its code segment. `cx_max` is the largest value CX can hold at it: the count of a
    /// REP string instruction (the whole run of at most cx_max elements is one instruction) and,
    /// by its low byte or 255 when larger, of a shift or rotate by CL. Every other operand value
    /// is taken at its worst. A run that raises a divide error (the harness sees a read of the
    /// type-0 vector, 00000-00003) is not a time of this instruction (the firmware's divide-error
    /// handler is another path) and is left out; only a form that faults on every run (DIV AH)
    /// is given what those runs took.
    unsigned instruction(const std::uint8_t* bytes, unsigned length, std::uint16_t ip, std::uint32_t cx_max = 0xFFFF);

    /// The worst clocks of running `pieces` in order: from the boundary before the first to the
    /// boundary after the last (the next instruction's opcode read, as instruction() measures
    /// one), under the conditions instruction() varies at the first boundary (BIU states,
    /// alignments, fill patterns, the same wait states); the later boundaries meet what the run
    /// leaves. One piece gives exactly instruction()'s bound.
    ///
    /// The pieces follow the flow: each next piece's ip is where the previous one goes (the next
    /// instruction, or a direct JMP/CALL's target: rel8, rel16 and ptr16:16 are allowed, a far
    /// one moving to its segment), and two pieces at one address hold the same bytes. No piece
    /// is a form whose time depends on what this does not vary or whose flow it does not know:
    /// a conditional transfer (Jcc, LOOP/LOOPE/LOOPNE, JCXZ), a return or IRET, a transfer
    /// through a register or memory (FF /2../5), INT/INT3/INTO, HLT, a REP string instruction,
    /// a shift or rotate by CL, MUL/IMUL/DIV/IDIV, AAM or AAD: those keep their own
    /// instruction() bound. The exception is the LAST piece, which may be a return (RET, RETF,
    /// with or without an immediate, their aliases C0/C1/C8/C9) or IRET: where it returns to
    /// is what the stack holds, the fill (FFFF or 0000: an odd and an even target, which fetch
    /// differently) or what the earlier pieces pushed there. A piece that breaks any of this
    /// throws std::invalid_argument.
    unsigned sequence(const std::vector<Piece>& pieces);

    /// The worst clocks of a line whose LAST piece is a conditional transfer (Jcc 70-7F and its
    /// aliases 60-6F, LOOPNE/LOOPE/LOOP E0-E2, JCXZ E3), each outcome measured apart: the
    /// outcome is forced at the branch's boundary by writing FLAGS and CX there (a register
    /// write changes no bus timing), so `taken` runs to the target's opcode read and
    /// `not_taken` to the next instruction's. The pieces before it follow sequence()'s rules
    /// (none may be a return); one piece, the branch alone, is allowed, and then the larger
    /// outcome is instruction()'s bound. Anything else throws std::invalid_argument.
    Outcomes branch(const std::vector<Piece>& pieces);

    /// Whether sequence() and branch() take the instruction at `bytes` (offset `ip`) as a piece
    /// anywhere in a line: its bytes hold all of it and it is none of the forms sequence()
    /// leaves to instruction() or lets only end a line (a return, a conditional transfer).
    static bool sequenceable(const std::uint8_t* bytes, unsigned length, std::uint16_t ip);

    /// The worst clocks of an interrupt entry: from the boundary at which INTR is taken (the two
    /// INTA cycles, the pushes of FLAGS, CS and IP, the vector's two words) to the boundary of
    /// the handler's first instruction (its opcode byte read).
    unsigned interrupt_entry();

    const WaitBounds& waits() const { return waits_; }

private:
    struct Harness;
    struct Code; // the pieces as the harness lays them out, by address
    Code lay_out(const std::vector<Piece>& pieces, bool branch, std::string& key) const;
    unsigned measure(const Code& code, std::uint32_t cx_max);
    WaitBounds waits_;
    std::unique_ptr<Harness> harness_;
    std::map<std::string, unsigned> cache_;    // bytes, ip parity and cx_max -> clocks
    std::map<std::string, unsigned> sequences_; // each piece's bytes and ip parity -> clocks
    std::map<std::string, Outcomes> branches_;  // the same, for branch()
    unsigned entry_ = 0;                    // interrupt_entry(), once measured
};

} // namespace rcsim::i8086
