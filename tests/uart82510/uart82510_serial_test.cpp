// Tests of the Intel 82510 model on the serial side: character timing, formats, FIFOs and their
// thresholds, receive errors, BREAK (sent and received), flushes, loopback, and two 82510s
// talking over a line. The registers and interrupts are uart82510_test.cpp; the set-up both use
// is uart_on_line.h.
#include "tests/uart82510/uart_on_line.h"

#include <string>
#include <vector>

using namespace rcsim;
using namespace rcsim::i82510;
using namespace rcsim::test::uart;
using sc_core::sc_time;

// ---- transmit, receive, timing -----------------------------------------------------------

TEST(Uart82510Serial, CharacterTimeIsExactToTheNanosecond) {
    UartOnLine b;
    sc_time written;
    run([&] {
        b.cpu.setup_9600_8e1();
        sc_core::wait(us(10));
        written = sc_core::sc_time_stamp();
        b.cpu.wr(TXD, 'U');
        EXPECT_EQ(b.cpu.rd(LSR) & LSR_TXST, 0); // shifting
        sc_core::wait(k_char - ps(1));
        EXPECT_EQ(b.cpu.rd(LSR) & LSR_TXST, 0);
        sc_core::wait(ps(1));
        EXPECT_EQ(b.cpu.rd(LSR) & LSR_TXST, LSR_TXST); // the stop bit has left
    });
    ASSERT_EQ(b.host.got.size(), 1u);
    EXPECT_EQ(b.host.got[0].data, 'U');
    EXPECT_FALSE(b.host.got[0].parity_error);
    EXPECT_EQ(b.host.got[0].stop - written, k_char);
    EXPECT_EQ((b.host.got[0].stop - written).value() / 1000, 1'145'833u);
    EXPECT_EQ(b.uart.stats().chars_sent, 1u);
}

TEST(Uart82510Serial, ClockFrequencyIsAProperty) {
    Uart82510::Config cfg;
    cfg.clock_hz = 3'686'400; // PC-card style: divisor 12 for 9600
    UartOnLine b(cfg);
    run([&] {
        b.cpu.wr(LCR, LCR_DLAB);
        b.cpu.wr(BAL, 12);
        b.cpu.wr(LCR, 0x1B);
        b.cpu.wr(TXD, 'x');
    });
    ASSERT_EQ(b.host.got.size(), 1u);
    EXPECT_EQ(b.host.got[0].stop, k_char);
    EXPECT_EQ(b.host.got[0].data, 'x');
}

TEST(Uart82510Serial, FormatFollowsLcrAndTmd) {
    UartOnLine b;
    run([&] {
        b.cpu.setup_9600_8e1();
        EXPECT_EQ(b.uart.tx_format().describe(), "9600,8E1");
        b.cpu.wr(LCR, 0x0A); // 7 bits, odd
        EXPECT_EQ(b.uart.tx_format().describe(), "9600,7O1");
        b.cpu.wr(LCR, 0x2F); // 8 bits, mark, 2 stop
        EXPECT_EQ(b.uart.tx_format().describe(), "9600,8M2");
        b.cpu.wr(LCR, 0x3C); // 5 bits, space, SBL0 with 5 bits = 1.5
        EXPECT_EQ(b.uart.tx_format().describe(), "9600,5S1.5");
        b.cpu.bank(2);
        b.cpu.wr(TMD, TMD_NBCL | 0x03); // 9-bit characters with CL = 00; SBL = 2 stop
        EXPECT_EQ(b.uart.tx_format().describe(), "9600,9S2");
        b.cpu.bank(3);
        b.cpu.wr(CLCF, CLCF_RXBRGA | CLCF_TXBRGA | CLCF_TX1X); // TX at the BRG output rate
        EXPECT_EQ(b.uart.tx_format().describe(), "153600,9S2");
        EXPECT_EQ(b.uart.rx_format().describe(), "9600,9S2");
    });
}

