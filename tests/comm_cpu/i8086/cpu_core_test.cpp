// Hand-written tests of the 8086 core for what the SingleStepTests vectors do not exercise:
// hardware interrupts, NMI, TF, HLT, the inhibit rules, REP interruption, wait states, odd words.
#include "comm_cpu/i8086/cpu.h"
#include "tests/comm_cpu/i8086/cpu_board.h"
#include "tests/support/sc_test.h"

#include <vector>

using namespace rcsim;
using namespace rcsim::i8086;

using rcsim::i8086::test::Board;
using rcsim::i8086::test::kStack;

TEST(Cpu8086Core, ResetVectorIsFFFF0) {
    Cpu cpu;
    cpu.reset();
    EXPECT_EQ(cpu.regs().s[CS], 0xFFFF);
    EXPECT_EQ(cpu.regs().ip, 0);
    EXPECT_EQ(cpu.pc(), 0xFFFF0u);
}

TEST(Cpu8086Core, IntrRunsTwoIntaCyclesAndReadsTheVectorOnTheSecond) {
    Board b;
    b.load({0xFB, 0x90, 0x90, 0x90, 0x90, 0x90}); // STI ; NOPs
    b.cpu.step(); // STI
    b.cpu.set_intr(true); // raised after STI: the boundary after STI is still inhibited
    b.cpu.step(); // NOP after STI always runs (STI inhibit)
    EXPECT_EQ(b.calls.size(), 0u);
    b.cpu.step(); // interrupt entry
    ASSERT_EQ(b.calls.size(), 2u);
    EXPECT_EQ(b.calls[0].kind, Bus::int_ack);
    EXPECT_EQ(b.calls[1].kind, Bus::int_ack);
    // back-to-back: the second INTA starts 4 clocks after the first (no wait states)
    EXPECT_EQ(b.calls[1].start - b.calls[0].start, 4u);
    EXPECT_EQ(b.cpu.regs().s[CS], 0);
    EXPECT_EQ(b.cpu.regs().ip, 0x0500);
    EXPECT_FALSE(b.cpu.regs().flags & flag::IF);
    // pushed: FLAGS (with IF), CS, IP of the next instruction (the third byte)
    EXPECT_EQ(b.word_at(kStack + 0xFE) & flag::IF, flag::IF);
    EXPECT_EQ(b.word_at(kStack + 0xFC), 0x1000);
    EXPECT_EQ(b.word_at(kStack + 0xFA), 0x0002);
    // The first ISR code fetch follows the pushes.
    bool fetched = false;
    for (const auto& c : b.cycles)
        if (c.kind == Bus::code_fetch && c.address == 0x500) fetched = true;
    EXPECT_TRUE(fetched);
}

// The end of the firmware's start-up (docs/scenarios.md "Start-up"): the first instruction
// boundary at which an INTR could be taken. The boundary after STI is inhibited, so it is the one
// after the instruction that follows STI, whether or not a request is pending.
TEST(Cpu8086Core, InterruptsEnabledAtIsTheFirstBoundaryThatCouldTakeAnIntr) {
    Board b;
    b.load({0x90, 0xFB, 0x90, 0x90, 0x90}); // NOP ; STI ; NOP ; NOP ; NOP
    b.cpu.step();                            // NOP, IF = 0
    EXPECT_EQ(b.cpu.interrupts_enabled_at(), Cpu::kNever);
    b.cpu.step(); // STI
    b.cpu.step(); // the NOP after STI: the boundary before it was inhibited
    EXPECT_EQ(b.cpu.interrupts_enabled_at(), Cpu::kNever);
    const auto after_nop = b.cpu.cycles(); // the boundary after that NOP
    b.cpu.step();
    EXPECT_EQ(b.cpu.interrupts_enabled_at(), after_nop);
    b.cpu.regs().flags &= static_cast<std::uint16_t>(~flag::IF); // set once, never cleared
    b.cpu.step();
    EXPECT_EQ(b.cpu.interrupts_enabled_at(), after_nop);
}

