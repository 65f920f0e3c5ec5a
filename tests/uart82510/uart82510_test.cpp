// Tests of the Intel 82510 model as the CPU sees it: registers of every bank, bank switching,
// software reset, bus lanes and configuration; the interrupt sources, their priority in GIR,
// the INT pin in automatic and manual acknowledge modes, the timers. The serial side is
// uart82510_serial_test.cpp; the set-up both use is uart_on_line.h.
#include "tests/uart82510/uart_on_line.h"

#include <set>
#include <string>
#include <utility>
#include <vector>

using namespace rcsim;
using namespace rcsim::i82510;
using namespace rcsim::test::uart;
using sc_core::sc_time;

// ---- registers ---------------------------------------------------------------------------

TEST(Uart82510Registers, ResetValuesOfEveryBank) {
    UartOnLine b;
    run([&] {
        Cpu& c = b.cpu;
        // bank 0
        EXPECT_EQ(c.rd(RXD), 0x00);
        EXPECT_EQ(c.rd(GER), 0x00);
        EXPECT_EQ(c.rd(GIR), 0x01); // bank 0, nothing pending
        EXPECT_EQ(c.rd(LCR), 0x00);
        EXPECT_EQ(c.rd(MCR), 0x00);
        EXPECT_EQ(c.rd(LSR), LSR_TFST | LSR_TXST);
        EXPECT_EQ(c.rd(MSR), 0x00);
        EXPECT_EQ(c.rd(ACR0), 0x00);
        c.wr(LCR, LCR_DLAB);
        EXPECT_EQ(c.rd(BAL), 0x00);
        EXPECT_EQ(c.rd(BAH), 0x00);
        c.wr(LCR, 0);
        // bank 1
        c.bank(1);
        EXPECT_EQ(c.rd(RXD), 0x00);
        EXPECT_EQ(c.rd(RXF), 0x00);
        EXPECT_EQ(c.rd(GIR), 0x21);
        EXPECT_EQ(c.rd(TMST), 0x00);
        EXPECT_EQ(c.rd(FLR), 0x00);
        EXPECT_EQ(c.rd(RST), 0x00);
        EXPECT_EQ(c.rd(6), 0x00);                                  // MSR
        EXPECT_EQ(c.rd(GSR), (1u << tx_fifo) | (1u << tx_machine)); // empty and idle
        // bank 2
        c.bank(2);
        EXPECT_EQ(c.rd(0), 0xFF); // unused
        EXPECT_EQ(c.rd(FMD), 0x00);
        EXPECT_EQ(c.rd(GIR), 0x41);
        EXPECT_EQ(c.rd(TMD), 0x00);
        EXPECT_EQ(c.rd(IMD), IMD_RFD);
        EXPECT_EQ(c.rd(ACR1), 0x00);
        EXPECT_EQ(c.rd(RIE), 0x1E);
        EXPECT_EQ(c.rd(RMD), 0x00);
        // bank 3
        c.bank(3);
        EXPECT_EQ(c.rd(CLCF), 0x50);
        EXPECT_EQ(c.rd(BACF), 0x04);
        EXPECT_EQ(c.rd(GIR), 0x61);
        EXPECT_EQ(c.rd(BBCF), 0x00);
        EXPECT_EQ(c.rd(PMD), 0x00);
        EXPECT_EQ(c.rd(MIE), 0x0F);
        EXPECT_EQ(c.rd(TMIE), 0x00);
        EXPECT_EQ(c.rd(7), 0xFF); // unused
    });
    EXPECT_FALSE(b.irq.read());
}

