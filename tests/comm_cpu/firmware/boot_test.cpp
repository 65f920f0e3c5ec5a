// The firmware ROM on the plain 8086 core: reset, start-up, 8259A/82510 set-up, main loop.
#include "fake_board.h"
#include "tests/support/sc_test.h"

#include <utility>
#include <vector>

namespace {

using namespace fakeboard;

using Writes = std::vector<std::pair<unsigned, unsigned>>; // (byte offset, value)

// The writes of uart_init() to one 82510, as docs/firmware.md lists them.
Writes expected_uart_setup(bool tick) {
    // offsets are bytes from the chip's base: register r at 2r (BANK = 4)
    Writes w = {{4, 0x20}, {14, 0x10},              // bank 1, ICM software reset
                {4, 0x00}, {6, 0x9B}, {0, 60}, {2, 0}}; // bank 0, LCR DLAB+8E1, BAL, BAH
    if (tick) w.insert(w.end(), {{4, 0x60}, {0, 0x00}, {2, 0x24}, {4, 0x00}}); // BRGB = 9216
    w.insert(w.end(), {{6, 0x1B}, {8, 0x0B},                                   // LCR 8E1, MCR
                       {4, 0x40}, {2, 0x00}, {6, 0x00}, {8, 0x00}, {12, 0x1E}, {14, 0x00}, // bank 2
                       {4, 0x60}, {0, 0x50}, {2, 0x04}, {6, 0x00}, {10, 0x00},             // bank 3
                       {12, std::uint8_t(tick ? 0x02 : 0x00)},
                       {4, 0x20}, {10, 0xB0}, {12, 0x0E}, {14, 0x04}});                    // bank 1
    if (tick) w.push_back({6, 0x22}); // TMCR: start timer B
    w.insert(w.end(), {{4, 0x00}, {2, std::uint8_t(tick ? 0x25 : 0x05)}, {4, 0x20}}); // GER, bank 1
    return w;
}

TEST(FirmwareBoot, ProgramsThe8259AFirst) {
    FakeBoard b;
    b.run_ms(5);
    ASSERT_GE(b.io_writes.size(), 4u);
    const std::pair<unsigned, unsigned> icw[] = {{0xC0, 0x13}, {0xC2, 0x20}, {0xC2, 0x01}, {0xC2, 0xF0}};
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(b.io_writes[i].port, icw[i].first) << i;
        EXPECT_EQ(b.io_writes[i].value, icw[i].second) << i;
    }
    EXPECT_EQ(b.pic.base, 0x20);
    EXPECT_EQ(b.pic.icw4, 0x01);
    EXPECT_EQ(b.pic.imr, 0xF0);
}

TEST(FirmwareBoot, SetsUpEach82510InOrder) {
    FakeBoard b;
    b.run_ms(5);
    for (unsigned p = 0; p < 3; ++p) {
        const unsigned base = 0x80 + 0x10 * p;
        Writes got;
        for (const auto& w : b.io_writes)
            if (w.port >= base && w.port < base + 0x10) got.push_back({w.port - base, w.value});
        const Writes want = expected_uart_setup(p == 0);
        ASSERT_GE(got.size(), want.size()) << "port " << p;
        for (std::size_t i = 0; i < want.size(); ++i) {
            EXPECT_EQ(got[i].first, want[i].first) << "port " << p << " write " << i;
            EXPECT_EQ(got[i].second, want[i].second) << "port " << p << " write " << i;
        }
        EXPECT_EQ(b.uart[p].bal, 60) << "9600 bps at 18.432 MHz";
        EXPECT_EQ(b.uart[p].lcr, 0x1B) << "8E1, DLAB off";
        EXPECT_EQ(b.uart[p].bank, 0x20) << "left in the working bank";
    }
    EXPECT_EQ(b.uart[0].bbl | (b.uart[0].bbh << 8), 9216);
}

TEST(FirmwareBoot, LineSetUpComesFromThePatchableTable) {
    FakeBoard b;
    // port 1: 19200 bps 8N1 (divisor 30, LCR 0x03); a 9.216 MHz-based tick of 2 ms on #0
    b.rom[fw::rom_offset_of(fw::data::port_div) + 2] = 30;
    b.rom[fw::rom_offset_of(fw::data::port_lcr) + 1] = 0x03;
    b.rom[fw::rom_offset_of(fw::data::tick_div)] = 0x00;
    b.rom[fw::rom_offset_of(fw::data::tick_div) + 1] = 0x48; // 18432
    b.run_ms(5);
    EXPECT_EQ(b.uart[0].bal, 60);
    EXPECT_EQ(b.uart[0].lcr, 0x1B);
    EXPECT_EQ(b.uart[1].bal, 30);
    EXPECT_EQ(b.uart[1].lcr, 0x03);
    EXPECT_EQ(b.uart[2].bal, 60);
    const unsigned t0 = b.var16(fw::data::ticks);
    b.run_ms(20);
    const unsigned n = b.var16(fw::data::ticks) - t0;
    EXPECT_GE(n, 9u);
    EXPECT_LE(n, 11u);
}