// The verdict's budget comes from a port only once the firmware chose its format: the LCR and a
// divisor (DLAB set) written since RESET; a RESET (pin or ICM software reset) forgets both.
TEST(Uart82510Serial, FormatIsProgrammedOnceLcrAndADivisorAreWritten) {
    UartOnLine b;
    run([&] {
        EXPECT_FALSE(b.uart.format_programmed());
        b.cpu.wr(LCR, LCR_DLAB);
        EXPECT_FALSE(b.uart.format_programmed()); // the LCR written, no divisor yet
        b.cpu.wr(BAL, 60);
        EXPECT_TRUE(b.uart.format_programmed());
        b.uart.reset();
        EXPECT_FALSE(b.uart.format_programmed());
        b.cpu.wr(TXD, 'x'); // DLAB clear after RESET: a character, not a divisor
        b.cpu.wr(LCR, 0x1B);
        EXPECT_FALSE(b.uart.format_programmed());
        b.cpu.setup_9600_8e1();
        EXPECT_TRUE(b.uart.format_programmed());
    });
}

TEST(Uart82510Serial, ReceivesIntoTheFifoWithLevels) {
    UartOnLine b;
    run([&] {
        b.cpu.setup_9600_8e1();
        b.cpu.bank(2);
        b.cpu.wr(IMD, 0x00); // 4-byte RX FIFO
        b.cpu.bank(1);
        b.host.send("abcd");
        sc_core::wait(us(1));
        EXPECT_EQ(b.cpu.rd(FLR), 0x40);
        EXPECT_EQ(b.cpu.rd(RXF), RXF_ROK | RXF_RPB); // 'a' has three ones: even parity bit 1
        std::string s;
        for (unsigned n = 4; n > 0; --n) {
            EXPECT_EQ(b.cpu.rd(FLR) >> 4, n);
            s += static_cast<char>(b.cpu.rd(RXD));
        }
        EXPECT_EQ(s, "abcd");
        EXPECT_EQ(b.cpu.rd(FLR), 0x00);
        EXPECT_EQ(b.cpu.rd(RXD), 'd'); // an empty FIFO repeats the last character
    });
    EXPECT_EQ(b.uart.stats().chars_received, 4u);
    EXPECT_EQ(b.uart.stats().rx_fifo_high_water, 4u);
}

TEST(Uart82510Serial, PeekOfAnyBankHasNoSideEffect) {
    // The debugger's register dump (peek(bank, offset)): bank 0's LCR and RXD read from bank 1
    // without switching banks, and RXD without taking the character out of the FIFO.
    UartOnLine b;
    run([&] {
        b.cpu.setup_9600_8e1();
        b.cpu.bank(2);
        b.cpu.wr(IMD, 0x00); // 4-byte RX FIFO
        b.cpu.bank(1);
        b.host.send("ab");
        sc_core::wait(k_char * 3.0);
        EXPECT_EQ(b.uart.peek(0, LCR), 0x1B);
        EXPECT_EQ(b.uart.peek(0, RXD), 'a');
        EXPECT_EQ(b.uart.peek(1, FLR) >> 4, 2); // RX FIFO level
        EXPECT_EQ(b.uart.bank(), 1u);
        EXPECT_EQ(b.uart.rx_level(), 2u);
        EXPECT_EQ(b.cpu.rd(RXD), 'a'); // the FIFO still starts with 'a'
        EXPECT_EQ(b.uart.rx_level(), 1u);
    });
}

TEST(Uart82510Serial, TxFifoFillsWhileTheShifterWorks) {
    UartOnLine b;
    run([&] {
        b.cpu.setup_9600_8e1();
        b.cpu.bank(1);
        for (char ch : std::string("123456")) b.cpu.wr(TXD, static_cast<std::uint8_t>(ch));
        EXPECT_EQ(b.cpu.rd(FLR) & 0x07, 4); // one shifting, four queued, the sixth lost
        EXPECT_EQ(b.cpu.rd(GSR) & (1u << tx_fifo), 0);
        sc_core::wait(k_char);
        EXPECT_EQ(b.cpu.rd(FLR) & 0x07, 3);
    });
    EXPECT_EQ(b.host.text(), "12345");
    EXPECT_EQ(b.uart.stats().tx_overflows, 1u);
    ASSERT_EQ(b.host.got.size(), 5u);
    EXPECT_EQ(b.host.got[4].stop, k_char * 5.0); // back to back
}