TEST(Cpu8086Core, IntrIgnoredWhileIfClear) {
    Board b;
    b.load({0x90, 0x90, 0x90, 0x90});
    b.cpu.set_intr(true);
    for (int i = 0; i < 3; ++i) b.cpu.step();
    EXPECT_TRUE(b.calls.empty());
    EXPECT_EQ(b.pc(), 0x10003u);
}

TEST(Cpu8086Core, NmiIsEdgeTriggeredAndIgnoresIf) {
    Board b;
    b.load({0x90, 0x90, 0x90, 0x90, 0x90, 0x90, 0x90, 0x90});
    b.cpu.step();
    b.cpu.set_nmi(true);
    b.cpu.step(); // NMI entry (IF=0)
    EXPECT_EQ(b.cpu.regs().ip, 0x0600);
    EXPECT_TRUE(b.calls.empty()) << "NMI has no INTA cycles";
    b.cpu.step(); // INC BX
    b.cpu.step(); // IRET
    EXPECT_EQ(b.pc(), 0x10001u);
    b.cpu.step();
    b.cpu.step(); // level still high: no second NMI without a new edge
    EXPECT_EQ(b.pc(), 0x10003u);
    EXPECT_EQ(b.cpu.regs().r[BX], 1);
}

TEST(Cpu8086Core, TrapFlagStepsEachInstruction) {
    Board b;
    // PUSHF; POP AX; OR AH,1; PUSH AX; POPF; NOP; NOP
    b.load({0x9C, 0x58, 0x80, 0xCC, 0x01, 0x50, 0x9D, 0x90, 0x90});
    for (int i = 0; i < 5; ++i) b.cpu.step();
    EXPECT_TRUE(b.cpu.regs().flags & flag::TF);
    b.cpu.step(); // the instruction after POPF runs, then the trap
    EXPECT_EQ(b.pc(), 0x10008u);
    b.cpu.step(); // trap entry
    EXPECT_EQ(b.cpu.regs().ip, 0x0700);
    EXPECT_FALSE(b.cpu.regs().flags & flag::TF);
    EXPECT_EQ(b.word_at(kStack + 0xFA), 0x0008);
}

TEST(Cpu8086Core, HltWaitsForIntr) {
    Board b;
    b.load({0xFB, 0xF4, 0x90});
    b.cpu.step(); // STI
    b.cpu.step(); // HLT
    EXPECT_TRUE(b.cpu.halted());
    const cycles_t c = b.cpu.cycles();
    for (int i = 0; i < 10; ++i) b.cpu.step();
    EXPECT_TRUE(b.cpu.halted());
    EXPECT_EQ(b.cpu.cycles(), c + 10);
    b.cpu.set_intr(true);
    b.cpu.step();
    EXPECT_FALSE(b.cpu.halted());
    EXPECT_EQ(b.cpu.regs().ip, 0x0500);
    EXPECT_EQ(b.word_at(kStack + 0xFA), 0x0002) << "returns after the HLT";
}

TEST(Cpu8086Core, HltWithIfClearWakesOnlyOnNmi) {
    Board b;
    b.load({0xF4, 0x90});
    b.cpu.step();
    b.cpu.set_intr(true);
    for (int i = 0; i < 5; ++i) b.cpu.step();
    EXPECT_TRUE(b.cpu.halted());
    b.cpu.set_nmi(true);
    b.cpu.step();
    EXPECT_FALSE(b.cpu.halted());
    EXPECT_EQ(b.cpu.regs().ip, 0x0600);
}