TEST(FirmwareBoot, InstallsVectors20To23InRam) {
    FakeBoard b;
    b.run_ms(5);
    const std::uint32_t isr[] = {fw::code::isr_port0, fw::code::isr_port1, fw::code::isr_port2,
                                 fw::code::isr_dpram};
    for (unsigned i = 0; i < 4; ++i) {
        const unsigned v = 4 * (0x20 + i);
        const unsigned off = b.ram[v] | (b.ram[v + 1] << 8), seg = b.ram[v + 2] | (b.ram[v + 3] << 8);
        EXPECT_EQ(seg, 0xF000u) << i;
        EXPECT_EQ(0xF0000u + off, isr[i]) << i;
    }
    // every other vector goes to the catch-all handler (e.g. the spurious IR7, vector 0x27)
    const unsigned v27 = 4 * 0x27;
    EXPECT_EQ(0xF0000u + (b.ram[v27] | (b.ram[v27 + 1] << 8)), fw::code::isr_unexpected);
    EXPECT_EQ(0xF0000u + (b.ram[0] | (b.ram[1] << 8)), fw::code::isr_unexpected);
}

TEST(FirmwareBoot, ReachesTheMainLoopWithInterruptsEnabled) {
    FakeBoard b;
    b.run_ms(5);
    std::uint32_t loop_end = 0xFFFFF;
    for (const auto& s : fw::symbols)
        if (s.code && s.linear > fw::code::main_loop && s.linear < loop_end) loop_end = s.linear;
    bool in_loop = false;
    for (int i = 0; i < 20000 && !in_loop; ++i) {
        b.cpu.step();
        in_loop = b.cpu.pc() >= fw::code::main_loop && b.cpu.pc() < loop_end;
    }
    ASSERT_TRUE(in_loop) << "pc " << std::hex << b.cpu.pc();
    EXPECT_TRUE(b.cpu.regs().flags & rcsim::i8086::flag::IF);
    EXPECT_EQ(b.cpu.regs().s[rcsim::i8086::DS], fw::data_segment);
    EXPECT_EQ(b.cpu.regs().s[rcsim::i8086::SS], fw::data_segment);
    EXPECT_EQ(b.cpu.rom_writes(), 0u);
    for (unsigned p = 0; p < 3; ++p) EXPECT_EQ(b.step(p), 0) << p;
}

TEST(FirmwareBoot, TimerTicksEveryMillisecond) {
    FakeBoard b;
    b.run_ms(5);
    const unsigned t0 = b.var16(fw::data::ticks);
    b.run_ms(50);
    const unsigned t1 = b.var16(fw::data::ticks);
    // the periodic BRGB timer is started once and never re-armed (that would add the latency)
    EXPECT_GE(t1 - t0, 49u);
    EXPECT_LE(t1 - t0, 51u);
    EXPECT_EQ(b.uart[0].timer_starts, 1u);
    EXPECT_EQ(b.var16(fw::data::unexpected), 0u);
    // every interrupt so far was IR0 (the tick) and ended with a rotate-on-non-specific EOI
    ASSERT_FALSE(b.irqs.empty());
    for (const auto& r : b.irqs) {
        EXPECT_EQ(r.vector, 0x20);
        EXPECT_TRUE(r.eoi_seen);
    }
    // a tick alone takes the assembly fast path: INTA to EOI well under 50 us
    const std::size_t n = b.irqs.size();
    ASSERT_TRUE(b.run_until([&] { return b.irqs.size() > n; }, 2));
    const cycles_t inta = b.irqs.back().inta;
    while (!b.irqs.back().eoi_seen) b.cpu.step();
    EXPECT_LT(b.now() - inta, 50 * cycles_per_us);
}

TEST(FirmwareBoot, IsrRestoresTheBankItInterrupted) {
    FakeBoard b;
    b.run_ms(5);
    ASSERT_FALSE(b.irqs.empty());
    for (const auto& r : b.irqs) {
        ASSERT_TRUE(r.eoi_seen);
        EXPECT_EQ(r.bank_at_eoi, r.bank_at_entry);
    }
    // interrupted while bank 2 is selected: the ISR works in bank 1 and restores bank 2
    const std::size_t writes = b.io_writes.size(), irqs = b.irqs.size();
    b.uart[0].bank = 0x40;
    ASSERT_TRUE(b.run_until([&] { return b.irqs.size() > irqs && b.irqs[irqs].eoi_seen; }, 3));
    EXPECT_EQ(b.irqs[irqs].bank_at_entry, 0x40);
    EXPECT_EQ(b.irqs[irqs].bank_at_eoi, 0x40);
    std::vector<unsigned> banks;
    for (std::size_t i = writes; i < b.io_writes.size(); ++i)
        if (b.io_writes[i].port == kUartIoBase + 2 * u::BANK) banks.push_back(b.io_writes[i].value); // #0's BANK
    ASSERT_GE(banks.size(), 2u);
    EXPECT_EQ(banks[0], 0x20u);
    EXPECT_EQ(banks[1], 0x40u);
    EXPECT_EQ(b.var16(fw::data::ticks) > 0, true);
}

TEST(FirmwareBoot, ClearsDpramFlagsAndTheStaleMailbox) {
    FakeBoard b;
    for (unsigned p = 0; p < 3; ++p) b.dp[dl::pflag_addr(p)] = 0x5A;
    b.dp[dl::int2ext] = 0x77;
    b.int_l = true; // left over from before the reset
    b.run_ms(5);
    for (unsigned p = 0; p < 3; ++p) EXPECT_EQ(b.pflag(p), 0) << p;
    EXPECT_FALSE(b.int_l);
    EXPECT_EQ(b.dp[dl::int2ext], 0);
    EXPECT_TRUE(b.posted.empty()) << "no word to the main CPU at start-up";
}

} // namespace
