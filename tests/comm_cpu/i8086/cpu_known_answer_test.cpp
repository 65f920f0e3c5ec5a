// Known-answer tests of multi-instruction programs on the bare 8086 core (no SystemC), for what
// the SingleStepTests vectors cannot check (no interrupts, no wait states, one instruction per
// test): hardware interrupt entry, NMI, the TF trap, INTR during REP, HLT wake, and every kind
// of bus cycle with 1-3 wait states.
//
// Every expected clock count is derived in a comment from the documented cycle structure: a
// bus cycle is T1 T2 T3 T4 with the Tw states inserted between T3 and T4 (8086 data sheet); an
// instruction's clocks run from the queue read of its first byte to that of the next one (the
// SingleStepTests convention, which reproduces the iAPX 86/88 User's Manual best-case counts
// when the queue holds the instruction); the interrupt sequence (data sheet, User's Manual):
// two back-to-back INTA cycles with LOCK from T2 of the first to T2 of the second and the type
// on D7-D0 in the second, then the vector read, FLAGS/CS/IP pushed and the handler fetched.
#include "comm_cpu/i8086/cpu.h"
#include "tests/comm_cpu/i8086/cpu_board.h"
#include "tests/support/sc_test.h"

#include <vector>

using namespace rcsim;
using namespace rcsim::i8086;
using rcsim::i8086::test::Board;
using rcsim::i8086::test::kStack;
using rcsim::i8086::test::kWindow;