TEST(Uart82510Registers, EveryReadWriteRegisterHoldsItsBits) {
    UartOnLine b;
    run([&] {
        Cpu& c = b.cpu;
        struct Reg {
            unsigned bank, off;
            std::uint8_t mask; // bits that hold a written value
            const char* name;
        };
        const Reg regs[] = {
            {0, GER, 0x3F, "GER"},  {0, LCR, 0xBF, "LCR"},  {0, MCR, 0x0F, "MCR"}, {0, ACR0, 0xFF, "ACR0"},
            {2, FMD, 0x33, "FMD"},  {2, TMD, 0xFF, "TMD"},  {2, IMD, 0x0F, "IMD"}, {2, ACR1, 0xFF, "ACR1"},
            {2, RIE, 0xFE, "RIE"},  {2, RMD, 0xFF, "RMD"},  {3, CLCF, 0xF0, "CLCF"}, {3, BACF, 0x7F, "BACF"},
            {3, BBCF, 0xFF, "BBCF"}, {3, PMD, 0xFF, "PMD"}, {3, MIE, 0x0F, "MIE"}, {3, TMIE, 0x03, "TMIE"},
        };
        for (std::uint8_t pattern : {0x55, 0xAA, 0xFF, 0x00}) {
            for (const Reg& r : regs) {
                c.bank(r.bank);
                c.wr(r.off, pattern & r.mask);
                EXPECT_EQ(c.rd(r.off), pattern & r.mask) << r.name << " pattern " << int(pattern);
            }
        }
        // DLAB: BAL/BAH in bank 0, BBL/BBH in bank 3, without touching RXD/GER/CLCF/BACF.
        c.bank(0);
        c.wr(GER, 0x05);
        c.wr(LCR, LCR_DLAB);
        c.wr(BAL, 0x34);
        c.wr(BAH, 0x12);
        c.bank(3);
        c.wr(CLCF, 0x50); // with DLAB: BBL
        c.wr(BACF, 0x06); // with DLAB: BBH
        EXPECT_EQ(c.rd(BBL), 0x50);
        EXPECT_EQ(c.rd(BBH), 0x06);
        c.bank(0);
        EXPECT_EQ(c.rd(BAL), 0x34);
        EXPECT_EQ(c.rd(BAH), 0x12);
        c.wr(LCR, 0x03);
        EXPECT_EQ(c.rd(GER), 0x05);
        c.bank(3);
        EXPECT_EQ(c.rd(CLCF), 0x00); // written 0x00 by the last pattern, not by the BBL writes
        EXPECT_EQ(c.rd(BACF), 0x00);
    });
}

TEST(Uart82510Registers, BankSwitchingAndGirInEveryBank) {
    UartOnLine b;
    run([&] {
        Cpu& c = b.cpu;
        c.wr(GER, 1u << tx_fifo); // the empty TX FIFO is a pending source
        for (unsigned bank = 0; bank < 4; ++bank) {
            c.wr(BANK, static_cast<std::uint8_t>((bank << 5) | 0x01)); // bit 0 and others ignored
            EXPECT_EQ(b.uart.bank(), bank);
            EXPECT_EQ(c.rd(GIR), (bank << 5) | 0x02) << "bank " << bank;
        }
        // The driver detection idiom: write 0x40 to offset 2, read bits 6:5 back.
        c.wr(BANK, 0x40);
        EXPECT_EQ(c.rd(GIR) & 0x60, 0x40);
        // Bits 7 and 4 of the bank write are ignored.
        c.wr(BANK, 0x90);
        EXPECT_EQ(b.uart.bank(), 0u);
    });
}

TEST(Uart82510Registers, SoftwareResetRestoresRegistersAndBank) {
    UartOnLine b;
    run([&] {
        Cpu& c = b.cpu;
        c.wr(GER, 0x3F);
        c.wr(LCR, 0x1B);
        c.bank(2);
        c.wr(IMD, 0x08);
        c.bank(1);
        c.wr(ICM, ICM_RESET);
        EXPECT_EQ(b.uart.bank(), 0u);
        EXPECT_EQ(c.rd(GER), 0x00);
        EXPECT_EQ(c.rd(LCR), 0x00);
        c.bank(2);
        EXPECT_EQ(c.rd(IMD), IMD_RFD);
    });
}

