#include "scenarios/board/controller.h"
#include "scenarios/board/interrupt_probe.h"
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

struct ControllerOnWire {
    Controller ctl{"ctl"};
    SerialLine line{"line0"};
    Wire host{line};
    InterruptProbe probe{"probe", ctl.comm.cpu,
                         {&ctl.comm.uart_int[0], &ctl.comm.uart_int[1], &ctl.comm.uart_int[2], &ctl.int_l},
                         ctl.comm.config.pic_io_base, ctl.comm.config.dpram_base, 1020};
    SerialLine idle1{"line1"}, idle2{"line2"};
    ControllerOnWire() {
        ctl.comm.load_rom(RCSIM_COMM_FW_ROM);
        ctl.comm.uart[0].connect(line, SerialLine::a);
        ctl.comm.uart[1].connect(idle1, SerialLine::a);
        ctl.comm.uart[2].connect(idle2, SerialLine::a);
    }
};
} // namespace

TEST(System, EnqIsAnsweredWithAckByTheRealFirmware) {
    ControllerOnWire b;
    sc_core::sc_start(us(20000)); // firmware initialisation
    b.host.send(0x05);
    sc_core::sc_start(us(10000));
    ASSERT_FALSE(b.host.got.empty());
    EXPECT_EQ(b.host.got.front().second, 0x06);
    // The RS-232 interrupt was taken and measured from bus cycles. Only interrupts requested once
    // the firmware runs its main loop count: the first 1 ms tick rises while start-up still has
    // interrupts disabled (about 4 ms after reset), and waits for the STI at the end of main().
    Samples lat, svc;
    for (const InterruptRecord* r : b.probe.of_level(0)) {
        if (!r->has_rise || r->ir_rise < us(20000)) continue;
        lat.add(r->latency_us());
        svc.add(r->service_us());
    }
    EXPECT_GE(lat.summary().count, 10u) << "the 1 ms tick and the ENQ";
    EXPECT_GT(lat.summary().min, 0.0);
    EXPECT_LT(lat.summary().max, 382.0);
    EXPECT_GT(svc.summary().min, 0.0);
}

