// The 8086 module's debugger access (comm_cpu/cpu8086.h) on the assembled controller: memory
// through the board's map without side effects, the second bus observer, and the core's
// debug_jump at an instruction boundary.
#include "scenarios/board/controller.h"
#include "tests/support/sc_test.h"

#include <gtest/gtest.h>

#include <vector>

using namespace rcsim;

namespace {

// The ROM (F0000-FFFFF): at F000:0000  INC AX; HLT   at F000:0010  INC BX; HLT
// and at the reset vector FFFF:0000 a far jump to F000:0000.
std::vector<std::uint8_t> tiny_rom() {
    std::vector<std::uint8_t> rom(0x10000, 0x90);
    rom[0x0000] = 0x40; // INC AX
    rom[0x0001] = 0xF4; // HLT
    rom[0x0010] = 0x43; // INC BX
    rom[0x0011] = 0xF4; // HLT
    const std::uint8_t jmp[] = {0xEA, 0x00, 0x00, 0x00, 0xF0}; // JMP FAR F000:0000
    std::copy(std::begin(jmp), std::end(jmp), rom.begin() + 0xFFF0);
    return rom;
}

TEST(CpuDebug, MemoryThroughTheBoardMapWithoutSideEffects) {
    Controller ctl("ctl");
    ctl.comm.load_rom(tiny_rom());
    Cpu8086& cpu = ctl.comm.cpu;
    sc_core::sc_start(sc_core::SC_ZERO_TIME); // the sockets are bound at the end of elaboration
    std::uint8_t b[2] = {0x12, 0x34};
    // RAM (00000-0FFFF) and ROM (F0000-FFFFF): the direct map, ROM writable for the debugger.
    ASSERT_TRUE(cpu.debug_write(0x0400, b, 2));
    EXPECT_EQ(ctl.comm.ram()[0x400], 0x12);
    EXPECT_EQ(ctl.comm.ram()[0x401], 0x34);
    std::uint8_t r[2] = {};
    ASSERT_TRUE(cpu.debug_read(0xF0000, r, 2));
    EXPECT_EQ(r[0], 0x40);
    EXPECT_EQ(r[1], 0xF4);
    ASSERT_TRUE(cpu.debug_write(0xF0001, b, 1));
    EXPECT_EQ(ctl.comm.rom()[1], 0x12);
    // DP-RAM (D0000-D03FF) through the debug transport: a write into the right CPU's mailbox
    // (3FF) is stored but does not raise INT_R as a bus write from the left port would.
    const std::uint8_t m = 0x5A;
    ASSERT_TRUE(cpu.debug_write(0xD03FF, &m, 1));
    std::uint8_t back = 0;
    ASSERT_TRUE(cpu.debug_read(0xD03FF, &back, 1));
    EXPECT_EQ(back, 0x5A);
    EXPECT_FALSE(ctl.dpram.int_r_pending());
    // Nothing decodes 10000-CFFFF.
    EXPECT_FALSE(cpu.debug_read(0x10000, r, 1));
    EXPECT_FALSE(cpu.debug_read(0xD03FF, r, 2)); // D0400 is past the DP-RAM
}

struct Seen {
    unsigned cycles = 0;
    static void hook(void* self, const i8086::BusRecord&) { ++static_cast<Seen*>(self)->cycles; }
};

struct Jumper {
    Cpu8086* cpu = nullptr;
    bool done = false;
    // At the first boundary in the ROM's program (F0000), continue at F000:0010 instead.
    static bool hook(void* self, const i8086::Cpu& core) {
        auto* j = static_cast<Jumper*>(self);
        if (!j->done && core.pc() == 0xF0000) {
            j->done = true;
            j->cpu->core().debug_jump(0xF000, 0x0010);
        }
        return false;
    }
};

TEST(CpuDebug, DebugBusObserverBesideTheFirstAndDebugJump) {
    Controller ctl("ctl");
    ctl.comm.load_rom(tiny_rom());
    Cpu8086& cpu = ctl.comm.cpu;
    Seen first, second;
    cpu.set_bus_observer(&Seen::hook, &first);
    cpu.set_debug_bus_observer(&Seen::hook, &second);
    Jumper j{&cpu};
    cpu.set_step_observer(&Jumper::hook, &j);
    sc_core::sc_start(sc_core::sc_time(20, sc_core::SC_US));
    EXPECT_TRUE(j.done);
    // INC AX at F0000 never ran; INC BX at F0010 did, then HLT.
    EXPECT_EQ(cpu.core().regs().r[i8086::AX], 0);
    EXPECT_EQ(cpu.core().regs().r[i8086::BX], 1);
    EXPECT_TRUE(cpu.core().halted());
    EXPECT_GT(first.cycles, 0u);
    EXPECT_EQ(second.cycles, first.cycles);
}

} // namespace
