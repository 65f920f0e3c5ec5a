// A host receiving from an 82510 while the controller's side of the line is held at SPACE by a
// BREAK (fault injection on side a, or LCR.SBK): the host-side receiver gets what a real one
// would, at each overlap of the BREAK with a character, and the protocol host sees the loss.
//
// 9600 8E1 on both ends (the 82510 at 18.432 MHz / 1920 = 1/9600 s a bit). The receiver samples
// cell k (k + 1/2) bits after the START edge: START 0.5, data bit n at n + 1.5, parity 9.5,
// STOP 10.5 bits, and has the character at 11 bits (one frame). A sample taken while the BREAK is
// held reads SPACE; a START sent while it is held is no edge (docs/serial.md, BREAK).
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include "scenarios/host/protocol_host.h"
#include "scenarios/host/raw_host.h"
#include "uart82510/uart82510.h"

#include "models/clock.h"
#include "tests/support/sc_test.h"
#include "tests/support/files.h"

#include <tlm_utils/simple_initiator_socket.h>

#include <fstream>
#include <functional>
#include <string>

using namespace rcsim;
using namespace rcsim::i82510;
using sc_core::sc_time;

namespace {
const BitTime k_bit = BitTime::baud(9600);
const sc_time k_char = k_bit.span(22);

/// The 82510's bus socket must be bound; the tests drive registers through read()/write().
struct Unused : sc_core::sc_module {
    tlm_utils::simple_initiator_socket<Unused> sock{"sock"};
    explicit Unused(sc_core::sc_module_name n) : sc_module(n) {}
};

/// An 82510 at 9600 8E1 on side a of a line, a raw host on side b.
struct UartAndRawHost {
    SerialLine line{"line"};
    Uart82510 uart{"uart"};
    Unused cpu{"cpu"};
    IrqLine irq{"irq"};
    RawHost host;
    explicit UartAndRawHost(const RawHostConfig& cfg = {}) : host("host", cfg) {
        cpu.sock.bind(uart.bus);
        uart.int_out.bind(irq);
        uart.connect(line, SerialLine::a);
        host.connect(line, SerialLine::b);
        uart.write(LCR, LCR_DLAB);
        uart.write(BAL, 60);
        uart.write(LCR, 0x1B);
    }
    /// Runs `f` at simulated time `t`.
    static void at(const sc_time& t, std::function<void()> f) {
        test::spawn_checked([t, f] {
            sc_core::wait(t);
            f();
        });
    }
};
} // namespace

TEST(HostBreakOverlap, BreakEndingBeforeTheStartBitLeavesTheCharacterIntact) {
    // BREAK [0, 2 frames) from the controller's side; 'A' written 1 bit after its end.
    UartAndRawHost b;
    UartAndRawHost::at(sc_core::SC_ZERO_TIME, [&] { b.line.insert_break(SerialLine::a, k_char * 2.0); });
    UartAndRawHost::at(k_char * 2.0 + k_bit.span(2), [&] { b.uart.write(TXD, 'A'); });
    sc_core::sc_start();
    ASSERT_EQ(b.host.breaks().size(), 2u);
    EXPECT_EQ(b.host.breaks()[0], std::make_pair(k_char, true));
    EXPECT_EQ(b.host.breaks()[1], std::make_pair(k_char * 2.0, false));
    ASSERT_EQ(b.host.received().size(), 1u);
    EXPECT_EQ(b.host.received()[0].byte, 'A');
    EXPECT_FALSE(b.host.received()[0].parity_error || b.host.received()[0].framing_error);
    EXPECT_EQ(b.host.received()[0].at, k_char * 3.0 + k_bit.span(2));
}

TEST(HostBreakOverlap, BreakStartingMidCharacterCutsItAndSwallowsTheNext) {
    // "AB" written at 0; BREAK from 5.5 bits (the data bit 4 sample) for 3 frames. 'A' = 0x41:
    // data bits 0 and 6 at MARK; from bit 4 on every sample reads SPACE, so bit 6 reads 0: 0x01;
    // its even parity bit would be 1, read 0: parity error; STOP 0: framing error. 'B' starts at
    // one frame, inside the BREAK: no edge, nothing of it arrives. The log shows "01 PF".
    RawHostConfig cfg;
    cfg.log_path = (test::scratch_dir() / "host_break_mid.log").string();
    UartAndRawHost b(cfg);
    const sc_time fall = k_bit.span(11);
    UartAndRawHost::at(sc_core::SC_ZERO_TIME, [&] {
        b.uart.write(TXD, 'A');
        b.uart.write(TXD, 'B');
    });
    UartAndRawHost::at(fall, [&] { b.line.insert_break(SerialLine::a, k_char * 3.0); });
    sc_core::sc_start();
    ASSERT_EQ(b.host.received().size(), 1u);
    EXPECT_EQ(b.host.received()[0].byte, 0x01);
    EXPECT_TRUE(b.host.received()[0].parity_error);
    EXPECT_TRUE(b.host.received()[0].framing_error);
    EXPECT_EQ(b.host.received()[0].at, k_char);
    ASSERT_EQ(b.host.breaks().size(), 2u);
    EXPECT_EQ(b.host.breaks()[0], std::make_pair(fall + k_char, true));
    EXPECT_EQ(b.host.breaks()[1], std::make_pair(fall + k_char * 3.0, false));
    EXPECT_EQ(b.uart.stats().chars_sent, 2u);
    EXPECT_EQ(b.line.stats(SerialLine::a).swallowed, 1u);
    std::ifstream log(cfg.log_path);
    std::string first;
    std::getline(log, first);
    EXPECT_EQ(first, std::to_string(k_char.value()) + " 01 PF");
}

