// InterruptProbe: every record is ordered as the 8086/8259A sequence demands, names the handler
// the vector table points at (checked against the firmware's own symbol map), and its latency
// and service figures are what the bus cycles say.
#include "comm_fw_symbols.h"
#include "scenarios/controller.h"
#include "scenarios/interrupt_probe.h"
#include "scenarios/host/protocol_host.h"
#include "tests/support/sc_test.h"

using namespace rcsim;

namespace {
struct Bench {
    Controller ctl{"ctl"};
    sc_core::sc_vector<SerialLine> lines{"line", 3};
    ProtocolHost host;
    InterruptProbe probe{"probe", ctl.comm.cpu,
                         {&ctl.comm.uart_int[0], &ctl.comm.uart_int[1], &ctl.comm.uart_int[2], &ctl.int_l},
                         ctl.comm.config.pic_io_base, ctl.comm.config.dpram_base, 1020};
    static ProtocolHostConfig host_config() {
        ProtocolHostConfig c;
        c.traffic.pattern = HostTraffic::Pattern::fixed;
        c.traffic.rate = 20;
        c.traffic.count = 3;
        c.traffic.start = us(30000);
        c.traffic.data_size = 20;
        return c;
    }
    Bench() : host("host", host_config()) {
        ctl.comm.load_rom(RCSIM_COMM_FW_ROM);
        for (unsigned p = 0; p < 3; ++p) ctl.comm.uart[p].connect(lines[p], SerialLine::a);
        host.connect(lines[1], SerialLine::b);
    }
};
} // namespace

TEST(InterruptProbe, RecordsFollowTheAcknowledgeSequenceAndNameTheRealHandlers) {
    Bench b;
    sc_core::sc_start(us(400000));
    ASSERT_EQ(b.host.counters().frames_delivered, 3u);
    const std::uint32_t handler[4] = {comm_fw::code::isr_port0, comm_fw::code::isr_port1,
                                      comm_fw::code::isr_port2, comm_fw::code::isr_dpram};
    unsigned per_level[4] = {};
    for (const InterruptRecord& r : b.probe.records()) {
        ASSERT_LT(r.level, 4u);
        ++per_level[r.level];
        EXPECT_EQ(r.vector, 0x20 + r.level);
        EXPECT_EQ(r.handler, handler[r.level]) << "level " << r.level;
        EXPECT_LT(r.inta1, r.inta2);
        EXPECT_LT(r.inta2, r.first_isr);
        EXPECT_LT(r.first_isr, r.iret_done);
        if (r.has_rise) {
            EXPECT_LE(r.ir_rise, r.inta1);
        }
        if (r.has_eoi) {
            EXPECT_LT(r.first_isr, r.eoi);
            EXPECT_LT(r.eoi, r.iret_done);
        }
        // Two back-to-back INTA cycles of 4 clocks (the 8086 idles between them).
        EXPECT_GE(r.inta2 - r.inta1, ns(500));
        EXPECT_DOUBLE_EQ(r.latency_us(), to_us(r.first_isr - r.ir_rise));
    }
    // Nesting is proper: an interrupt taken inside a handler (the DP-RAM handler runs with IF=1)
    // lies within that handler's time. An entry the probe failed to close would instead stay
    // open and make later interrupts look nested in it, ending after them.
    const auto& recs = b.probe.records();
    for (const InterruptRecord& r : recs) {
        if (r.depth == 0) continue;
        bool inside = false;
        for (const InterruptRecord& p : recs)
            inside = inside || (p.depth == r.depth - 1 && p.first_isr < r.inta1 && r.iret_done < p.iret_done);
        EXPECT_TRUE(inside) << "level " << r.level << " at " << r.inta1 << " depth " << r.depth;
    }
    // Every acknowledged interrupt was recorded (but those still running at the end).
    std::uint64_t acks = 0;
    for (unsigned level = 0; level < 8; ++level) acks += b.ctl.comm.pic.acks(level);
    EXPECT_LE(acks - b.probe.records().size(), 2u);
    EXPECT_GT(per_level[0], 300u); // the 1 ms tick on 82510 #0
    EXPECT_GT(per_level[1], 0u);   // port 1 receiving and sending
    EXPECT_GT(per_level[3], 0u);   // the main CPU's response chunks and ACK words
    EXPECT_EQ(per_level[2], 0u);   // nothing on port 2
    EXPECT_EQ(b.probe.latency_us(2).count(), 0u);
    EXPECT_EQ(b.probe.service_us(1).count(), per_level[1]);
}