TEST(Uart82510Serial, FifoThresholds) {
    UartOnLine b;
    run([&] {
        b.cpu.setup_9600_8e1();
        b.cpu.bank(2);
        b.cpu.wr(IMD, 0x00);
        b.cpu.wr(FMD, 0x22); // RFT = 2: request at 3 characters; TFT = 2: request at <= 2 queued
        b.cpu.bank(1);
        b.host.send("xy");
        sc_core::wait(us(1));
        EXPECT_EQ(b.cpu.rd(GSR) & (1u << rx_fifo), 0);
        b.host.send("z");
        sc_core::wait(us(1));
        EXPECT_NE(b.cpu.rd(GSR) & (1u << rx_fifo), 0);
        b.cpu.rd(RXD);
        EXPECT_EQ(b.cpu.rd(GSR) & (1u << rx_fifo), 0);
        // TX: one character shifting + 3 queued: above TFT; after one more leaves, 2: request.
        for (int i = 0; i < 4; ++i) b.cpu.wr(TXD, 'q');
        EXPECT_EQ(b.cpu.rd(GSR) & (1u << tx_fifo), 0);
        sc_core::wait(k_char);
        EXPECT_NE(b.cpu.rd(GSR) & (1u << tx_fifo), 0);
    });
}

TEST(Uart82510Serial, OverrunOnTheFifthCharacter) {
    UartOnLine b;
    run([&] {
        b.cpu.setup_9600_8e1();
        b.cpu.bank(2);
        b.cpu.wr(IMD, 0x00);
        b.cpu.bank(0);
        b.host.send("1234");
        sc_core::wait(us(1));
        EXPECT_EQ(b.cpu.rd(LSR) & RST_OE, 0);
        b.host.send("5");
        sc_core::wait(us(1));
        EXPECT_EQ(b.cpu.rd(LSR) & RST_OE, RST_OE);
        EXPECT_EQ(b.cpu.rd(LSR) & RST_OE, 0); // cleared by the read
        std::string s;
        while (b.cpu.rd(LSR) & LSR_DR) s += static_cast<char>(b.cpu.rd(RXD));
        EXPECT_EQ(s, "1234"); // the fifth is lost
    });
    EXPECT_EQ(b.uart.stats().overruns, 1u);
}

TEST(Uart82510Serial, OneByteFifoAfterResetOverrunsOnTheSecond) {
    UartOnLine b;
    run([&] {
        b.cpu.setup_9600_8e1();
        b.host.send("12");
        EXPECT_EQ(b.cpu.rd(LSR) & (RST_OE | LSR_DR), RST_OE | LSR_DR);
        EXPECT_EQ(b.cpu.rd(RXD), '1');
    });
}

TEST(Uart82510Serial, ParityFramingAndBreakDetection) {
    UartOnLine b;
    run([&] {
        b.cpu.setup_9600_8e1();
        b.cpu.bank(2);
        b.cpu.wr(IMD, 0x00);
        b.cpu.bank(1);
        b.line.inject(SerialLine::b, 0, FaultKind::flip_data_bit, 0);
        b.host.send("A");
        sc_core::wait(us(1));
        EXPECT_EQ(b.cpu.rd(RXF), RXF_RPE);
        EXPECT_EQ(b.cpu.rd(RST), RST_RFIR | RST_PE);
        EXPECT_EQ(b.cpu.rd(RST), RST_RFIR); // latched bits cleared by the read
        EXPECT_EQ(b.cpu.rd(RXD), 'A' ^ 1);
        b.line.inject(SerialLine::b, 1, FaultKind::corrupt_stop);
        b.host.send("B");
        sc_core::wait(us(1));
        EXPECT_EQ(b.cpu.rd(RXF), RXF_RFE);
        EXPECT_EQ(b.cpu.rd(RST) & RST_FE, RST_FE);
        b.cpu.rd(RXD);
        // BREAK for 5 character times: detect after one frame, terminate at release.
        b.line.insert_break(SerialLine::b, k_char * 5.0);
        sc_core::wait(k_char + us(1));
        EXPECT_EQ(b.cpu.rd(RST) & (RST_BKD | RST_BKT), RST_BKD);
        EXPECT_EQ(b.cpu.rd(RXF), RXF_BKF | RXF_RFE);
        EXPECT_EQ(b.cpu.rd(RXD), 0x00);
        sc_core::wait(k_char * 4.0);
        EXPECT_EQ(b.cpu.rd(RST) & RST_BKT, RST_BKT);
    });
    EXPECT_EQ(b.uart.stats().parity_errors, 1u);
    EXPECT_EQ(b.uart.stats().framing_errors, 1u);
    EXPECT_EQ(b.uart.stats().break_detects, 1u);
}

