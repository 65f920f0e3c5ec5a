// The core's interrupt history (Cpu::if_change, held_cycle, instruction_start, interrupt_boundary;
// docs/cpu8086.md "Interrupt history"): what the interrupt probe reads to say why an interrupt
// waited. Each change of IF is recorded with the boundary its instruction began at (found here
// with a step hook, which sees every boundary), its CS:IP and opcode; an interrupt taken at a
// boundary with that boundary and the CS:IP it interrupted. The fast-forward keeps the history
// as the clock-by-clock run does: a loop that clears and sets IF in every period, forwarded,
// leaves the same history at the interrupt as the same run executed.
#include "comm_cpu/i8086/cpu.h"
#include "tests/comm_cpu/i8086/cpu_board.h"

#include <gtest/gtest.h>

#include <map>
#include <vector>

using namespace rcsim::i8086;
using rcsim::i8086::test::Board;
using rcsim::i8086::test::kWindow;

namespace {

// The boundary (cycles() before the instruction) of every instruction, by its linear address;
// the last visit wins.
struct Boundaries {
    std::map<std::uint32_t, cycles_t> at;
    static bool hook(void* c, const Cpu& cpu) {
        static_cast<Boundaries*>(c)->at[cpu.pc()] = cpu.cycles();
        return false;
    }
};

bool same(const IfChange& a, const IfChange& b) {
    return a.cycle == b.cycle && a.instructions == b.instructions && a.cs == b.cs && a.ip == b.ip &&
           a.opcode == b.opcode && a.vector == b.vector && a.enabled == b.enabled && a.how == b.how;
}

} // namespace

TEST(CpuInterruptHistory, ResetStartsTheHistoryWithInterruptsOff) {
    Cpu cpu;
    ASSERT_EQ(cpu.if_changes(), 1u);
    const IfChange& c = cpu.if_change(0);
    EXPECT_EQ(c.how, IfChange::How::reset);
    EXPECT_FALSE(c.enabled);
    EXPECT_EQ(c.cycle, 0u);
    EXPECT_EQ(c.cs, 0xFFFF);
    EXPECT_EQ(c.ip, 0x0000);
}

// STI / NOP / CLI / PUSHF / STI / POPF / STI / INT 21h (handler: IRET) / HLT at 1000:0000.
// Changes: STI sets, CLI clears, STI sets, POPF clears (the flags PUSHF saved with IF = 0), STI
// sets, INT clears and its IRET sets again. NOP and PUSHF change nothing.
TEST(CpuInterruptHistory, EveryChangeOfIfWithItsInstruction) {
    Board b;
    b.load({0xFB, 0x90, 0xFA, 0x9C, 0xFB, 0x9D, 0xFB, 0xCD, 0x21, 0xF4});
    b.set_vector(0x21, 0x0900, 0);
    b.ram[0x900] = 0xCF; // IRET
    Boundaries seen;
    b.cpu.set_step_hook(&Boundaries::hook, &seen);
    b.cpu.run_until(2000, false);
    ASSERT_TRUE(b.cpu.halted());
    ASSERT_EQ(b.cpu.if_changes(), 7u); // load_state cleared the history: these seven only
    struct Want {
        std::uint16_t ip;
        std::uint8_t opcode;
        bool enabled;
        std::uint16_t cs;
    };
    const Want want[] = {{0x0000, 0xFB, true, 0x1000},  {0x0002, 0xFA, false, 0x1000}, {0x0004, 0xFB, true, 0x1000},
                         {0x0005, 0x9D, false, 0x1000}, {0x0006, 0xFB, true, 0x1000},  {0x0007, 0xCD, false, 0x1000},
                         {0x0900, 0xCF, true, 0x0000}};
    for (unsigned i = 0; i < 7; ++i) {
        const IfChange& c = b.cpu.if_change(6 - i);
        SCOPED_TRACE(i);
        EXPECT_EQ(c.how, IfChange::How::instruction);
        EXPECT_EQ(c.ip, want[i].ip);
        EXPECT_EQ(c.cs, want[i].cs);
        EXPECT_EQ(c.opcode, want[i].opcode);
        EXPECT_EQ(c.enabled, want[i].enabled);
        EXPECT_EQ(c.cycle, seen.at.at(Cpu::linear(want[i].cs, want[i].ip)));
    }
    EXPECT_EQ(b.cpu.if_change(1).vector, 0x21); // INT 21h
    // HLT is the last instruction; it began at its boundary.
    EXPECT_EQ(b.cpu.instruction_ip(), 0x0009);
    EXPECT_EQ(b.cpu.instruction_cs(), 0x1000);
    EXPECT_EQ(b.cpu.instruction_start(), seen.at.at(0x10009));
}