// MOV SS, POP SS, MOV DS and STI each hold INTR off for one instruction.
TEST(Cpu8086Core, InhibitAfterMovSegPopSegAndSti) {
    struct Case {
        std::vector<std::uint8_t> code;
        const char* what;
    };
    const std::vector<Case> cases = {
        {{0x8E, 0xD0, 0x90, 0x90}, "MOV SS,AX"},
        {{0x8E, 0xD8, 0x90, 0x90}, "MOV DS,AX"},
        {{0x16, 0x17, 0x90, 0x90}, "PUSH SS; POP SS"},
    };
    for (const auto& k : cases) {
        Board b;
        b.cpu.regs().r[AX] = 0x2000;
        b.cpu.regs().flags |= flag::IF;
        b.load(k.code);
        if (k.code[0] == 0x16) b.cpu.step(); // PUSH SS
        b.cpu.step();                         // the segment load
        b.cpu.set_intr(true);
        b.cpu.step(); // the boundary after it is inhibited: the next instruction runs
        EXPECT_EQ(b.pc(), 0x10000u + k.code.size() - 1) << k.what;
        EXPECT_TRUE(b.calls.empty()) << k.what;
        b.cpu.step();
        EXPECT_EQ(b.calls.size(), 2u) << k.what;
    }
    // STI with IF already set does not delay.
    Board b;
    b.cpu.regs().flags |= flag::IF;
    b.load({0x90, 0xFB, 0x90, 0x90});
    b.cpu.step(); // NOP
    b.cpu.set_intr(true);
    b.cpu.step(); // the boundary before STI sees the request: taken at once
    EXPECT_EQ(b.calls.size(), 2u);
}

TEST(Cpu8086Core, NoInterruptBetweenPrefixAndInstruction) {
    Board b;
    b.cpu.regs().flags |= flag::IF;
    b.load({0x26, 0x8B, 0x07, 0x90}); // ES: MOV AX,[BX]
    b.cpu.set_intr(false);
    b.cpu.step(); // prefix + instruction as one step
    EXPECT_EQ(b.pc(), 0x10003u);
    b.cpu.set_intr(true);
    b.cpu.step();
    EXPECT_EQ(b.word_at(kStack + 0xFA), 0x0003) << "return address is an instruction start";
}

// REP MOVSB with INTR: stops between elements with IP at the last prefix; CX/SI/DI count the
// completed elements; IRET resumes and finishes the run.
TEST(Cpu8086Core, RepMovsIsInterruptibleAndResumes) {
    Board b;
    b.cpu.regs().flags |= flag::IF;
    b.cpu.regs().r[CX] = 20;
    b.cpu.regs().r[SI] = 0;
    b.cpu.regs().r[DI] = 0;
    for (int i = 0; i < 20; ++i) b.ram[0x30000 + i] = std::uint8_t(i + 1);
    b.load({0xF3, 0xA4, 0x90, 0x90}); // REP MOVSB
    b.cpu.start();
    // A run_until limit inside the run suspends it at an element boundary (as the SystemC
    // module does at a slice end); INTR raised there is taken before the next element.
    b.cpu.run_until(b.cpu.cycles() + 60);
    const std::uint16_t cx = b.cpu.regs().r[CX];
    EXPECT_GT(cx, 0);
    EXPECT_LT(cx, 20);
    EXPECT_EQ(b.cpu.regs().r[SI], 20 - cx);
    b.cpu.set_intr(true);
    b.cpu.step(); // interrupt entry
    EXPECT_EQ(b.cpu.regs().ip, 0x0500);
    EXPECT_EQ(b.word_at(kStack + 0xFA), 0x0000) << "return to the REP prefix";
    b.cpu.set_intr(false);
    b.cpu.step(); // INC BX
    b.cpu.step(); // IRET
    b.cpu.step(); // the rest of the run
    EXPECT_EQ(b.cpu.regs().r[CX], 0);
    for (int i = 0; i < 20; ++i) EXPECT_EQ(b.ram[0x40000 + i], i + 1);
}