TEST(Uart82510Serial, SetBreakHoldsTheLine) {
    UartOnLine b;
    run([&] {
        b.cpu.setup_9600_8e1();
        b.cpu.wr(LCR, 0x1B | LCR_SBK);
        b.cpu.wr(TXD, 'z'); // held while the break is on
        sc_core::wait(k_char * 3.0);
        b.cpu.wr(LCR, 0x1B);
    });
    ASSERT_EQ(b.host.breaks.size(), 2u);
    EXPECT_EQ(b.host.breaks[0], std::make_pair(k_char, true));
    EXPECT_EQ(b.host.breaks[1], std::make_pair(k_char * 3.0, false));
    ASSERT_EQ(b.host.got.size(), 1u);
    EXPECT_EQ(b.host.got[0].data, 'z');
    EXPECT_EQ(b.host.got[0].stop, k_char * 4.0);
}

TEST(Uart82510Serial, FlushAndDisableCommands) {
    UartOnLine b;
    run([&] {
        b.cpu.setup_9600_8e1();
        b.cpu.bank(2);
        b.cpu.wr(IMD, 0x00);
        b.cpu.bank(1);
        b.host.send("ab");
        b.cpu.wr(RCM, RCM_FRF);
        EXPECT_EQ(b.cpu.rd(FLR), 0x00);
        b.cpu.wr(RCM, RCM_RXDI);
        b.host.send("c");
        EXPECT_EQ(b.cpu.rd(FLR), 0x00);
        b.cpu.wr(RCM, RCM_RXE);
        b.host.send("d");
        EXPECT_EQ(b.cpu.rd(FLR), 0x10);
        // TX: disable holds the FIFO, flush empties it.
        b.cpu.wr(TCM, TCM_TXDI);
        b.cpu.wr(TXD, '1');
        b.cpu.wr(TXD, '2');
        EXPECT_EQ(b.cpu.rd(FLR) & 7, 2);
        b.cpu.wr(TCM, TCM_FTF);
        EXPECT_EQ(b.cpu.rd(FLR) & 7, 0);
        b.cpu.wr(TCM, TCM_TXEN);
        b.cpu.wr(TXD, '3');
    });
    EXPECT_EQ(b.host.text(), "3");
    EXPECT_EQ(b.uart.stats().rx_disabled_drops, 1u);
}

TEST(Uart82510Serial, LocalLoopback) {
    UartOnLine b;
    run([&] {
        b.cpu.setup_9600_8e1();
        b.cpu.wr(MCR, MCR_LOOP | 0x01); // loop, DTR -> DSR
        EXPECT_EQ(b.cpu.rd(MSR), 0x22); // DSR with its delta
        b.cpu.wr(TXD, 'L');
        sc_core::wait(k_char);
        EXPECT_EQ(b.cpu.rd(LSR) & LSR_DR, LSR_DR);
        EXPECT_EQ(b.cpu.rd(RXD), 'L');
    });
    EXPECT_TRUE(b.host.got.empty()); // nothing on the wire
}

TEST(Uart82510Serial, ProbeReportsStopAndReadTimes) {
    UartOnLine b;
    std::vector<Uart82510::CharTiming> seen;
    b.uart.on_char_read = [&](const Uart82510::CharTiming& t) { seen.push_back(t); };
    run([&] {
        b.cpu.setup_9600_8e1();
        b.host.send("k");
        sc_core::wait(us(37));
        b.cpu.rd(RXD);
    });
    ASSERT_EQ(seen.size(), 1u);
    EXPECT_EQ(seen[0].data, 'k');
    EXPECT_EQ(seen[0].stop, k_char);
    EXPECT_EQ(seen[0].read - seen[0].stop, us(37));
}