// STI, then NOPs: INTR rises while the NOPs run. The interrupt is taken at the boundary after the
// instruction in progress; the entry clears IF with that boundary and the CS:IP it interrupted.
TEST(CpuInterruptHistory, AnInterruptTakenAtABoundary) {
    Board b;
    std::vector<std::uint8_t> code{0xFB};
    code.insert(code.end(), 40, 0x90);
    code.push_back(0xF4);
    b.load(code);
    Boundaries seen;
    b.cpu.set_step_hook(&Boundaries::hook, &seen);
    cycles_t boundary = 0, instr_start = 0;
    std::uint16_t instr_ip = 0;
    b.on_access = [&](const BusRecord& r) {
        if (r.kind != Bus::int_ack || b.intas != 1) return;
        boundary = b.cpu.interrupt_boundary();
        instr_start = b.cpu.instruction_start();
        instr_ip = b.cpu.instruction_ip();
        b.cpu.set_intr(false);
    };
    b.cpu.run_until(50, false);
    b.cpu.set_intr(true);
    b.cpu.run_until(2000, false);
    ASSERT_EQ(b.intas, 2u);
    // The last change is the entry's (the handler's IRET sets IF again after it).
    ASSERT_GE(b.cpu.if_changes(), 3u);
    const IfChange& entry = b.cpu.if_change(1);
    EXPECT_EQ(entry.how, IfChange::How::entry);
    EXPECT_FALSE(entry.enabled);
    EXPECT_EQ(entry.cycle, boundary);
    EXPECT_EQ(entry.vector, 0x20);
    EXPECT_EQ(entry.cs, 0x1000);
    // The instruction in progress began at a boundary the step hook saw, at its address; the
    // entry interrupted the NOP after it (the hook is not called where an interrupt is taken).
    std::uint32_t previous = 0;
    for (const auto& [pc, c] : seen.at)
        if (c == instr_start) previous = pc;
    ASSERT_NE(previous, 0u);
    EXPECT_EQ(Cpu::linear(0x1000, instr_ip), previous);
    EXPECT_EQ(Cpu::linear(entry.cs, entry.ip), previous + 1); // one NOP on
    EXPECT_LT(instr_start, boundary);
    EXPECT_FALSE(b.cpu.interrupt_from_halt());
}

// A memory cycle the handler answers with wait states (the device window) is kept with its
// start and wait states; one without is not.
TEST(CpuInterruptHistory, HeldCyclesOfTheHandler) {
    Board b(0, true);
    b.window_waits = 7;
    // MOV AX,8000h / MOV DS,AX / MOV AL,[0010h] / HLT
    b.load({0xB8, 0x00, 0x80, 0x8E, 0xD8, 0xA0, 0x10, 0x00, 0xF4});
    b.cpu.run_until(500, false);
    ASSERT_TRUE(b.cpu.halted());
    ASSERT_EQ(b.cpu.held_cycles(), 1u);
    const HeldCycle& h = b.cpu.held_cycle(0);
    EXPECT_EQ(h.address, kWindow + 0x10);
    EXPECT_EQ(h.waits, 7u);
    EXPECT_EQ(h.kind, Bus::mem_read);
    std::vector<BusRecord> reads;
    for (const BusRecord& r : b.calls)
        if (r.kind == Bus::mem_read) reads.push_back(r);
    ASSERT_EQ(reads.size(), 1u);
    EXPECT_EQ(h.start, reads[0].start);
}