// The multiple-prefix bug: REP ES: MOVSB resumes at ES: only, so the REP is lost.
TEST(Cpu8086Core, RepWithSegmentPrefixLosesRepAfterInterrupt) {
    Board b;
    b.cpu.regs().flags |= flag::IF;
    b.cpu.regs().r[CX] = 20;
    b.load({0xF3, 0x26, 0xA4, 0x90, 0x90}); // REP ES: MOVSB
    b.cpu.start();
    b.cpu.run_until(b.cpu.cycles() + 60);
    const std::uint16_t cx = b.cpu.regs().r[CX];
    ASSERT_GT(cx, 1);
    b.cpu.set_intr(true);
    b.cpu.step(); // interrupt
    EXPECT_EQ(b.word_at(kStack + 0xFA), 0x0001) << "IP rewound to the last prefix (ES:)";
    b.cpu.set_intr(false);
    b.cpu.step();
    b.cpu.step(); // IRET
    b.cpu.step(); // ES: MOVSB without REP: one element
    EXPECT_EQ(b.cpu.regs().r[CX], cx) << "CX untouched: the REP prefix was lost";
    EXPECT_EQ(b.pc(), 0x10003u);
}

TEST(Cpu8086Core, WaitStatesStretchBusCycles) {
    std::vector<CycleRecord> trace;
    for (unsigned waits : {0u, 2u}) {
        Board b(waits);
        b.load({0x8B, 0x07, 0x90, 0x90}); // MOV AX,[BX]
        b.cpu.start();
        trace.clear();
        b.cpu.set_cycle_trace(&trace);
        b.cpu.step();
        unsigned reads = 0, run = 0, ends = 0;
        bool seen_t3 = false;
        for (const auto& r : b.cycles) reads += r.kind == Bus::mem_read;
        EXPECT_EQ(reads, 1u);
        // every bus cycle seen from T3 to T4 in the trace has exactly `waits` Tw states
        for (const auto& c : trace) {
            if (c.t == TState::T3) { seen_t3 = true; run = 0; }
            else if (c.t == TState::Tw) ++run;
            else if (c.t == TState::T4 && seen_t3) { EXPECT_EQ(run, waits); ++ends; }
        }
        EXPECT_GE(ends, 2u);
        for (const auto& r : b.cycles) EXPECT_EQ(r.wait_states, waits);
    }
}

TEST(Cpu8086Core, IoWaitStatesComeFromTheHandler) {
    Board b;
    b.io_waits = 3;
    b.load({0xE4, 0x40, 0x90}); // IN AL,40h
    std::vector<CycleRecord> trace;
    b.cpu.start();
    b.cpu.set_cycle_trace(&trace);
    b.cpu.step();
    ASSERT_EQ(b.calls.size(), 1u);
    EXPECT_EQ(b.calls[0].kind, Bus::io_read);
    EXPECT_EQ(b.calls[0].address, 0x40u);
    EXPECT_EQ(b.cpu.regs().r[AX] & 0xFF, 0x34);
    unsigned tw = 0;
    for (const auto& c : trace) tw += c.t == TState::Tw && c.status == Bus::passive;
    EXPECT_GE(tw, 3u);
}

TEST(Cpu8086Core, OddWordIsTwoByteCycles) {
    Board b;
    b.cpu.regs().r[BX] = 0x0011;
    b.cpu.regs().r[AX] = 0xBEEF;
    b.load({0x89, 0x07, 0x89, 0x47, 0x01}); // MOV [BX],AX ; MOV [BX+1],AX
    b.cpu.step();
    b.cpu.step();
    std::vector<BusRecord> writes;
    for (const auto& c : b.cycles)
        if (c.kind == Bus::mem_write) writes.push_back(c);
    ASSERT_EQ(writes.size(), 3u);
    EXPECT_EQ(writes[0].width, 1);
    EXPECT_EQ(writes[0].address, 0x30011u);
    EXPECT_EQ(writes[1].width, 1);
    EXPECT_EQ(writes[1].address, 0x30012u);
    EXPECT_EQ(writes[1].start - writes[0].start, 4u) << "second byte follows T4 directly";
    EXPECT_EQ(writes[2].width, 2) << "an even word is one cycle";
    EXPECT_EQ(b.word_at(0x30012), 0xBEEF);
}