// ---- two 82510s --------------------------------------------------------------------------

namespace {
/// Interrupt-driven driver for one 82510: sends `out`, collects what arrives.
struct Driver {
    Cpu& cpu;
    IrqLine& irq;
    std::string out, in;
    std::size_t next = 0;
    void start() {
        // The driver's interrupt loop, like the firmware's, never returns.
        const std::string name = std::string(cpu.basename()) + "_driver";
        test::spawn_forever([this] {
            cpu.setup_9600_8e1();
            cpu.bank(2);
            cpu.wr(IMD, 0x00);
            cpu.bank(0);
            cpu.wr(GER, (1u << rx_fifo) | (1u << tx_fifo));
            for (;;) {
                if (!irq.read()) sc_core::wait(irq.posedge_event());
                for (std::uint8_t g = cpu.rd(GIR); !(g & 1); g = cpu.rd(GIR)) { // until none pending
                    if ((g & 0x0E) == 0x04) {
                        while (cpu.rd(LSR) & LSR_DR) in += static_cast<char>(cpu.rd(RXD));
                    } else if ((g & 0x0E) == 0x02) {
                        for (int i = 0; i < 4 && next < out.size(); ++i)
                            cpu.wr(TXD, static_cast<std::uint8_t>(out[next++]));
                        if (next == out.size()) cpu.wr(GER, 1u << rx_fifo);
                    }
                }
                sc_core::wait(us(5)); // the ISR's own time; INT has settled by then
            }
        }, name.c_str());
    }
};

struct Pair {
    SerialLine line{"line"};
    Uart82510 u0{"u0"}, u1{"u1"};
    Cpu c0{"c0"}, c1{"c1"};
    IrqLine i0{"i0"}, i1{"i1"};
    Pair() {
        c0.sock.bind(u0.bus);
        c1.sock.bind(u1.bus);
        u0.int_out.bind(i0);
        u1.int_out.bind(i1);
        u0.connect(line, SerialLine::a);
        u1.connect(line, SerialLine::b);
    }
};
} // namespace

TEST(Uart82510Pair, TwoUartsLoopedOverALine) {
    Pair p;
    Driver d0{p.c0, p.i0, "The quick brown fox", {}};
    Driver d1{p.c1, p.i1, "jumps over the lazy dog!", {}};
    d0.start();
    d1.start();
    sc_core::sc_start(sc_core::sc_time(100, sc_core::SC_MS));
    EXPECT_EQ(d1.in, d0.out);
    EXPECT_EQ(d0.in, d1.out);
    EXPECT_EQ(p.u0.stats().chars_sent, d0.out.size());
    EXPECT_EQ(p.u1.stats().chars_received, d0.out.size());
    EXPECT_EQ(p.u0.stats().overruns + p.u1.stats().overruns, 0u);
    EXPECT_EQ(p.u0.stats().parity_errors + p.u1.stats().parity_errors, 0u);
}

TEST(Uart82510Pair, MismatchedBaudGivesWrongDataAndErrors) {
    Pair p;
    Driver d0{p.c0, p.i0, std::string("U") + std::string(1, '\0'), {}};
    d0.start();
    test::spawn_checked([&] {
        p.c1.setup_9600_8e1();
        p.c1.wr(LCR, 0x9B);
        p.c1.wr(BAL, 30); // 19200: twice too fast
        p.c1.wr(LCR, 0x1B);
        p.c1.bank(2);
        p.c1.wr(IMD, 0x00);
        p.c1.bank(0);
    }, "c1_setup");
    sc_core::sc_start(sc_core::sc_time(20, sc_core::SC_MS));
    // 'U' (0x55) sampled twice per bit reads 0x66 with correct parity and stop: silent garbage.
    // 0x00 puts the 19200 receiver's stop sample on a SPACE data bit: a framing error.
    EXPECT_EQ(p.u1.stats().chars_received, 2u);
    EXPECT_EQ(p.u1.stats().parity_errors, 0u);
    EXPECT_EQ(p.u1.stats().framing_errors, 1u);
    EXPECT_EQ(p.u1.peek(RXD), 0x66);
}