TEST(Uart82510Registers, BusRejectsOtherLanesAndInta) {
    UartOnLine b;
    run([&] {
        std::uint8_t d = 0;
        EXPECT_EQ(bus_access(b.cpu.sock, BusCycle::io_read, 3, &d, 1, sc_core::sc_time_stamp()).status,
                  tlm::TLM_ADDRESS_ERROR_RESPONSE); // odd address: high lane, not wired
        EXPECT_EQ(bus_access(b.cpu.sock, BusCycle::io_read, 16, &d, 1, sc_core::sc_time_stamp()).status,
                  tlm::TLM_ADDRESS_ERROR_RESPONSE); // beyond register 7
        EXPECT_EQ(bus_access(b.cpu.sock, BusCycle::int_ack, 0, &d, 1, sc_core::sc_time_stamp()).status,
                  tlm::TLM_ADDRESS_ERROR_RESPONSE);
        std::uint8_t w[2] = {0, 0};
        EXPECT_TRUE(bus_access(b.cpu.sock, BusCycle::io_read, 2 * LSR, w, 2, sc_core::sc_time_stamp()).ok());
        EXPECT_EQ(w[0], LSR_TFST | LSR_TXST);
        EXPECT_EQ(w[1], 0xFF); // high byte floats
    });
}

TEST(Uart82510Registers, AddressShiftIsAProperty) {
    Uart82510::Config cfg;
    cfg.addr_shift = 2; // e.g. the QT960 board: A0..A2 on CPU A2..A4
    UartOnLine b(cfg);
    run([&] {
        std::uint8_t d = 0;
        EXPECT_TRUE(bus_access(b.cpu.sock, BusCycle::io_read, 4 * LSR, &d, 1, sc_core::sc_time_stamp()).ok());
        EXPECT_EQ(d, LSR_TFST | LSR_TXST);
        EXPECT_EQ(bus_access(b.cpu.sock, BusCycle::io_read, 2 * LSR, &d, 1, sc_core::sc_time_stamp()).status,
                  tlm::TLM_ADDRESS_ERROR_RESPONSE);
    });
}