TEST(Cpu8086Core, DivideErrorPushesNextInstruction) {
    Board b;
    b.cpu.regs().r[CX] = 0;
    b.load({0xF6, 0xF1, 0x90}); // DIV CL (by zero)
    b.cpu.step();
    EXPECT_EQ(b.cpu.regs().ip, 0x0800);
    EXPECT_EQ(b.word_at(kStack + 0xFA), 0x0002);
}

TEST(Cpu8086Core, IntNAndInto) {
    Board b;
    b.set_vector(4, 0x0900, 0);
    b.ram[0x900] = 0xCF;
    b.load({0xCD, 0x20, 0xCE, 0x90});
    b.cpu.step();
    EXPECT_EQ(b.cpu.regs().ip, 0x0500);
    b.cpu.step();
    b.cpu.step(); // IRET
    EXPECT_EQ(b.pc(), 0x10002u);
    b.cpu.step(); // INTO with OF=0: no interrupt
    EXPECT_EQ(b.pc(), 0x10003u);
}

TEST(Cpu8086Core, RomWritesAreIgnoredAndCounted) {
    std::vector<std::uint8_t> rom(0x10000, 0x90);
    std::vector<std::uint8_t> ram(0x10000, 0);
    Cpu cpu;
    cpu.map_memory(MemRegion{"ram", 0, 0x10000, ram.data(), 0, true});
    cpu.map_memory(MemRegion{"rom", 0xF0000, 0x10000, rom.data(), 0, false});
    rom[0xFFF0] = 0xA2; // MOV [0000],AL with DS=0 -> RAM
    rom[0xFFF1] = 0x00;
    rom[0xFFF2] = 0x00;
    cpu.reset();
    cpu.regs().s[DS] = 0xF000;
    cpu.step();
    EXPECT_EQ(cpu.rom_writes(), 1u);
    EXPECT_EQ(rom[0], 0x90);
}

namespace {
struct StepSpy {
    std::vector<std::uint32_t> seen;
    std::uint32_t stop_at = 0xFFFFFFFF;
    static bool hook(void* ctx, const Cpu& cpu) {
        auto* spy = static_cast<StepSpy*>(ctx);
        spy->seen.push_back(cpu.pc());
        return cpu.pc() == spy->stop_at;
    }
};
} // namespace

TEST(Cpu8086Core, StepHookSeesEveryInstructionOnceWithPrefixesAsPartOfIt) {
    Board b;
    // NOP ; ES: MOV AL,[0] (prefix + 3 bytes) ; INC AX ; HLT
    b.load({0x90, 0x26, 0xA0, 0x00, 0x00, 0x40, 0xF4});
    StepSpy spy;
    b.cpu.set_step_hook(&StepSpy::hook, &spy);
    b.cpu.run_until(b.cpu.cycles() + 200, false);
    EXPECT_EQ(spy.seen, (std::vector<std::uint32_t>{0x10000, 0x10001, 0x10005, 0x10006}));
}

TEST(Cpu8086Core, StepHookStopsBeforeTheInstructionAndResumesWithoutStoppingAgain) {
    Board b;
    b.load({0x40, 0x40, 0x40, 0xF4}); // INC AX x3 ; HLT
    StepSpy spy;
    spy.stop_at = 0x10001;
    b.cpu.set_step_hook(&StepSpy::hook, &spy);
    b.cpu.regs().r[AX] = 0;
    b.cpu.run_until(b.cpu.cycles() + 200, false);
    EXPECT_EQ(b.pc(), 0x10001u);
    EXPECT_EQ(b.cpu.regs().r[AX], 1); // the second INC has not run
    b.cpu.run_until(b.cpu.cycles() + 200, false);
    EXPECT_EQ(b.cpu.regs().r[AX], 3);
    EXPECT_TRUE(b.cpu.halted());
    EXPECT_EQ(spy.seen, (std::vector<std::uint32_t>{0x10000, 0x10001, 0x10002, 0x10003}));
}