// ---- less common paths -------------------------------------------------------------------

TEST(Uart82510Serial, FlushRxMachineDropsTheCharacterInProgress) {
    UartOnLine b;
    run([&] {
        b.cpu.setup_9600_8e1();
        b.cpu.bank(1);
        test::spawn_checked([&] { b.host.send("ab"); }, "host_send");
        sc_core::wait(k_char / 2.0); // 'a' half received
        b.cpu.wr(RCM, RCM_FRM);
        sc_core::wait(k_char * 3.0);
        EXPECT_EQ(b.cpu.rd(FLR) >> 4, 1); // only 'b'
        EXPECT_EQ(b.cpu.rd(RXD), 'b');
    });
}

TEST(Uart82510Serial, NineBitCharactersAndSoftwareParity) {
    UartOnLine b;
    b.host.fmt.data_bits = 9;
    b.host.fmt.parity = Parity::none;
    run([&] {
        b.cpu.wr(LCR, LCR_DLAB);
        b.cpu.wr(BAL, 60);
        b.cpu.wr(LCR, 0x00); // CL = 00 with NBCL: 9 bits, no parity
        b.cpu.bank(2);
        b.cpu.wr(TMD, TMD_NBCL);
        b.cpu.bank(1);
        b.cpu.wr(TXF, 0x20); // D8 = 1
        b.cpu.wr(TXD, 0x41);
        sc_core::wait(k_char * 2.0);
        // And a 9-bit character in: RXF.RND holds bit 8.
        b.host.line.transmit(SerialLine::b, SerialWord::encode(0x155, b.host.fmt));
        sc_core::wait(k_char * 2.0);
        EXPECT_EQ(b.cpu.rd(RXF) & RXF_RND, RXF_RND);
        EXPECT_EQ(b.cpu.rd(RXD), 0x55);
        // Software parity: 8 data + parity cell from TXF.SP regardless of the data.
        b.cpu.bank(0);
        b.cpu.wr(LCR, 0x1B); // 8E1
        b.cpu.bank(2);
        b.cpu.wr(TMD, TMD_SPF);
        b.cpu.bank(1);
        b.cpu.wr(TXF, 0x40); // SP = 1
        b.host.fmt = SerialFormat::rs232(9600);
        b.cpu.wr(TXD, 0x03); // even parity would be 0
    });
    ASSERT_EQ(b.host.got.size(), 2u);
    EXPECT_EQ(b.host.got[0].data, 0x141);
    EXPECT_EQ(b.host.got[1].data & 0xFF, 0x03);
    EXPECT_TRUE(b.host.got[1].parity);       // the forced parity bit
    EXPECT_TRUE(b.host.got[1].parity_error); // as an even-parity receiver sees it
}

TEST(Uart82510Serial, FlushTxMachineFreesTheShifter) {
    UartOnLine b;
    run([&] {
        b.cpu.setup_9600_8e1();
        b.cpu.bank(1);
        b.cpu.wr(TXD, '1');
        b.cpu.wr(TXD, '2');
        EXPECT_EQ(b.cpu.rd(FLR) & 7, 1);
        b.cpu.wr(TCM, TCM_FTM); // '1' already on the wire; '2' starts now
        EXPECT_EQ(b.cpu.rd(FLR) & 7, 0);
    });
    ASSERT_EQ(b.host.got.size(), 2u);
    EXPECT_EQ(b.host.got[0].data, '1');
    EXPECT_EQ(b.host.got[1].data, '2');
    EXPECT_EQ(b.host.got[1].start, sc_core::SC_ZERO_TIME);
}

