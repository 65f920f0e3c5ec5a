// The trace on an assembled world, with an event handed to a chip's probe hook directly: BUSY of
// the DP-RAM, which no shipped scenario provokes (report.json dpram.collisions is 0 in all).
#include "tests/scenarios/trace/trace_check.h"

#include "models/clock.h"
#include "scenarios/world/world.h"
#include "scenarios/config/scenario.h"
#include "scenarios/trace/perfetto_trace.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using nlohmann::json;

namespace {

std::vector<std::pair<double, std::int64_t>> counter(const json& d, const std::string& name) {
    std::vector<std::pair<double, std::int64_t>> v;
    for (const auto& e : rcsim::test::trace_events(d))
        if (e["ph"] == "C" && e["name"] == name) v.emplace_back(e["ts"].get<double>(), e["args"]["value"].get<std::int64_t>());
    return v;
}

TEST(TraceWorld, EachBusyEpisodeIsAStepOnItsPortsCounter) {
    const rcsim::Scenario s = rcsim::load_scenario(RCSIM_TRACE_DATA "/short_trace.yaml");
    rcsim::World world("world", s);
    std::filesystem::create_directories(RCSIM_TRACE_WORK);
    const std::string path = RCSIM_TRACE_WORK "/busy.json";
    bool before = false; // a hook set before the trace keeps being called
    world.ctl.dpram.on_busy = [&before](const rcsim::Idt7130::BusyEvent&) { before = true; };
    rcsim::trace::PerfettoTrace trace(world, path);
    using E = rcsim::Idt7130::BusyEvent;
    world.ctl.dpram.on_busy(E{rcsim::Idt7130::left_port, 0x10, false, rcsim::ps(5'000'000), rcsim::ps(5'250'000), 2});
    world.ctl.dpram.on_busy(E{rcsim::Idt7130::right_port, 0x20, true, rcsim::ps(7'000'000), rcsim::ps(7'562'500), 1});
    trace.finish();
    EXPECT_TRUE(before);
    std::ifstream in(path);
    const json d = json::parse(in);
    EXPECT_TRUE(rcsim::test::check_trace(d).empty());
    using V = std::vector<std::pair<double, std::int64_t>>;
    EXPECT_EQ(counter(d, "BUSY left (comm CPU)"), (V{{0, 0}, {5, 1}, {5.25, 0}}));
    EXPECT_EQ(counter(d, "BUSY right (main CPU)"), (V{{0, 0}, {7, 1}, {7.5625, 0}}));
}

} // namespace