TEST(Uart82510Registers, BadConfigurationIsNamed) {
    auto message = [](Uart82510::Config cfg) {
        try {
            Uart82510 u("u", cfg);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    Uart82510::Config c1;
    c1.clock_hz = 0;
    EXPECT_NE(message(c1).find("clock 0 Hz"), std::string::npos);
    Uart82510::Config c2;
    c2.fifo_depth = 17;
    EXPECT_NE(message(c2).find("FIFO depth 17"), std::string::npos);
    Uart82510::Config c3;
    c3.addr_shift = 9;
    EXPECT_NE(message(c3).find("address shift 9"), std::string::npos);
    Uart82510::Config c4;
    c4.inta_low_cycles = 0;
    EXPECT_NE(message(c4).find("INTA low time 0"), std::string::npos);
}

// ---- interrupts --------------------------------------------------------------------------

TEST(Uart82510Interrupts, GirPriorityWithSeveralSourcesPending) {
    UartOnLine b;
    run([&] {
        Cpu& c = b.cpu;
        c.setup_9600_8e1();
        c.timer_b_1us();
        c.bank(1);
        c.wr(TMCR, 0x22); // start B, gate open
        b.line.inject(SerialLine::b, 0, FaultKind::flip_data_bit, 0);
        b.host.send("p");                   // rx FIFO + rx machine (parity error)
        b.uart.set_modem_inputs(true, false, false, false); // modem: DCTS
        c.bank(1);
        c.wr(TMCR, 0x00); // stop the timer, keep its expired flag
        c.bank(0);
        c.wr(GER, 0x3F);
        settle();
        EXPECT_TRUE(b.irq.read());
        EXPECT_EQ(c.rd(GIR), 0x0A); // timer
        c.bank(1);
        c.rd(TMST);
        EXPECT_EQ(c.rd(GIR), 0x28); // Tx machine idle (bank 1 in bits 6:5)
        c.bank(0);
        c.wr(GER, 0x3F & ~(1u << tx_machine));
        EXPECT_EQ(c.rd(GIR), 0x06); // Rx machine: parity error
        c.rd(LSR);
        EXPECT_EQ(c.rd(GIR), 0x04); // Rx FIFO
        c.rd(RXD);
        EXPECT_EQ(c.rd(GIR), 0x02); // Tx FIFO empty
        c.wr(GER, (1u << modem) | (1u << rx_fifo));
        EXPECT_EQ(c.rd(GIR), 0x00); // modem status
        c.rd(MSR);
        EXPECT_EQ(c.rd(GIR), 0x01); // none
        settle();
        EXPECT_FALSE(b.irq.read());
    });
}

TEST(Uart82510Interrupts, RieGatesRxMachineEvents) {
    UartOnLine b;
    run([&] {
        b.cpu.setup_9600_8e1();
        b.cpu.bank(2);
        b.cpu.wr(RIE, 0x10); // break detect only (as Intel's driver)
        b.cpu.bank(0);
        b.cpu.wr(GER, 1u << rx_machine);
        b.line.inject(SerialLine::b, 0, FaultKind::flip_data_bit, 2);
        b.host.send("e");
        settle();
        EXPECT_FALSE(b.irq.read());
        EXPECT_EQ(b.cpu.rd(GIR), 0x01);
        b.cpu.rd(RXD);
        b.line.insert_break(SerialLine::b, k_char * 2.0);
        sc_core::wait(k_char + ps(1));
        EXPECT_TRUE(b.irq.read());
        EXPECT_EQ(b.cpu.rd(GIR), 0x06);
    });
}

TEST(Uart82510Interrupts, IntFollowsSourcesInAutomaticMode) {
    UartOnLine b;
    std::vector<std::pair<sc_time, bool>> edges;
    test::spawn_forever(
        [&] {
            for (;;) {
                sc_core::wait(b.irq.value_changed_event());
                edges.emplace_back(sc_core::sc_time_stamp(), b.irq.read());
            }
        },
        "int_edges");
    run([&] {
        b.cpu.setup_9600_8e1();
        b.cpu.wr(GER, 1u << rx_fifo);
        b.host.send("r");
        sc_core::wait(us(20));
        b.cpu.rd(RXD);
    });
    ASSERT_EQ(edges.size(), 2u);
    EXPECT_EQ(edges[0], std::make_pair(k_char, true));
    EXPECT_EQ(edges[1], std::make_pair(k_char + us(20), false));
}

TEST(Uart82510Interrupts, ManualAcknowledgeModeNeedsIcmInta) {
    UartOnLine b;
    std::vector<std::pair<sc_time, bool>> edges;
    test::spawn_forever(
        [&] {
            for (;;) {
                sc_core::wait(b.irq.value_changed_event());
                edges.emplace_back(sc_core::sc_time_stamp(), b.irq.read());
            }
        },
        "int_edges");
    run([&] {
        b.cpu.setup_9600_8e1();
        b.cpu.bank(2);
        b.cpu.wr(IMD, IMD_IAM); // manual acknowledge, 4-byte FIFO
        b.cpu.bank(0);
        b.cpu.wr(GER, 1u << rx_fifo);
        b.host.send("mn");      // two characters
        sc_core::wait(us(10));
        b.cpu.rd(RXD);
        b.cpu.rd(RXD);          // sources gone, INT still latched
        sc_core::wait(us(10));
        EXPECT_TRUE(b.irq.read());
        b.cpu.bank(1);
        b.cpu.wr(ICM, ICM_INTA); // nothing pending: INT drops and stays low
        sc_core::wait(us(10));
        EXPECT_FALSE(b.irq.read());
        b.host.send("o");
        sc_core::wait(us(10));
        b.cpu.wr(ICM, ICM_INTA); // still pending: a fresh edge after the low time
    });
    const sc_time t2 = k_char * 2.0;
    ASSERT_EQ(edges.size(), 5u);
    EXPECT_EQ(edges[0], std::make_pair(k_char, true));
    EXPECT_EQ(edges[1], std::make_pair(t2 + us(20), false));
    EXPECT_EQ(edges[2].second, true);
    const sc_time t3 = edges[2].first;
    EXPECT_EQ(edges[3], std::make_pair(t3 + us(10), false));
    EXPECT_EQ(edges[4], std::make_pair(t3 + us(10) + ratio_time(2, 18'432'000), true));
}

TEST(Uart82510Interrupts, TimerInterruptPeriod) {
    UartOnLine b;
    std::vector<sc_time> ticks;
    run(
        [&] {
            Cpu& c = b.cpu;
            c.wr(LCR, LCR_DLAB);
            c.bank(3);
            c.wr(BBL, 9216 & 0xFF); // 9216 x 2 / 18.432 MHz = 1 ms
            c.wr(BBH, 9216 >> 8);
            c.wr(TMIE, 0x02);
            c.bank(0);
            c.wr(LCR, 0x03);
            c.wr(GER, 1u << timer);
            c.bank(1);
            c.wr(TMCR, 0x22); // STB + TGB
            for (int i = 0; i < 5; ++i) {
                sc_core::wait(b.irq.posedge_event());
                ticks.push_back(sc_core::sc_time_stamp());
                EXPECT_EQ(c.rd(GIR), 0x2A);
                EXPECT_EQ(c.rd(TMST), 0x22); // TBEx + gate B
                EXPECT_EQ(c.rd(TMST), 0x20); // read clears the expiry
            }
            // Close the gate 300 us into a period, reopen 1 ms later: 700 us remain.
            sc_core::wait(us(300));
            c.wr(TMCR, 0x00);
            sc_core::wait(us(1000));
            c.wr(TMCR, 0x20);
            sc_core::wait(b.irq.posedge_event());
            ticks.push_back(sc_core::sc_time_stamp());
            c.rd(TMST);
            c.wr(TMCR, 0x00);
        },
        sc_core::sc_time(20, sc_core::SC_MS));
    ASSERT_EQ(ticks.size(), 6u);
    for (int i = 0; i < 5; ++i) EXPECT_EQ(ticks[i], us(1000) * (i + 1.0)) << i;
    EXPECT_EQ(ticks[5], us(5000 + 300 + 1000 + 700));
}

TEST(Uart82510Interrupts, TimerModeOnlyWhenTheBrgIsNotABaudGenerator) {
    UartOnLine b;
    run(
        [&] {
            b.cpu.wr(LCR, LCR_DLAB);
            b.cpu.wr(BAL, 100);
            b.cpu.wr(LCR, 0);
            b.cpu.bank(3);
            b.cpu.wr(TMIE, 0x01);
            b.cpu.bank(1);
            b.cpu.wr(TMCR, 0x11); // BRGA is a baud generator (BACF.BAM = 1): no timer
            sc_core::wait(us(100));
            EXPECT_EQ(b.cpu.rd(TMST) & 0x01, 0);
            b.cpu.bank(3);
            b.cpu.wr(BACF, 0x00); // now a timer: 100 x 2 clocks = 10.85 us
            sc_core::wait(us(11));
            b.cpu.bank(1);
            EXPECT_EQ(b.cpu.rd(TMST) & 0x01, 0x01);
        },
        us(500));
}

// ---- modem status changes ----------------------------------------------------------------

TEST(Uart82510Interrupts, ModemDeltasAndMieGating) {
    UartOnLine b;
    run([&] {
        b.cpu.wr(GER, 1u << modem);
        b.cpu.bank(3);
        b.cpu.wr(MIE, 0x04); // TERI only
        b.cpu.bank(0);
        b.uart.set_modem_inputs(true, true, true, true);
        EXPECT_EQ(b.cpu.rd(GIR), 0x01); // DCTS, DDSR, DDCD set but masked; RI rising is no TERI
        EXPECT_EQ(b.cpu.rd(MSR), 0xFB);
        EXPECT_EQ(b.cpu.rd(MSR), 0xF0); // deltas cleared by the read
        b.uart.set_modem_inputs(true, true, false, true); // RI trailing edge
        EXPECT_EQ(b.cpu.rd(GIR), 0x00);
        settle();
        EXPECT_TRUE(b.irq.read());
        b.cpu.bank(1);
        b.cpu.wr(ICM, ICM_STC); // status clear takes the delta too
        EXPECT_EQ(b.cpu.rd(GIR), 0x21);
    });
}

// ---- stable reads --------------------------------------------------------------------------

// The declaration (Uart82510::read_is_stable, docs/architecture.md "Stable reads"): a read it
// declares stable changes nothing (every register of every bank, INT, the FIFO levels), so it
// may be made ahead of kernel time; each of the others, made with every source pending, clears
// or pops something (the data sheet's reads with an effect: RXD, LSR, MSR in bank 0; RXD, TMST,
// RST and MSR in bank 1), so made early it would move INT before its T1.
TEST(Uart82510StableReads, DeclaredReadsChangeNothingTheOthersClearSomething) {
    UartOnLine b;
    std::set<std::pair<unsigned, unsigned>> with_effect;
    run([&] {
        Cpu& c = b.cpu;
        const auto dump = [&] {
            settle();
            std::vector<unsigned> d;
            for (unsigned bank = 0; bank < 4; ++bank)
                for (unsigned off = 0; off < 8; ++off) d.push_back(b.uart.peek(bank, off));
            d.push_back(b.irq.read());
            d.push_back(b.uart.rx_level());
            d.push_back(b.uart.tx_level());
            return d;
        };
        c.setup_9600_8e1();
        c.timer_b_1us();
        c.bank(0);
        c.wr(GER, 0x3F);
        bool cts = false;
        std::uint64_t sent = 0;
        // Every source pending: a character with a parity error in the RX FIFO, a modem delta,
        // timer B expired (and stopped).
        const auto raise_all = [&] {
            b.line.inject(SerialLine::b, sent++, FaultKind::flip_data_bit, 0);
            b.host.send("p");
            cts = !cts;
            b.uart.set_modem_inputs(cts, false, false, false);
            c.bank(1);
            c.wr(TMCR, 0x22);
            sc_core::wait(k_char + us(2));
            c.wr(TMCR, 0x00);
        };
        raise_all();
        unsigned stable = 0;
        for (unsigned bank = 0; bank < 4; ++bank)
            for (unsigned off = 0; off < 8; ++off) {
                c.bank(bank);
                if (!b.uart.read_is_stable(off * 2, 1)) continue;
                const std::vector<unsigned> before = dump();
                c.rd(off);
                EXPECT_EQ(dump(), before) << "bank " << bank << " offset " << off << " is declared stable";
                ++stable;
            }
        EXPECT_EQ(stable, 32u - 7u);
        for (unsigned bank = 0; bank < 2; ++bank)
            for (unsigned off = 0; off < 8; ++off) {
                c.bank(bank);
                if (b.uart.read_is_stable(off * 2, 1)) continue;
                raise_all();
                c.bank(bank);
                const std::vector<unsigned> before = dump();
                c.rd(off);
                EXPECT_NE(dump(), before) << "bank " << bank << " offset " << off << " is not declared stable";
                with_effect.insert({bank, off});
            }
        // With DLAB, offset 0 of bank 0 is BAL: no FIFO pop, stable.
        c.bank(0);
        c.wr(LCR, LCR_DLAB | 0x1B);
        EXPECT_TRUE(b.uart.read_is_stable(RXD * 2, 1));
        c.wr(LCR, 0x1B);
        // Only byte reads of a register's lane.
        EXPECT_FALSE(b.uart.read_is_stable(GIR * 2 + 1, 1));
        EXPECT_FALSE(b.uart.read_is_stable(GIR * 2, 2));
        EXPECT_FALSE(b.uart.read_is_stable(16, 1));
    }, sc_time(50, sc_core::SC_MS));
    const std::set<std::pair<unsigned, unsigned>> datasheet{{0, RXD}, {0, LSR}, {0, MSR}, {1, RXD},
                                                           {1, TMST}, {1, RST}, {1, MSR}};
    EXPECT_EQ(with_effect, datasheet);
}