// ---- the 82510 receiving while the host holds a BREAK ---------------------------------------
// The host sends 9600 8E1 (bit = 1/9600 s, the 82510's 18.432 MHz / 1920 exactly). The 82510
// samples cell k at (k + 1/2) bits after the START edge: START 0.5, data bit n at n + 1.5, parity
// 9.5, STOP 10.5 bits; a sample taken while the BREAK holds the line reads SPACE. Datasheet
// facts (uart82510/README.md): STOP read as SPACE is a framing error (RXF.RFE, RST.FE); the line
// at SPACE for one frame is a break detect (RST.BKD, one 0x00 with RXF.BKF | RXF.RFE); its end
// is RST.BKT.

namespace {
const BitTime k_bit = BitTime::baud(9600);

/// A UartOnLine with a 4-character RX FIFO and the host's characters and BREAKs at given times.
struct UartUnderBreak : UartOnLine {
    struct Entry {
        std::uint8_t rxf, data;
    };
    std::vector<Entry> fifo;
    std::uint8_t rst = 0; // RST latched before the FIFO was drained

    void program() {
        cpu.setup_9600_8e1();
        cpu.bank(2);
        cpu.wr(IMD, 0x00);
        cpu.bank(1);
    }
    void host_sends_at(const sc_time& t, std::uint8_t byte) {
        test::spawn_checked([this, t, byte] {
            sc_core::wait(t - sc_core::sc_time_stamp());
            line.transmit(SerialLine::b, SerialWord::encode(byte, host.fmt));
        });
    }
    void host_breaks_at(const sc_time& t, const sc_time& duration) {
        test::spawn_checked([this, t, duration] {
            sc_core::wait(t - sc_core::sc_time_stamp());
            line.insert_break(SerialLine::b, duration);
        });
    }
    /// At `t`: reads RST once, then every FIFO entry (RXF, then RXD pops it).
    void drain_at(const sc_time& t) {
        sc_core::wait(t - sc_core::sc_time_stamp());
        rst = cpu.rd(RST);
        for (unsigned level = (cpu.rd(FLR) >> 4) & 7; level; --level) {
            const std::uint8_t f = cpu.rd(RXF);
            fifo.push_back({f, cpu.rd(RXD)});
        }
    }
};
} // namespace

TEST(Uart82510Break, BreakEndingBeforeTheStartBitLeavesTheCharacterIntact) {
    // BREAK [0, 2 frames): detected at one frame, ended at two. 'A' sent 1 bit after the end.
    UartUnderBreak b;
    run([&] {
        b.program();
        b.host_breaks_at(sc_core::SC_ZERO_TIME, k_char * 2.0);
        b.host_sends_at(k_char * 2.0 + k_bit.span(2), 'A');
        b.drain_at(k_char * 3.0 + k_bit.span(2) + us(1));
    });
    EXPECT_EQ(b.rst & (RST_BKD | RST_BKT | RST_FE | RST_PE), RST_BKD | RST_BKT);
    ASSERT_EQ(b.fifo.size(), 2u);
    EXPECT_EQ(b.fifo[0].rxf, RXF_BKF | RXF_RFE);
    EXPECT_EQ(b.fifo[0].data, 0x00);
    EXPECT_EQ(b.fifo[1].rxf, RXF_ROK);
    EXPECT_EQ(b.fifo[1].data, 'A');
}

TEST(Uart82510Break, BreakStartingMidCharacterIsAFramingError) {
    // 0xFF, BREAK from 4 bits (the start of data bit 3's cell) for 5 frames. Samples from 4.5
    // bits on read SPACE: data bits 3..7, parity, STOP. RXD = 0x07; even parity of three ones
    // is 1, read 0: RXF.RPE; STOP 0: RXF.RFE. Then the break detect one frame after the fall.
    UartUnderBreak b;
    const sc_time fall = k_bit.span(8);
    run([&] {
        b.program();
        b.host_sends_at(sc_core::SC_ZERO_TIME, 0xFF);
        b.host_breaks_at(fall, k_char * 5.0);
        b.drain_at(fall + k_char + us(1));
    });
    EXPECT_EQ(b.rst & (RST_BKD | RST_FE | RST_PE), RST_BKD | RST_FE | RST_PE);
    ASSERT_EQ(b.fifo.size(), 2u);
    EXPECT_EQ(b.fifo[0].rxf, RXF_RFE | RXF_RPE);
    EXPECT_EQ(b.fifo[0].data, 0x07);
    EXPECT_EQ(b.fifo[1].rxf, RXF_BKF | RXF_RFE);
    EXPECT_EQ(b.fifo[1].data, 0x00);
    EXPECT_EQ(b.uart.stats().framing_errors, 1u);
    EXPECT_EQ(b.uart.stats().parity_errors, 1u);
}

