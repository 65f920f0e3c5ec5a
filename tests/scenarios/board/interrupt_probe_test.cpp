// InterruptProbe: every record is ordered as the 8086/8259A sequence demands, names the handler
// the vector table points at (checked against the firmware's own symbol map), and its latency
// and service figures are what the bus cycles say.
#include "comm_fw_symbols.h"
#include "scenarios/board/controller.h"
#include "scenarios/board/interrupt_probe.h"
#include "scenarios/host/protocol_host.h"
#include "tests/support/sc_test.h"

#include <algorithm>
#include <utility>
#include <vector>

using namespace rcsim;

namespace {
struct ProbedController {
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
    ProbedController() : host("host", host_config()) {
        ctl.comm.load_rom(RCSIM_COMM_FW_ROM);
        for (unsigned p = 0; p < 3; ++p) ctl.comm.uart[p].connect(lines[p], SerialLine::a);
        host.connect(lines[1], SerialLine::b);
    }
};
} // namespace

TEST(InterruptProbe, RecordsFollowTheAcknowledgeSequenceAndNameTheRealHandlers) {
    ProbedController b;
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

TEST(InterruptProbe, HandsEveryRecordOverOnceInEntryOrderAndNoneStartsBeforeTheHorizon) {
    ProbedController b;
    std::vector<InterruptRecord> handed;
    std::vector<std::pair<std::size_t, sc_core::sc_time>> settled; // records handed so far, horizon
    b.probe.on_record = [&](const InterruptRecord& r) { handed.push_back(r); };
    b.probe.on_settled = [&](const sc_core::sc_time& h) { settled.emplace_back(handed.size(), h); };
    sc_core::sc_start(us(400000));
    b.probe.flush();
    ASSERT_EQ(b.host.counters().frames_delivered, 3u);
    // The same records as the kept list (which is in completion order), each once.
    const auto& kept = b.probe.records();
    ASSERT_EQ(handed.size(), kept.size());
    auto by_entry = [](const InterruptRecord& x, const InterruptRecord& y) { return x.inta1 < y.inta1; };
    std::vector<InterruptRecord> sorted = kept;
    std::sort(sorted.begin(), sorted.end(), by_entry);
    EXPECT_TRUE(std::is_sorted(handed.begin(), handed.end(), by_entry)) << "entry order";
    for (std::size_t i = 0; i < handed.size(); ++i) {
        EXPECT_EQ(handed[i].inta1, sorted[i].inta1) << i;
        EXPECT_EQ(handed[i].iret_done, sorted[i].iret_done) << i;
    }
    std::size_t nested = 0;
    for (const auto& r : kept) nested += r.depth > 0;
    EXPECT_GT(nested, 0u) << "the test's premise: some were held back behind the DP-RAM handler";
    // Every record handed over after a settle starts at its horizon or later.
    ASSERT_FALSE(settled.empty());
    for (const auto& [from, h] : settled)
        for (std::size_t i = from; i < handed.size(); ++i) {
            const sc_core::sc_time start = handed[i].has_rise ? handed[i].ir_rise : handed[i].inta1;
            ASSERT_GE(start, h) << "record " << i << " after the settle at record " << from;
        }
    // Per level the online counts and sample sets are those of the records after start-up; the
    // start-up records (requested before the CPU could first take an interrupt) are apart.
    for (unsigned level = 0; level < 4; ++level) {
        std::uint64_t startup = 0, after = 0;
        for (const InterruptRecord* r : b.probe.of_level(level)) {
            const bool early = r->has_rise && r->ir_rise < *b.probe.interrupts_enabled();
            EXPECT_EQ(r->startup, early);
            (early ? startup : after) += 1;
        }
        EXPECT_EQ(b.probe.count(level), after);
        EXPECT_EQ(b.probe.service_us(level).count(), after);
        std::uint64_t apart = 0;
        for (const InterruptRecord& r : b.probe.startup_records()) apart += r.level == level;
        EXPECT_EQ(apart, startup);
    }
}

TEST(InterruptProbe, KeepsNoRecordWhenToldNot) {
    ProbedController b;
    b.probe.keep_records(false);
    std::uint64_t handed = 0;
    b.probe.on_record = [&](const InterruptRecord&) { ++handed; };
    sc_core::sc_start(us(100000));
    b.probe.flush();
    EXPECT_TRUE(b.probe.records().empty());
    EXPECT_GT(handed, 50u); // the 1 ms tick alone in 100 ms
    std::uint64_t counted = 0;
    for (unsigned level = 0; level < 8; ++level) counted += b.probe.count(level);
    EXPECT_EQ(handed, counted + b.probe.startup_records().size());
}