namespace {

// Clock (trace row) of every queue read of a first byte: row k reports the queue operation of
// clock k-1, the same offset for every row, so differences are instruction lengths.
std::vector<std::size_t> first_reads(const std::vector<CycleRecord>& trace) {
    std::vector<std::size_t> f;
    for (std::size_t k = 0; k < trace.size(); ++k)
        if (trace[k].qop == QueueOp::first) f.push_back(k);
    return f;
}

// The T-states of the bus cycle whose T1 is row k, up to and including its T4.
std::vector<TState> cycle_states(const std::vector<CycleRecord>& trace, std::size_t k) {
    std::vector<TState> s;
    for (; k < trace.size(); ++k) {
        s.push_back(trace[k].t);
        if (trace[k].t == TState::T4) break;
    }
    return s;
}

std::vector<TState> expected_states(unsigned waits) {
    std::vector<TState> s{TState::T1, TState::T2, TState::T3};
    s.insert(s.end(), waits, TState::Tw);
    s.push_back(TState::T4);
    return s;
}

// Every bus cycle of `kind` in the trace is T1 T2 T3 Tw*waits T4, with the data moving in the
// last of T3/Tw. Returns how many there were.
unsigned check_cycles(const std::vector<CycleRecord>& trace, Bus kind, unsigned waits) {
    unsigned n = 0;
    for (std::size_t k = 0; k < trace.size(); ++k) {
        if (!trace[k].ale || trace[k].status != kind) continue;
        const std::vector<TState> s = cycle_states(trace, k);
        if (s.back() != TState::T4) continue; // still running when the trace ends
        ++n;
        EXPECT_EQ(s, expected_states(waits)) << to_string(kind) << " cycle at row " << k;
        // The transfer is flagged on the clock before T4 only.
        for (std::size_t i = 0; i < s.size(); ++i)
            EXPECT_EQ(trace[k + i].transfer, i + 2 == s.size()) << to_string(kind) << " row " << k + i;
    }
    return n;
}

// SHL SI,CL with CL = 16: 8 + 4 * 16 = 72 clocks (User's Manual), long enough for the BIU to
// fill the queue, so the instruction after it starts from a full queue as in the manual's counts.
const std::vector<std::uint8_t> kFill = {0xD3, 0xE6};
const std::vector<std::uint8_t> kNop = {0x90};

std::vector<std::uint8_t> operator+(std::vector<std::uint8_t> a, const std::vector<std::uint8_t>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

} // namespace

// IN AL,DX / OUT DX,AL (I/O read and write) and MOV AL,[BX] / MOV [BX],AL (memory read and write
// through the handler window) with 0-3 wait states, each from a full queue at an even address
// (there the queue holds 6 bytes; at an odd one at most 5, and OUT then takes 9 clocks, as the
// SingleStepTests EE captures show).
// Expected (User's Manual, 8086 column): IN AL,DX 8, OUT DX,AL 8, MOV r8,m 8+EA, MOV m,r8 9+EA
// with EA([BX]) = 5, so 13 and 14 clocks; the EU waits for the single bus cycle of each, which
// the Tw states lengthen one clock each: + w. (With a full queue no prefetch competes.)
TEST(Cpu8086KnownAnswer, IoAndMemoryCyclesStretchByTheirWaitStates) {
    for (unsigned w = 0; w <= 3; ++w) {
        Board b(0, true);
        b.io_waits = w;
        b.window_waits = w;
        b.cpu.regs().r[CX] = 16;
        b.cpu.regs().r[DX] = 0x40;
        b.cpu.regs().r[BX] = 0x10;
        b.cpu.regs().s[DS] = kWindow >> 4; // [BX] in the device window
        b.ram[kWindow + 0x10] = 0x5A;
        // 0: SHL; 2: IN AL,DX; NOP; 4: SHL; 6: OUT DX,AL; NOP; 8: SHL; 10: MOV AL,[BX];
        // 12: SHL; 14: MOV [BX],AL; 16: SHL; NOP
        b.load(kFill + std::vector<std::uint8_t>{0xEC} + kNop + kFill + std::vector<std::uint8_t>{0xEE} + kNop +
               kFill + std::vector<std::uint8_t>{0x8A, 0x07} + kFill + std::vector<std::uint8_t>{0x88, 0x07} +
               kFill + kNop + kNop);
        std::vector<CycleRecord> trace;
        b.cpu.set_cycle_trace(&trace);
        for (int i = 0; i < 12; ++i) b.cpu.step();
        const std::vector<std::size_t> f = first_reads(trace);
        ASSERT_GE(f.size(), 12u);
        EXPECT_EQ(f[2] - f[1], 8 + w) << "IN AL,DX, " << w << " wait states";
        EXPECT_EQ(f[5] - f[4], 8 + w) << "OUT DX,AL, " << w << " wait states";
        EXPECT_EQ(f[8] - f[7], 13 + w) << "MOV AL,[BX], " << w << " wait states";
        EXPECT_EQ(f[10] - f[9], 14 + w) << "MOV [BX],AL, " << w << " wait states";
        EXPECT_EQ(check_cycles(trace, Bus::io_read, w), 1u);
        EXPECT_EQ(check_cycles(trace, Bus::io_write, w), 1u);
        EXPECT_EQ(check_cycles(trace, Bus::mem_read, w), 1u);
        EXPECT_EQ(check_cycles(trace, Bus::mem_write, w), 1u);
        for (const BusRecord& r : b.calls) EXPECT_EQ(r.wait_states, w) << to_string(r.kind);
        EXPECT_EQ(b.cpu.regs().r[AX] & 0xFF, 0x5A) << "MOV AL,[BX] read the window";
        EXPECT_EQ(b.calls.back().data & 0xFF, 0x5A) << "and MOV [BX],AL wrote it back";
    }
}

// A long run of NOPs from memory with w wait states: the EU needs 3 clocks per NOP (User's
// Manual); the BIU delivers a word (two NOPs) per prefetch of 4 + w clocks, back to back while
// the queue has room. In the steady state each NOP therefore takes max(3, (4 + w) / 2) clocks:
// 3 for w = 0..2 and 3.5 for w = 3, i.e. 300, 300, 300, 350 clocks per 100 NOPs.
TEST(Cpu8086KnownAnswer, CodeFetchesStretchByTheirWaitStates) {
    const unsigned expected[4] = {300, 300, 300, 350};
    for (unsigned w = 0; w <= 3; ++w) {
        Board b(w);
        b.load(std::vector<std::uint8_t>(300, 0x90));
        std::vector<CycleRecord> trace;
        b.cpu.set_cycle_trace(&trace);
        for (int i = 0; i < 250; ++i) b.cpu.step();
        const std::vector<std::size_t> f = first_reads(trace);
        ASSERT_GE(f.size(), 250u);
        EXPECT_EQ(f[200] - f[100], expected[w]) << w << " wait states";
        EXPECT_GT(check_cycles(trace, Bus::code_fetch, w), 100u);
        for (const BusRecord& r : b.cycles) EXPECT_EQ(r.wait_states, w);
    }
}

namespace {

// Runs STI; NOP; NOP with INTR raised after STI and returns the trace from the start. The
// interrupt is taken at the boundary after the NOP (STI delays recognition by one instruction).
struct IntrRun {
    std::vector<CycleRecord> trace;
    std::vector<BusRecord> cycles;
    std::vector<std::size_t> f;
};
IntrRun run_intr(unsigned inta_waits, Board& b) {
    IntrRun r;
    b.inta_waits = inta_waits;
    b.load({0xFB, 0x90, 0x90, 0x90});
    b.cpu.set_cycle_trace(&r.trace);
    b.cpu.step(); // STI
    b.cpu.set_intr(true);
    b.cpu.step(); // NOP (the STI delay)
    b.cpu.step(); // interrupt entry; ends with the handler's first byte read
    b.cpu.set_intr(false);
    b.cpu.step(); // INC BX in the handler
    r.cycles = b.cycles;
    r.f = first_reads(r.trace);
    return r;
}

} // namespace

// The interrupt sequence: INTA, INTA (the type on the second; the first floats 0xFF here), the
// vector read at 4 * type (IP, then CS), FLAGS pushed (with IF still set), CS pushed, the first
// code fetch at the handler (the FARCALL/NEARCALL tail flushes the queue before the IP push, as
// the INT n captures show), IP pushed; IF and TF clear in the handler.
TEST(Cpu8086KnownAnswer, HardwareInterruptEntrySequence) {
    Board b;
    const IntrRun r = run_intr(0, b);
    std::vector<BusRecord> seq;
    for (const BusRecord& c : r.cycles)
        if (c.kind != Bus::code_fetch || c.address == 0x500) seq.push_back(c);
    ASSERT_GE(seq.size(), 8u);
    EXPECT_EQ(seq[0].kind, Bus::int_ack);
    EXPECT_EQ(seq[1].kind, Bus::int_ack);
    EXPECT_EQ(seq[1].data & 0xFF, 0x20) << "the type is read in the second INTA";
    EXPECT_EQ(seq[2].kind, Bus::mem_read);
    EXPECT_EQ(seq[2].address, 0x20u * 4);
    EXPECT_EQ(seq[3].kind, Bus::mem_read);
    EXPECT_EQ(seq[3].address, 0x20u * 4 + 2);
    EXPECT_EQ(seq[4].kind, Bus::mem_write);
    EXPECT_EQ(seq[4].address, kStack + 0xFE);
    EXPECT_TRUE(seq[4].data & flag::IF) << "FLAGS pushed before IF is cleared";
    EXPECT_EQ(seq[5].kind, Bus::mem_write);
    EXPECT_EQ(seq[5].address, kStack + 0xFC);
    EXPECT_EQ(seq[5].data, 0x1000) << "CS";
    EXPECT_EQ(seq[6].kind, Bus::code_fetch);
    EXPECT_EQ(seq[6].address, 0x500u) << "first fetch at the vector";
    EXPECT_EQ(seq[7].kind, Bus::mem_write);
    EXPECT_EQ(seq[7].address, kStack + 0xFA);
    EXPECT_EQ(seq[7].data, 0x0002) << "IP of the instruction after the NOP";
    EXPECT_EQ(b.cpu.regs().r[BX], 1) << "the handler ran";
    EXPECT_FALSE(b.cpu.regs().flags & flag::IF);
    EXPECT_FALSE(b.cpu.regs().flags & flag::TF);
}

// LOCK from T2 of the first INTA to T2 of the second (data sheet), nowhere else.
TEST(Cpu8086KnownAnswer, LockSpansTheIntaPair) {
    Board b;
    const IntrRun r = run_intr(0, b);
    std::vector<std::size_t> inta;
    for (std::size_t k = 0; k < r.trace.size(); ++k)
        if (r.trace[k].ale && r.trace[k].status == Bus::int_ack) inta.push_back(k);
    ASSERT_EQ(inta.size(), 2u);
    for (std::size_t k = 0; k < r.trace.size(); ++k)
        EXPECT_EQ(r.trace[k].lock, k > inta[0] && k <= inta[1]) << "row " << k;
}

// INTA with w wait states: each INTA cycle is T1 T2 T3 Tw*w T4; the two are back to back, so
// the second T1 follows the first by 4 + w clocks. Both lie on the path to the vector read (the
// type is needed first, prefetching is suspended), so the whole entry - from the read of the
// opcode byte it replaces to the handler's first byte - grows by exactly 2w.
TEST(Cpu8086KnownAnswer, IntaCyclesStretchByTheirWaitStates) {
    Board b0;
    const IntrRun r0 = run_intr(0, b0);
    ASSERT_GE(r0.f.size(), 4u);
    const std::size_t entry0 = r0.f[3] - r0.f[2];
    for (unsigned w = 1; w <= 3; ++w) {
        Board b;
        const IntrRun r = run_intr(w, b);
        EXPECT_EQ(check_cycles(r.trace, Bus::int_ack, w), 2u);
        std::vector<cycles_t> starts;
        for (const BusRecord& c : r.cycles)
            if (c.kind == Bus::int_ack) starts.push_back(c.start);
        ASSERT_EQ(starts.size(), 2u);
        EXPECT_EQ(starts[1] - starts[0], 4 + w);
        ASSERT_GE(r.f.size(), 4u);
        EXPECT_EQ(r.f[3] - r.f[2], entry0 + 2 * w) << w << " wait states";
    }
}

// INTR is a level sampled at the instruction boundary: raised by the first of the two byte
// cycles of IN AX,DX at an odd port and dropped by the second, it is never seen; raised by the
// I/O write of OUT, the interrupt follows that instruction (the pushed IP is the next one).
TEST(Cpu8086KnownAnswer, IntrIsSampledAtTheInstructionBoundary) {
    {
        Board b;
        b.cpu.regs().flags |= flag::IF;
        b.cpu.regs().r[DX] = 0x41;
        b.load({0xED, 0x90, 0x90});
        b.on_access = [&](const BusRecord& r) { b.cpu.set_intr(r.address == 0x41); };
        b.cpu.step();
        b.cpu.step();
        unsigned intas = 0;
        for (const BusRecord& c : b.cycles) intas += c.kind == Bus::int_ack;
        EXPECT_EQ(intas, 0u) << "a pulse inside an instruction is not an interrupt";
        EXPECT_EQ(b.pc(), 0x10002u);
    }
    {
        Board b;
        b.cpu.regs().flags |= flag::IF;
        b.load({0xEE, 0x90, 0x90});
        b.on_access = [&](const BusRecord& r) {
            if (r.kind == Bus::io_write) b.cpu.set_intr(true);
            if (r.kind == Bus::int_ack) b.cpu.set_intr(false);
        };
        b.cpu.step(); // OUT DX,AL
        b.cpu.step(); // the boundary after it: interrupt entry
        EXPECT_EQ(b.cpu.regs().ip, 0x0500);
        EXPECT_EQ(b.word_at(kStack + 0xFA), 0x0001) << "the interrupt follows the OUT";
    }
}

// NMI: no INTA cycles, type 2, taken with IF clear. It enters the INTR microcode routine the
// way the single-step trap does (one line and a jump each: the INT1/INT2 entries of the
// microcode), so from the replaced opcode read to the handler's first byte both take the same
// clocks (50 here, with a prefetch ending at the boundary in both programs).
TEST(Cpu8086KnownAnswer, NmiAndTrapEntriesTakeTheSameClocks) {
    auto entry = [](bool nmi) {
        Board b;
        // PUSHF; POP AX; OR AH,1; PUSH AX; POPF (TF on); NOP; NOP
        if (nmi) b.load({0x90, 0x90, 0x90});
        else b.load({0x9C, 0x58, 0x80, 0xCC, 0x01, 0x50, 0x9D, 0x90, 0x90});
        std::vector<CycleRecord> trace;
        b.cpu.set_cycle_trace(&trace);
        const int before = nmi ? 1 : 6; // instructions before the entry
        for (int i = 0; i < before; ++i) b.cpu.step();
        if (nmi) b.cpu.set_nmi(true);
        b.cpu.step(); // the entry
        b.cpu.step(); // INC BX in the handler
        EXPECT_EQ(b.cpu.regs().r[BX], 1);
        EXPECT_EQ(b.cpu.regs().ip, nmi ? 0x0601 : 0x0701);
        for (const BusRecord& c : b.cycles) EXPECT_NE(c.kind, Bus::int_ack);
        const std::vector<std::size_t> f = first_reads(trace);
        return f[std::size_t(before) + 1] - f[std::size_t(before)];
    };
    const std::size_t nmi = entry(true), trap = entry(false);
    EXPECT_EQ(nmi, trap);
    Board b;
    const IntrRun r = run_intr(0, b);
    // INTR: the same routine entered after the two INTA bus cycles (2 x 4 clocks) and at least
    // one IRQ line of the microcode after them, in place of NMI's entry line and jump.
    ASSERT_GE(r.f.size(), 4u);
    EXPECT_GE(r.f[3] - r.f[2], nmi + 2 * 4 + 1);
}

// TF: after an instruction that began with TF set, type 1 is taken; the handler runs with TF
// clear and its IRET restores TF, so exactly one instruction runs between traps, and each trap
// pushes the address of the instruction after the one that ran.
TEST(Cpu8086KnownAnswer, TrapAfterEveryInstruction) {
    Board b;
    // PUSHF; POP AX; OR AH,1; PUSH AX; POPF; then INC CX three times, NOP.
    b.load({0x9C, 0x58, 0x80, 0xCC, 0x01, 0x50, 0x9D, 0x41, 0x41, 0x41, 0x90});
    for (int i = 0; i < 5; ++i) b.cpu.step();
    std::vector<std::uint16_t> pushed;
    for (int k = 0; k < 3; ++k) {
        b.cpu.step(); // one INC CX (POPF's own boundary is not trapped: TF was clear when it began)
        EXPECT_EQ(b.cpu.regs().r[CX], k + 1);
        b.cpu.step(); // the trap entry
        EXPECT_EQ(b.cpu.regs().ip, 0x0700);
        EXPECT_FALSE(b.cpu.regs().flags & flag::TF);
        pushed.push_back(b.word_at(kStack + 0xFA));
        b.cpu.step(); // INC BX
        b.cpu.step(); // IRET: TF back on
        EXPECT_TRUE(b.cpu.regs().flags & flag::TF);
    }
    EXPECT_EQ(pushed, (std::vector<std::uint16_t>{0x0008, 0x0009, 0x000A}));
    EXPECT_EQ(b.cpu.regs().r[BX], 3);
}

// INTR raised during the third element's write of REP MOVSB: the element completes, the
// interrupt is taken before the fourth (the "end of a whole move" sampling point of the data
// sheet), with IP at the REP prefix and CX/SI/DI counting three elements; IRET resumes the run
// and all 10 bytes arrive.
TEST(Cpu8086KnownAnswer, InterruptDuringRepResumesTheStringOp) {
    Board b(0, true);
    b.cpu.regs().flags |= flag::IF;
    b.cpu.regs().r[CX] = 10;
    b.cpu.regs().s[ES] = kWindow >> 4; // the destination in the device window
    for (int i = 0; i < 10; ++i) b.ram[0x30000 + i] = std::uint8_t(0xA0 + i);
    b.load({0x90, 0xF3, 0xA4, 0x90, 0x90});
    unsigned writes = 0;
    b.on_access = [&](const BusRecord& r) {
        if (r.kind == Bus::mem_write && r.address >= kWindow && ++writes == 3) b.cpu.set_intr(true);
        if (r.kind == Bus::int_ack) b.cpu.set_intr(false);
    };
    b.cpu.step(); // NOP
    b.cpu.step(); // REP MOVSB, cut short after the element in progress
    EXPECT_EQ(b.cpu.regs().r[CX], 7);
    EXPECT_EQ(b.cpu.regs().r[SI], 3);
    EXPECT_EQ(b.cpu.regs().r[DI], 3);
    b.cpu.step(); // interrupt entry
    EXPECT_EQ(b.cpu.regs().ip, 0x0500);
    EXPECT_EQ(b.word_at(kStack + 0xFA), 0x0001) << "return to the REP prefix";
    b.cpu.step(); // INC BX
    b.cpu.step(); // IRET
    b.cpu.step(); // the rest of the run
    EXPECT_EQ(b.cpu.regs().r[CX], 0);
    EXPECT_EQ(b.pc(), 0x10003u);
    for (int i = 0; i < 10; ++i) EXPECT_EQ(b.ram[kWindow + i], 0xA0 + i) << i;
    EXPECT_EQ(writes, 10u) << "no element written twice";
}

// HLT: no bus cycles while halted; every clock is a boundary where INTR is sampled, so the
// first INTA starts the same number of clocks after INTR rises wherever it rises; the pushed IP
// is the instruction after HLT.
TEST(Cpu8086KnownAnswer, HltWakesOnIntrAtAFixedLatency) {
    auto latency = [](unsigned idle) {
        Board b;
        b.load({0xFB, 0xF4, 0x90});
        b.cpu.step(); // STI
        b.cpu.step(); // HLT
        EXPECT_TRUE(b.cpu.halted());
        const std::size_t bus_before = b.cycles.size();
        const cycles_t halted_at = b.cpu.cycles();
        while (b.cpu.cycles() < halted_at + idle) b.cpu.step();
        EXPECT_EQ(b.cycles.size(), bus_before) << "no bus cycles while halted (prefetch stopped)";
        const cycles_t raised = b.cpu.cycles();
        b.cpu.set_intr(true);
        b.cpu.step();
        EXPECT_FALSE(b.cpu.halted());
        EXPECT_EQ(b.word_at(kStack + 0xFA), 0x0002) << "returns after the HLT";
        for (const BusRecord& c : b.cycles)
            if (c.kind == Bus::int_ack) return c.start - raised;
        ADD_FAILURE() << "no INTA";
        return cycles_t(0);
    };
    const cycles_t l10 = latency(10), l17 = latency(17);
    EXPECT_EQ(l10, l17);
    EXPECT_GT(l10, 0u);
}

// A LOCK prefix drives LOCK# for the instruction it prefixes and for nothing else.
TEST(Cpu8086KnownAnswer, LockPrefixDrivesLockForItsInstruction) {
    Board b;
    b.load({0x90, 0xF0, 0x86, 0x07, 0x90, 0x90}); // NOP; LOCK XCHG [BX],AL; NOP
    std::vector<CycleRecord> trace;
    b.cpu.set_cycle_trace(&trace);
    for (int i = 0; i < 3; ++i) b.cpu.step();
    unsigned locked_mem = 0, unlocked_mem = 0;
    bool locked_fetch_after = false;
    const std::vector<std::size_t> f = first_reads(trace);
    ASSERT_GE(f.size(), 4u);
    for (std::size_t k = 0; k < trace.size(); ++k) {
        const bool mem = trace[k].ale && (trace[k].status == Bus::mem_read || trace[k].status == Bus::mem_write);
        if (mem) (trace[k].lock ? locked_mem : unlocked_mem)++;
        if (k > f[3] && trace[k].lock) locked_fetch_after = true;
        if (k < f[1]) {
            EXPECT_FALSE(trace[k].lock) << "row " << k;
        }
    }
    EXPECT_EQ(locked_mem, 2u) << "the read and the write of XCHG";
    EXPECT_EQ(unlocked_mem, 0u);
    EXPECT_FALSE(locked_fetch_after);
}