TEST(HostBreakOverlap, SetBreakAfterTheStopSampleLeavesTheCharacterIntact) {
    // 0xFF written at 0; LCR.SBK set 1 ps after the STOP sample (10.5 bits), cleared 3 frames
    // later: the character arrives intact, then the break (detected one frame after the fall).
    UartAndRawHost b;
    const sc_time fall = k_bit.span(21) + ps(1);
    UartAndRawHost::at(sc_core::SC_ZERO_TIME, [&] { b.uart.write(TXD, 0xFF); });
    UartAndRawHost::at(fall, [&] { b.uart.write(LCR, 0x1B | LCR_SBK); });
    UartAndRawHost::at(fall + k_char * 3.0, [&] { b.uart.write(LCR, 0x1B); });
    sc_core::sc_start();
    ASSERT_EQ(b.host.received().size(), 1u);
    EXPECT_EQ(b.host.received()[0].byte, 0xFF);
    EXPECT_FALSE(b.host.received()[0].parity_error || b.host.received()[0].framing_error);
    ASSERT_EQ(b.host.breaks().size(), 2u);
    EXPECT_EQ(b.host.breaks()[0], std::make_pair(fall + k_char, true));
    EXPECT_EQ(b.host.breaks()[1], std::make_pair(fall + k_char * 3.0, false));
}

TEST(HostBreakOverlap, BreakCoveringCharactersDeliversOnlyTheBreak) {
    // BREAK [0, 5 frames); "OK" written at one frame: both STARTs (1 and 2 frames) fall inside
    // it. The host receives no byte, only the break detect (the all-zero character with its STOP
    // at SPACE) at one frame and its end at five.
    UartAndRawHost b;
    UartAndRawHost::at(sc_core::SC_ZERO_TIME, [&] { b.line.insert_break(SerialLine::a, k_char * 5.0); });
    UartAndRawHost::at(k_char, [&] {
        b.uart.write(TXD, 'O');
        b.uart.write(TXD, 'K');
    });
    sc_core::sc_start();
    EXPECT_TRUE(b.host.received().empty());
    ASSERT_EQ(b.host.breaks().size(), 2u);
    EXPECT_EQ(b.host.breaks()[0], std::make_pair(k_char, true));
    EXPECT_EQ(b.host.breaks()[1], std::make_pair(k_char * 5.0, false));
    EXPECT_EQ(b.uart.stats().chars_sent, 2u);
    EXPECT_EQ(b.line.stats(SerialLine::a).swallowed, 2u);
}

TEST(HostBreakOverlap, ControllerSideBreakOverTheAckMakesTheProtocolHostRetry) {
    // The protocol host's ENQ (START at 1 ms) reaches a responder behind the 82510 at 1 ms + one
    // frame; the ACK it writes 50 us later starts inside a controller-side BREAK [2 ms, 12 ms):
    // no edge, no ACK. The host times out after T1 (50 ms), pauses 10 ms, sends ENQ again; that
    // ACK, the frame and the EOT go through: one timeout, one retry, the command delivered.
    SerialLine line("line");
    Uart82510 uart("uart");
    Unused cpu("cpu");
    cpu.sock.bind(uart.bus);
    IrqLine irq("irq");
    uart.int_out.bind(irq);
    uart.connect(line, SerialLine::a);
    ProtocolHostConfig cfg;
    cfg.traffic.wait_response = false;
    cfg.traffic.pattern = HostTraffic::Pattern::fixed;
    cfg.traffic.count = 1;
    cfg.traffic.data_size = 4;
    cfg.traffic.start = us(1000);
    ProtocolHost host("host", cfg);
    host.connect(line, SerialLine::b);
    test::spawn_forever([&] {
        uart.write(LCR, LCR_DLAB);
        uart.write(BAL, 60);
        uart.write(LCR, 0x1B);
        uart.write(BANK, 0x40);
        uart.write(IMD, 0x00);
        uart.write(BANK, 0x00);
        uart.write(GER, 1u << rx_fifo);
        for (;;) {
            sc_core::wait(irq.posedge_event());
            sc_core::wait(us(50));
            while (uart.read(LSR) & LSR_DR) {
                const std::uint8_t c = uart.read(RXD);
                if (c == proto::ENQ) uart.write(TXD, proto::ACK);
                if (c == proto::ETX) uart.write(TXD, proto::EOT);
            }
        }
    }, "controller");
    UartAndRawHost::at(us(2000), [&] { line.insert_break(SerialLine::a, us(10000)); });
    sc_core::sc_start(sc_core::sc_time(1, sc_core::SC_SEC));
    const auto& c = host.counters();
    EXPECT_EQ(c.timeouts, 1u);
    EXPECT_EQ(c.retries, 1u);
    EXPECT_EQ(c.frames_delivered, 1u);
    EXPECT_EQ(line.stats(SerialLine::a).swallowed, 1u);
}