TEST(Uart82510Break, BreakStartingAfterTheStopSampleLeavesTheCharacterIntact) {
    // 0xFF, BREAK falling 1 ps after the STOP sample (10.5 bits): the character is intact, the
    // fall is a new START edge, detected as a break one frame later.
    UartUnderBreak b;
    const sc_time fall = k_bit.span(21) + ps(1);
    run([&] {
        b.program();
        b.host_sends_at(sc_core::SC_ZERO_TIME, 0xFF);
        b.host_breaks_at(fall, k_char * 5.0);
        b.drain_at(fall + k_char + us(1));
    });
    EXPECT_EQ(b.rst & (RST_BKD | RST_FE | RST_PE), RST_BKD);
    ASSERT_EQ(b.fifo.size(), 2u);
    EXPECT_EQ(b.fifo[0].rxf, RXF_ROK);
    EXPECT_EQ(b.fifo[0].data, 0xFF);
    EXPECT_EQ(b.fifo[1].rxf, RXF_BKF | RXF_RFE);
    EXPECT_EQ(b.fifo[1].data, 0x00);
}

TEST(Uart82510Break, BreakCoveringACharacterIsOneBreakCharacter) {
    // BREAK [0, 5 frames); 'Z' sent at 1 frame + 1 bit, inside it: its START is no edge. The FIFO
    // gets the one 0x00 with RXF.BKF | RXF.RFE of the break detect, and nothing of the 'Z'.
    UartUnderBreak b;
    run([&] {
        b.program();
        b.host_breaks_at(sc_core::SC_ZERO_TIME, k_char * 5.0);
        b.host_sends_at(k_char + k_bit.span(2), 'Z');
        b.drain_at(k_char * 6.0);
    });
    EXPECT_EQ(b.rst & (RST_BKD | RST_BKT | RST_FE | RST_PE), RST_BKD | RST_BKT);
    ASSERT_EQ(b.fifo.size(), 1u);
    EXPECT_EQ(b.fifo[0].rxf, RXF_BKF | RXF_RFE);
    EXPECT_EQ(b.fifo[0].data, 0x00);
    EXPECT_EQ(b.uart.stats().chars_received, 1u);
    EXPECT_EQ(b.line.stats(SerialLine::b).swallowed, 1u);
}

TEST(Uart82510Break, SetBreakMidCharacterCutsTheCharacterOnTheWire) {
    // LCR.SBK puts TXD at SPACE at once (README: "line to SPACE at once"), even with a character
    // in the shifter. 0xFF written at 0, SBK set at 4 bits: the host samples data bits 3..7,
    // parity and STOP as SPACE: 0x07 with parity and framing errors at one frame, the break one
    // frame after the fall, its end when SBK is cleared.
    UartOnLine b;
    const sc_time fall = k_bit.span(8);
    run([&] {
        b.cpu.setup_9600_8e1();
        b.cpu.wr(TXD, 0xFF);
        sc_core::wait(fall);
        b.cpu.wr(LCR, 0x1B | LCR_SBK);
        sc_core::wait(k_char * 3.0);
        b.cpu.wr(LCR, 0x1B);
    });
    ASSERT_EQ(b.host.got.size(), 1u);
    EXPECT_EQ(b.host.got[0].data, 0x07);
    EXPECT_TRUE(b.host.got[0].parity_error);
    EXPECT_TRUE(b.host.got[0].framing_error);
    EXPECT_EQ(b.host.got[0].stop, k_char);
    ASSERT_EQ(b.host.breaks.size(), 2u);
    EXPECT_EQ(b.host.breaks[0], std::make_pair(fall + k_char, true));
    EXPECT_EQ(b.host.breaks[1], std::make_pair(fall + k_char * 3.0, false));
}
