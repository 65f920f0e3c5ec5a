// The core's exact idle fast-forward (Cpu::set_fast_forward, docs/cpu8086.md "Idle
// fast-forward") on polling loops of the bare core: with it on, every handler call (kind,
// address, data, start cycle), every bus cycle the hook sees, the registers, the cycle and
// instruction counts are those of the same run with it off, while most of the clocks were
// forwarded. The loops end on a change the fast path must catch: a port answer that changes
// (the replay diverges and the period is executed again), an interrupt at the run's horizon
// (an ISR that writes the RAM flag the loop polls). A horizon set past the interrupt shows the
// comparison sees a skip that crosses an event.
#include "comm_cpu/i8086/cpu.h"
#include "tests/comm_cpu/i8086/cpu_board.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <tuple>
#include <vector>

using namespace rcsim::i8086;
using rcsim::i8086::test::Board;
using rcsim::i8086::test::kStack;

namespace {

bool same(const BusRecord& a, const BusRecord& b) {
    return a.kind == b.kind && a.address == b.address && a.data == b.data && a.width == b.width &&
           a.wait_states == b.wait_states && a.start == b.start;
}

void expect_same_run(const Board& on, const Board& off) {
    EXPECT_EQ(on.cpu.cycles(), off.cpu.cycles());
    EXPECT_EQ(on.cpu.instructions(), off.cpu.instructions());
    const Registers& a = on.cpu.regs();
    const Registers& b = off.cpu.regs();
    for (int i = 0; i < 8; ++i) EXPECT_EQ(a.r[i], b.r[i]) << "register " << i;
    for (int i = 0; i < 4; ++i) EXPECT_EQ(a.s[i], b.s[i]) << "segment " << i;
    EXPECT_EQ(a.ip, b.ip);
    EXPECT_EQ(a.flags, b.flags);
    ASSERT_EQ(on.calls.size(), off.calls.size());
    for (std::size_t i = 0; i < on.calls.size(); ++i) ASSERT_TRUE(same(on.calls[i], off.calls[i])) << "handler call " << i;
    ASSERT_EQ(on.cycles.size(), off.cycles.size());
    for (std::size_t i = 0; i < on.cycles.size(); ++i) ASSERT_TRUE(same(on.cycles[i], off.cycles[i])) << "bus cycle " << i;
}

// IN AL,40h / TEST AL,1 / JZ back / HLT: the status port reads 0 until the first read whose
// T1 is at or after `ready`, then 1. Run in slices of `slice` clocks (run_until limits, as the
// SystemC module does): forwarding then also ends at slice limits.
void poll_port(Board& b, bool forward, cycles_t ready, cycles_t slice = 1'000'000) {
    b.load({0xE4, 0x40, 0xA8, 0x01, 0x74, 0xFA, 0xF4});
    b.io_value = 0;
    b.on_access = [&b, ready](const BusRecord& r) {
        if (r.kind == Bus::io_read && r.start >= ready) b.io_value = 1;
    };
    b.cpu.set_fast_forward(forward);
    while (!b.cpu.halted() && b.cpu.cycles() < 1'000'000) b.cpu.run_until(b.cpu.cycles() + slice, false);
}

TEST(CpuFastForward, PortPollingLoopIsExactAndForwarded) {
    constexpr cycles_t ready = 200'003; // not a multiple of the loop's period
    Board on, off;
    poll_port(on, true, ready);
    poll_port(off, false, ready);
    ASSERT_TRUE(off.cpu.halted());
    EXPECT_EQ(off.cpu.forwarded_cycles(), 0u);
    // The loop ran to the answer's change: most of it was forwarded, the rest executed.
    EXPECT_GT(on.cpu.forwarded_cycles(), ready / 2);
    EXPECT_LT(on.cpu.forwarded_cycles(), on.cpu.cycles());
    // The forwarded instructions are counted apart, at the loop's rate: as many clocks per
    // instruction as the run without forwarding (nearly all of it that loop), and at least
    // the data sheet's 30 clocks per three instructions (IN AL,imm8 10, TEST AL,imm8 4, JZ
    // taken 16; the table assumes a full queue, which the jump empties).
    EXPECT_EQ(off.cpu.forwarded_instructions(), 0u);
    ASSERT_GT(on.cpu.forwarded_instructions(), 0u);
    ASSERT_LT(on.cpu.forwarded_instructions(), on.cpu.instructions());
    const double forwarded = double(on.cpu.forwarded_cycles()) / double(on.cpu.forwarded_instructions());
    EXPECT_NEAR(forwarded, double(off.cpu.cycles()) / double(off.cpu.instructions()), 0.05);
    EXPECT_GE(forwarded, 10.0);
    expect_same_run(on, off);
}

// STI / CMP byte [0100h],0 / JE back / HLT, and an ISR at 0500h: MOV byte [0100h],1 / IRET.
// INTR rises at cycle `irq` (the run's limit and horizon: the event the fast path must not
// cross, unless `horizon` says otherwise) and falls with the second INTA.
void poll_ram(Board& b, bool forward, cycles_t irq, cycles_t horizon) {
    b.load({0xFB, 0x80, 0x3E, 0x00, 0x01, 0x00, 0x74, 0xF9, 0xF4});
    b.load({0xC6, 0x06, 0x00, 0x01, 0x01, 0xCF}, 0x500);
    b.ram[0x30100] = 0; // the flag (DS = 3000h); the board's RAM is HLT bytes elsewhere
    b.on_access = [&b](const BusRecord& r) {
        if (r.kind == Bus::int_ack && b.intas % 2 == 0) b.cpu.set_intr(false);
    };
    b.cpu.set_fast_forward(forward);
    b.cpu.run_until(horizon, false, horizon); // the forwarding never passes the limit either
    b.cpu.set_intr(true);
    b.cpu.run_until(irq + 100'000, false);
}

TEST(CpuFastForward, PortPollingInSlicesIsExact) {
    // Slices of a prime number of clocks: periods end short of each limit, the next slice's
    // first accesses are real ones again.
    constexpr cycles_t ready = 200'003;
    Board on, off;
    poll_port(on, true, ready, 7919);
    poll_port(off, false, ready, 7919);
    ASSERT_TRUE(off.cpu.halted());
    EXPECT_GT(on.cpu.forwarded_cycles(), ready / 2);
    expect_same_run(on, off);
}

TEST(CpuFastForward, RamFlagLoopStopsAtTheHorizonAndSeesTheInterrupt) {
    constexpr cycles_t irq = 150'001;
    Board on, off;
    poll_ram(on, true, irq, irq);
    poll_ram(off, false, irq, irq);
    ASSERT_TRUE(off.cpu.halted());
    ASSERT_EQ(off.intas, 2u);
    EXPECT_EQ(on.ram[0x30100], 1); // DS = 3000h: the ISR's write ended the loop
    EXPECT_GT(on.cpu.forwarded_cycles(), irq / 2);
    expect_same_run(on, off);
}

TEST(CpuFastForward, SkippingPastAnEventIsSeen) {
    // The same run with the limit and horizon told to lie 20 000 clocks beyond the interrupt: the
    // loop is forwarded past the INTR rise, so the interrupt is taken late and the comparison differs.
    constexpr cycles_t irq = 150'001;
    Board wrong, off;
    poll_ram(wrong, true, irq, irq + 20'000);
    poll_ram(off, false, irq, irq);
    ASSERT_EQ(wrong.intas, 2u);
    ASSERT_EQ(off.intas, 2u);
    const auto first_inta = [](const Board& b) {
        for (const BusRecord& r : b.calls)
            if (r.kind == Bus::int_ack) return r.start;
        return cycles_t(0);
    };
    EXPECT_GT(first_inta(wrong), first_inta(off) + 10'000);
}

// A loop whose period writes RAM in the middle and puts it back before its end: STI, then
//   loop: CALL sub / MOV [0104h],AL / INC byte [0106h] / DEC byte [0106h] / CMP byte [0100h],0 /
//         JE loop / HLT        sub: IN AL,40h / PUSH AX / POP BX / RET
// (the CALL and the PUSH write the stack, [0106h] is 1 between INC and DEC). The ISR at 0500h
// sets [0100h]. INTR rises at `irq`; before it the run goes in slices of `slice` clocks, each
// limit also its horizon, so the forwarding stops inside a period at every slice end. Returns
// the clocks executed one by one (not forwarded) up to the INTR rise.
cycles_t call_loop(Board& b, bool forward, cycles_t irq, cycles_t slice) {
    b.load({0xFB, 0xE8, 0x13, 0x00, 0xA2, 0x04, 0x01, 0xFE, 0x06, 0x06, 0x01, 0xFE, 0x0E, 0x06, 0x01,
            0x80, 0x3E, 0x00, 0x01, 0x00, 0x74, 0xEB, 0xF4, 0xE4, 0x40, 0x50, 0x5B, 0xC3});
    b.load({0xC6, 0x06, 0x00, 0x01, 0x01, 0xCF}, 0x500);
    for (std::uint32_t a = 0x30100; a < 0x30108; ++a) b.ram[a] = 0;
    b.on_access = [&b](const BusRecord& r) {
        if (r.kind == Bus::int_ack && b.intas % 2 == 0) b.cpu.set_intr(false);
    };
    b.cpu.set_fast_forward(forward);
    while (b.cpu.cycles() < irq) {
        const cycles_t limit = std::min(irq, b.cpu.cycles() + slice);
        b.cpu.run_until(limit, false, limit);
    }
    const cycles_t executed = b.cpu.cycles() - b.cpu.forwarded_cycles();
    b.cpu.set_intr(true);
    b.cpu.run_until(irq + 100'000, false);
    return executed;
}

void expect_same_ram(const Board& on, const Board& off) {
    for (std::uint32_t a = kStack; a < kStack + 0x100; ++a) ASSERT_EQ(on.ram[a], off.ram[a]) << "stack byte " << a;
    for (std::uint32_t a = 0x30100; a < 0x30108; ++a) ASSERT_EQ(on.ram[a], off.ram[a]) << "data byte " << a;
}

TEST(CpuFastForward, StopsInsideAPeriodAtEachSliceEnd) {
    // 100 slices of a prime number of clocks, each ending somewhere inside the loop's period.
    constexpr cycles_t slice = 1009, irq = 100 * slice + 17;
    Board on, off;
    const cycles_t executed = call_loop(on, true, irq, slice);
    call_loop(off, false, irq, slice);
    ASSERT_TRUE(off.cpu.halted());
    ASSERT_EQ(off.intas, 2u);
    EXPECT_EQ(on.ram[0x30106], 0);
    expect_same_run(on, off);
    expect_same_ram(on, off);
    // The period, from the clock-by-clock run: the distance between two IN cycles.
    cycles_t period = 0;
    for (std::size_t i = 1; i < off.calls.size() && !period; ++i)
        if (off.calls[i].kind == Bus::io_read) period = off.calls[i].start - off.calls[i - 1].start;
    ASSERT_GT(period, 100u); // 10 instructions, CALL/RET and a taken JE among them
    // Clocks executed one by one: the recording (a few periods), then in each slice only the
    // instruction that crosses its end, never longer than the CALL or the taken JE with their
    // fetches (under 40 clocks, well below half a period). A forwarding that stops only at whole
    // periods would execute half a period per slice on average (50 slices' worth of periods).
    // (10 periods allowed for the recording: it needs two visits with the same state.)
    EXPECT_LT(executed, 10 * period + 100 * 40) << "period " << period;
}

TEST(CpuFastForward, StopsInsideAPeriodAtTheInterrupt) {
    // One run up to an INTR rise that falls between two boundaries of the loop: the forwarding
    // gets to the last boundary before it, the rest is executed; the interrupt is taken at the
    // same boundary as clock by clock, with the RAM of that point of the period.
    for (cycles_t irq : {cycles_t(150'001), cycles_t(150'037), cycles_t(150'121)}) {
        Board on, off;
        call_loop(on, true, irq, irq);
        call_loop(off, false, irq, irq);
        ASSERT_TRUE(off.cpu.halted());
        ASSERT_EQ(off.intas, 2u);
        expect_same_run(on, off);
        expect_same_ram(on, off);
        EXPECT_GT(on.cpu.forwarded_cycles(), irq - 10'000) << "irq " << irq;
        // The case is the one named: the last boundary before the rise is not the loop head
        // (CALL at 1000:0001) and the rise is not at a boundary.
        struct Seen {
            cycles_t irq, last = 0;
            std::uint32_t pc = 0;
            bool at_boundary = false;
        } seen{irq};
        Board hooked;
        hooked.cpu.set_step_hook(
            [](void* c, const Cpu& cpu) {
                auto* s = static_cast<Seen*>(c);
                if (cpu.cycles() == s->irq) s->at_boundary = true;
                if (cpu.cycles() < s->irq) {
                    s->last = cpu.cycles();
                    s->pc = cpu.pc();
                }
                return false;
            },
            &seen);
        call_loop(hooked, false, irq, irq);
        EXPECT_FALSE(seen.at_boundary) << "irq " << irq;
        EXPECT_NE(seen.pc, 0x10001u) << "irq " << irq;
    }
}

TEST(CpuFastForward, NotWhileAStepHookIsSet) {
    // A debugger's step hook sees every instruction: nothing is forwarded.
    Board b;
    std::uint64_t steps = 0;
    b.cpu.set_step_hook([](void* c, const Cpu&) { ++*static_cast<std::uint64_t*>(c); return false; }, &steps);
    poll_port(b, true, 50'000);
    ASSERT_TRUE(b.cpu.halted());
    EXPECT_EQ(b.cpu.forwarded_cycles(), 0u);
    EXPECT_EQ(steps, b.cpu.instructions()); // once before every instruction (HLT included)
}

// A counter on the step hook with a SkipHook (coverage): the fast-forward stays on and tells it
// the boundaries it went past, so the counts per boundary (address, and the registers a branch
// counter decides from) are those of every boundary executed with the fast-forward off.
struct BoundaryCounts {
    std::map<std::tuple<std::uint32_t, std::uint16_t, std::uint16_t>, std::uint64_t> seen; // (pc, flags, CX)
    void add(std::uint32_t pc, const Registers& r, std::uint64_t n) { seen[{pc, r.flags, r.r[CX]}] += n; }
    std::uint64_t total() const {
        std::uint64_t t = 0;
        for (const auto& e : seen) t += e.second;
        return t;
    }
    static bool step(void* c, const Cpu& cpu) {
        static_cast<BoundaryCounts*>(c)->add(cpu.pc(), cpu.regs(), 1);
        return false;
    }
    static void skipped(void* c, const Boundary* b, std::size_t n, std::uint64_t times) {
        for (std::size_t i = 0; i < n; ++i) static_cast<BoundaryCounts*>(c)->add(b[i].pc, b[i].regs, times);
    }
};

TEST(CpuFastForward, ACountingStepHookIsToldTheSkippedBoundaries) {
    // The CALL loop in slices that end inside its period (partial segments), up to an INTR whose
    // ISR ends the loop (an interrupt entry, which the hook does not see, in the run), and the
    // port polling loop (whole periods) whose answer changes mid-period (a re-execution).
    constexpr cycles_t slice = 1009, irq = 100 * slice + 17;
    BoundaryCounts on, off;
    Board a, b;
    a.cpu.set_step_hook(&BoundaryCounts::step, &on, &BoundaryCounts::skipped);
    b.cpu.set_step_hook(&BoundaryCounts::step, &off);
    call_loop(a, true, irq, slice);
    call_loop(b, false, irq, slice);
    expect_same_run(a, b);
    EXPECT_GT(a.cpu.forwarded_instructions(), a.cpu.instructions() / 2) << "the fast-forward stayed on";
    EXPECT_EQ(b.cpu.forwarded_instructions(), 0u);
    EXPECT_EQ(off.total(), b.cpu.instructions()); // once before every instruction (HLT included)
    EXPECT_EQ(on.seen, off.seen);

    BoundaryCounts on2, off2;
    Board c, d;
    c.cpu.set_step_hook(&BoundaryCounts::step, &on2, &BoundaryCounts::skipped);
    d.cpu.set_step_hook(&BoundaryCounts::step, &off2);
    poll_port(c, true, 200'003);
    poll_port(d, false, 200'003);
    expect_same_run(c, d);
    EXPECT_GT(c.cpu.forwarded_instructions(), c.cpu.instructions() / 2);
    EXPECT_EQ(on2.seen, off2.seen);
    EXPECT_EQ(on2.total(), d.cpu.instructions());
}

// ---------------------------------------------------------------------------------------------
// Bus hook kinds (Cpu::set_bus_hook_kinds): a hook told to watch some kinds of cycle is called
// for exactly those cycles of the full list, in order, with the fast-forward off and on (the
// replay hands it only those too).

std::vector<BusRecord> of_kinds(const std::vector<BusRecord>& all, BusKinds kinds) {
    std::vector<BusRecord> out;
    for (const BusRecord& r : all)
        if (kinds & bus_kind_bit(r.kind)) out.push_back(r);
    return out;
}

void expect_same_cycles(const std::vector<BusRecord>& a, const std::vector<BusRecord>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) ASSERT_TRUE(same(a[i], b[i])) << "bus cycle " << i;
}

TEST(CpuBusHookKinds, TheHookSeesOnlyItsKindsWithAndWithoutForwarding) {
    constexpr cycles_t slice = 1009, irq = 100 * slice + 17;
    constexpr BusKinds kinds = bus_kind_bit(Bus::int_ack) | bus_kind_bit(Bus::mem_write);
    Board all, off, on;
    call_loop(all, false, irq, slice);
    off.cpu.set_bus_hook_kinds(kinds);
    on.cpu.set_bus_hook_kinds(kinds);
    call_loop(off, false, irq, slice);
    call_loop(on, true, irq, slice);
    const std::vector<BusRecord> want = of_kinds(all.cycles, kinds);
    // The case is the one named: both kinds occur, and most cycles are of other kinds.
    ASSERT_EQ(of_kinds(want, bus_kind_bit(Bus::int_ack)).size(), 2u);
    ASSERT_GT(of_kinds(want, bus_kind_bit(Bus::mem_write)).size(), 100u);
    ASSERT_LT(2 * want.size(), all.cycles.size());
    EXPECT_GT(on.cpu.forwarded_cycles(), irq / 2);
    expect_same_cycles(off.cycles, want);
    expect_same_cycles(on.cycles, want);
}

// The hook changes its kinds as it goes (the interrupt probe widens them at an INTA): here it
// watches I/O reads only until it sees the port answer 1, then every cycle. In the forwarded run
// the answer's change makes a replayed segment diverge and run again: the cycles already handed
// over in it are not handed over twice, whatever their kind, and none is lost.
struct Widening {
    Board* board;
    std::vector<BusRecord> seen;
    static void hook(void* c, const BusRecord& r) {
        auto* w = static_cast<Widening*>(c);
        w->seen.push_back(r);
        if (r.kind == Bus::io_read && r.data == 1) w->board->cpu.set_bus_hook_kinds(kAllBusKinds);
    }
};

TEST(CpuBusHookKinds, KindsChangedByTheHookSurviveAReplayThatDiverges) {
    constexpr cycles_t ready = 200'003;
    Board all, off, on;
    poll_port(all, false, ready);
    Widening woff{&off, {}}, won{&on, {}};
    off.cpu.set_bus_hook(&Widening::hook, &woff, bus_kind_bit(Bus::io_read));
    on.cpu.set_bus_hook(&Widening::hook, &won, bus_kind_bit(Bus::io_read));
    poll_port(off, false, ready);
    poll_port(on, true, ready);
    ASSERT_TRUE(on.cpu.halted());
    EXPECT_GT(on.cpu.forwarded_cycles(), ready / 2);
    // Clock by clock: the I/O reads up to the one that answered 1, then every cycle after it.
    std::size_t first_one = 0;
    while (first_one < all.cycles.size() &&
           !(all.cycles[first_one].kind == Bus::io_read && all.cycles[first_one].data == 1))
        ++first_one;
    ASSERT_LT(first_one + 3, all.cycles.size()); // the fetches and the HLT after it
    std::vector<BusRecord> want =
        of_kinds({all.cycles.begin(), all.cycles.begin() + std::ptrdiff_t(first_one)}, bus_kind_bit(Bus::io_read));
    want.insert(want.end(), all.cycles.begin() + std::ptrdiff_t(first_one), all.cycles.end());
    expect_same_cycles(woff.seen, want);
    expect_same_cycles(won.seen, want);
}

} // namespace
