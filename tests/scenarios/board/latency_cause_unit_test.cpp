// The bounded keepers of the latency causes: WorstLatencies (the longest records, longest first)
// and RequestTrack (what the 8259A did with one request, in stretches).
#include "scenarios/board/interrupt_probe.h"
#include "scenarios/board/latency_cause.h"
#include "tests/support/sc_test.h"

using namespace rcsim;
using namespace sc_core;
using Kind = LatencyPhase::Kind;
using Hold = Pic8259::Hold;

namespace {

InterruptRecord with_latency(unsigned rise_ns, unsigned latency_ns) {
    InterruptRecord r;
    r.has_rise = true;
    r.ir_rise = sc_time(rise_ns, SC_NS);
    r.first_isr = r.ir_rise + sc_time(latency_ns, SC_NS);
    return r;
}

} // namespace

// The `keep` longest, longest first; a tie keeps the one added first ahead; no rise, no latency.
TEST(WorstLatencies, KeepsTheLongestInBoundedMemory) {
    WorstLatencies w(3);
    InterruptRecord none;
    w.add(none);
    EXPECT_TRUE(w.records().empty());
    const unsigned latencies[] = {50, 10, 70, 70, 20, 90, 60, 70};
    for (unsigned k = 0; k < 8; ++k) w.add(with_latency(1000 * k, latencies[k]));
    ASSERT_EQ(w.records().size(), 3u);
    EXPECT_EQ(w.records()[0].first_isr - w.records()[0].ir_rise, sc_time(90, SC_NS));
    EXPECT_EQ(w.records()[1].ir_rise, sc_time(2000, SC_NS)); // the first 70
    EXPECT_EQ(w.records()[2].ir_rise, sc_time(3000, SC_NS)); // the second; the third 70 came too late
    EXPECT_EQ(WorstLatencies().records().size(), 0u);
}

// A hold that changes in no time is dropped (the earlier stretch goes on); the running stretch
// ends where asked; stretches past the end are cut.
TEST(RequestTrack, StretchesOfTheHolds) {
    RequestTrack t;
    std::array<LatencyPhase, RequestTrack::kMaxPhases> out{};
    EXPECT_FALSE(t.is_open());
    t.open(sc_time(100, SC_NS), Hold{Hold::Kind::masked, -1});
    t.update(sc_time(200, SC_NS), Hold{Hold::Kind::in_service, 1});
    t.update(sc_time(200, SC_NS), Hold{Hold::Kind::priority, 0}); // same instant: replaces it
    t.update(sc_time(200, SC_NS), Hold{Hold::Kind::in_service, 1});
    t.update(sc_time(300, SC_NS), Hold{Hold::Kind::in_service, 1}); // unchanged
    t.update(sc_time(400, SC_NS), Hold{});
    ASSERT_EQ(t.phases(sc_time(450, SC_NS), out), 3u);
    EXPECT_EQ(out[0].kind, Kind::masked);
    EXPECT_EQ(out[0].to, sc_time(200, SC_NS));
    EXPECT_EQ(out[1].kind, Kind::in_service);
    EXPECT_EQ(out[1].level, 1);
    EXPECT_EQ(out[1].from, sc_time(200, SC_NS));
    EXPECT_EQ(out[1].to, sc_time(400, SC_NS));
    EXPECT_EQ(out[2].kind, Kind::presented);
    EXPECT_EQ(out[2].to, sc_time(450, SC_NS));
    ASSERT_EQ(t.phases(sc_time(250, SC_NS), out), 2u); // cut at 250
    EXPECT_EQ(out[1].to, sc_time(250, SC_NS));
    t.close();
    EXPECT_FALSE(t.is_open());
}

// More changes than it keeps: the last stretch holds the rest, memory stays bounded.
TEST(RequestTrack, BoundedWhateverTheChanges) {
    RequestTrack t;
    t.open(SC_ZERO_TIME, Hold{});
    for (unsigned k = 1; k <= 100; ++k)
        t.update(sc_time(10 * k, SC_NS), k % 2 ? Hold{Hold::Kind::in_service, 2} : Hold{});
    std::array<LatencyPhase, RequestTrack::kMaxPhases> out{};
    const unsigned n = t.phases(sc_time(2000, SC_NS), out);
    ASSERT_EQ(n, RequestTrack::kMaxPhases);
    EXPECT_EQ(out[0].from, SC_ZERO_TIME);
    EXPECT_EQ(out[n - 1].to, sc_time(2000, SC_NS));
    for (unsigned k = 1; k < n; ++k) EXPECT_EQ(out[k].from, out[k - 1].to);
}