namespace {

// loop: CLI / IN AL,40h / STI / NOP / JMP loop, at 1000:0000; the ISR (0:0500) INC BX / IRET.
// INTR rises at `irq` (the run's limit and horizon before it) and falls at the first INTA. At the
// second INTA the history is copied: every change of IF, the instruction in progress, the boundary.
struct AtInta {
    std::vector<IfChange> changes;
    cycles_t boundary = 0, instr_start = 0;
    std::uint16_t instr_cs = 0, instr_ip = 0;
};

AtInta cli_sti_loop(Board& b, bool forward, cycles_t irq, cycles_t slice) {
    b.load({0xFA, 0xE4, 0x40, 0xFB, 0x90, 0xEB, 0xF9});
    AtInta seen;
    b.on_access = [&b, &seen](const BusRecord& r) {
        if (r.kind != Bus::int_ack) return;
        if (b.intas == 1) b.cpu.set_intr(false);
        if (b.intas != 2) return;
        for (unsigned k = 0; k < b.cpu.if_changes(); ++k) seen.changes.push_back(b.cpu.if_change(k));
        seen.boundary = b.cpu.interrupt_boundary();
        seen.instr_start = b.cpu.instruction_start();
        seen.instr_cs = b.cpu.instruction_cs();
        seen.instr_ip = b.cpu.instruction_ip();
    };
    b.cpu.set_fast_forward(forward);
    while (b.cpu.cycles() < irq) {
        const cycles_t limit = std::min(irq, b.cpu.cycles() + slice);
        b.cpu.run_until(limit, false, limit);
    }
    b.cpu.set_intr(true);
    b.cpu.run_until(irq + 2'000, false);
    return seen;
}

} // namespace

TEST(CpuInterruptHistory, TheFastForwardKeepsTheHistory) {
    for (cycles_t irq : {cycles_t(150'001), cycles_t(150'013), cycles_t(150'029)}) {
        for (cycles_t slice : {cycles_t(1009), irq}) {
            SCOPED_TRACE(testing::Message() << "irq " << irq << " slice " << slice);
            Board on, off;
            const AtInta a = cli_sti_loop(on, true, irq, slice);
            const AtInta b = cli_sti_loop(off, false, irq, slice);
            ASSERT_EQ(off.intas, 2u);
            ASSERT_EQ(on.intas, 2u);
            EXPECT_GT(on.cpu.forwarded_cycles(), irq / 2);
            ASSERT_EQ(a.changes.size(), Cpu::kIfHistory);
            ASSERT_EQ(a.changes.size(), b.changes.size());
            for (std::size_t i = 0; i < a.changes.size(); ++i) EXPECT_TRUE(same(a.changes[i], b.changes[i])) << "change " << i;
            EXPECT_EQ(a.boundary, b.boundary);
            EXPECT_EQ(a.instr_start, b.instr_start);
            EXPECT_EQ(a.instr_cs, b.instr_cs);
            EXPECT_EQ(a.instr_ip, b.instr_ip);
            // The history is of the loop right before the interrupt: the newest change is the
            // STI that let it in or the CLI before it, within one period of the boundary.
            EXPECT_LT(a.boundary - a.changes[0].cycle, 100u);
        }
    }
}

namespace {

void collect(void* out, const IfChange& c) { static_cast<std::vector<IfChange>*>(out)->push_back(c); }

} // namespace

// The IF hook (Cpu::set_if_hook) sees every change, in order, each as the history records it: all
// of them, not the last kIfHistory; a forwarded loop's changes too, the same as executed.
TEST(CpuInterruptHistory, TheIfHookSeesEveryChangeForwardedOrNot) {
    constexpr cycles_t irq = 150'013;
    Board on, off;
    std::vector<IfChange> seen_on, seen_off;
    on.cpu.set_if_hook(&collect, &seen_on);
    off.cpu.set_if_hook(&collect, &seen_off);
    cli_sti_loop(on, true, irq, 1009);
    cli_sti_loop(off, false, irq, 1009);
    ASSERT_GT(on.cpu.forwarded_cycles(), irq / 2);
    // Each period of the loop (CLI 2, IN 10 + 1 Tw, STI 2, NOP 3, JMP 15: at least 32 clocks)
    // clears and sets IF: thousands of changes, far more than the history keeps.
    ASSERT_GT(seen_off.size(), 2 * (irq / 40));
    ASSERT_EQ(seen_on.size(), seen_off.size());
    for (std::size_t i = 0; i < seen_on.size(); ++i) ASSERT_TRUE(same(seen_on[i], seen_off[i])) << "change " << i;
    for (std::size_t i = 1; i < seen_off.size(); ++i) ASSERT_NE(seen_off[i].enabled, seen_off[i - 1].enabled) << i;
    // The newest ones are the history's.
    for (unsigned k = 0; k < off.cpu.if_changes(); ++k)
        EXPECT_TRUE(same(off.cpu.if_change(k), seen_off[seen_off.size() - 1 - k])) << k;
}
