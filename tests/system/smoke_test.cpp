#include "models/controller.h"
#include "models/interrupt_probe.h"
#include "models/serial_line.h"
#include "tests/support/sc_test.h"

using namespace rcsim;
using sc_core::sc_time;

namespace {
// A minimal host end: records what it receives, sends bytes on request.
struct Wire : SerialEndpoint {
    SerialLine& line;
    SerialFormat fmt = SerialFormat::rs232();
    std::vector<std::pair<sc_time, std::uint8_t>> got;
    explicit Wire(SerialLine& l) : line(l) { line.attach(SerialLine::b, *this); }
    SerialFormat rx_format() const override { return fmt; }
    void rx_char(const SerialRx& c) override { got.emplace_back(c.stop, static_cast<std::uint8_t>(c.data)); }
    void rx_break(bool) override {}
    void send(std::uint8_t b) { line.transmit(SerialLine::b, SerialWord::encode(b, fmt)); }
};

struct Bench {
    Controller ctl{"ctl"};
    SerialLine line{"line0"};
    Wire host{line};
    InterruptProbe probe{"probe", ctl.comm.cpu,
                         {&ctl.comm.uart_int[0], &ctl.comm.uart_int[1], &ctl.comm.uart_int[2], &ctl.int_l},
                         ctl.comm.config.pic_io_base, ctl.comm.config.dpram_base, 1020};
    SerialLine idle1{"line1"}, idle2{"line2"};
    Bench() {
        ctl.comm.load_rom(RCSIM_COMM_FW_ROM);
        ctl.comm.uart[0].connect(line, SerialLine::a);
        ctl.comm.uart[1].connect(idle1, SerialLine::a);
        ctl.comm.uart[2].connect(idle2, SerialLine::a);
    }
};
} // namespace

TEST(System, EnqIsAnsweredWithAckByTheRealFirmware) {
    Bench b;
    sc_core::sc_start(us(20000)); // firmware initialisation
    b.host.send(0x05);
    sc_core::sc_start(us(10000));
    ASSERT_FALSE(b.host.got.empty());
    EXPECT_EQ(b.host.got.front().second, 0x06);
    // The RS-232 interrupt was taken and measured from bus cycles.
    const auto lat = b.probe.latency_us(0).summary();
    EXPECT_GE(lat.count, 1u);
    EXPECT_GT(lat.min, 0.0);
    EXPECT_LT(lat.max, 382.0);
    EXPECT_GT(b.probe.service_us(0).summary().min, 0.0);
}

