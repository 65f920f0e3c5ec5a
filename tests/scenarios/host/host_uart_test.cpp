// The protocol host talking to a real 82510 model (host at nominal 9600 bps, the 82510 at
// 18.432 MHz / 60): a tiny interrupt-driven responder behind the 82510 answers ENQ with ACK and
// ETX with EOT. Checks that the two ends' timing and formats interoperate byte for byte.
#include "scenarios/host/protocol_host.h"
#include "uart82510/uart82510.h"

#include "models/clock.h"
#include "tests/support/sc_test.h"

#include <tlm_utils/simple_initiator_socket.h>

using namespace rcsim;
using namespace rcsim::i82510;

namespace {
/// The 82510's bus socket must be bound; this test drives registers through read()/write().
struct Unused : sc_core::sc_module {
    tlm_utils::simple_initiator_socket<Unused> sock{"sock"};
    explicit Unused(sc_core::sc_module_name n) : sc_module(n) {}
};
} // namespace

TEST(HostWithUart82510, CommandsCrossTheLineIntact) {
    SerialLine line("line");
    Uart82510 uart("uart");
    Unused cpu("cpu");
    cpu.sock.bind(uart.bus);
    IrqLine irq("irq");
    uart.int_out.bind(irq);
    uart.connect(line, SerialLine::a);
    ProtocolHostConfig cfg;
    cfg.traffic.wait_response = false;
    cfg.traffic.pattern = HostTraffic::Pattern::saturate;
    cfg.traffic.count = 5;
    cfg.traffic.random_size = true;
    cfg.traffic.data_size = 40;
    cfg.traffic.start = us(1000); // after the 82510 is programmed (a START edge before that is
                                  // sampled with the reset divisor: garbage, as on hardware)
    ProtocolHost host("host", cfg);
    host.connect(line, SerialLine::b);

    std::string seen;
    test::spawn_forever([&] { // the comm CPU's receive ISR: serves the line until the end
        uart.write(LCR, LCR_DLAB);
        uart.write(BAL, 60);
        uart.write(LCR, 0x1B);
        uart.write(BANK, 0x40);
        uart.write(IMD, 0x00);
        uart.write(BANK, 0x00);
        uart.write(GER, 1u << rx_fifo);
        for (;;) {
            sc_core::wait(irq.posedge_event());
            sc_core::wait(us(50)); // the "ISR" latency
            while (uart.read(LSR) & LSR_DR) {
                const std::uint8_t c = uart.read(RXD);
                seen += static_cast<char>(c);
                if (c == proto::ENQ) uart.write(TXD, proto::ACK);
                if (c == proto::ETX) uart.write(TXD, proto::EOT);
            }
        }
    }, "isr");
    sc_core::sc_start(sc_core::sc_time(2, sc_core::SC_SEC));
    EXPECT_EQ(host.counters().frames_delivered, 5u);
    EXPECT_EQ(host.counters().naks + host.counters().timeouts + host.counters().line_errors, 0u);
    EXPECT_EQ(uart.stats().parity_errors + uart.stats().framing_errors + uart.stats().overruns, 0u);
    // Five ENQ + frame sequences, every frame valid.
    std::size_t frames = 0;
    for (std::size_t p = seen.find('\x01'); p != std::string::npos; p = seen.find('\x01', p + 1)) {
        proto::Frame f;
        EXPECT_EQ(proto::decode(seen.substr(p, seen.find('\x03', p) - p + 1), f), "");
        ++frames;
    }
    EXPECT_EQ(frames, 5u);
    ASSERT_FALSE(host.log().empty());
    EXPECT_EQ(host.log()[0].at, us(1000));
}
