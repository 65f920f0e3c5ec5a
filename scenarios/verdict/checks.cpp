#include "scenarios/verdict/checks.h"

#include "scenarios/verdict/measure.h"

#include <algorithm>

namespace rcsim {

namespace {

Check judge(std::string name, const Figure& f, double limit, bool holds) {
    Check c;
    c.name = std::move(name);
    c.status = Check::Status::not_measured;
    c.figure = f;
    c.limit = limit;
    if (f.value) c.status = holds ? Check::Status::passed : Check::Status::failed;
    return c;
}

/// The detail of an exactly-once check (docs/scenarios.md "Expected drops"): the first frames that
/// count against it, earliest first, with port, direction and simulated time; how many drops the
/// scenario caused and how many frames were in flight at an interrupted stop. Null (no detail)
/// when all three are nothing, so a clean run's report is unchanged.
nlohmann::json exactly_once_detail(const World& b, bool commands) {
    constexpr std::size_t kShown = 5;
    const unsigned dir = commands ? LineObserver::host_to_controller : LineObserver::controller_to_host;
    std::vector<std::pair<unsigned, const FrameEvent*>> events;
    std::uint64_t expected = 0, in_flight = 0, counted = 0;
    for (unsigned p = 0; p < World::kPorts; ++p) {
        const SequenceMatcher& m = commands ? b.observers[p].command_books() : b.observers[p].response_books();
        for (const FrameEvent& e : m.unexplained()) events.emplace_back(p, &e);
        expected += m.counts().expected;
        in_flight += m.counts().in_flight;
        counted += m.counts().mismatches();
    }
    if (counted == 0 && expected == 0 && in_flight == 0) return nullptr;
    std::stable_sort(events.begin(), events.end(),
                     [](const auto& x, const auto& y) { return x.second->time_us < y.second->time_us; });
    nlohmann::json first = nlohmann::json::array();
    for (std::size_t i = 0; i < events.size() && i < kShown; ++i) {
        nlohmann::json j = frame_event_json(*events[i].second, dir);
        j["port"] = events[i].first;
        first.push_back(j);
    }
    return {{"unexplained", first}, {"expected_drops", expected}, {"in_flight", in_flight}};
}

} // namespace

Check Check::at_most(std::string name, const Figure& f, double limit) {
    return judge(std::move(name), f, limit, f.value && *f.value <= limit);
}

Check Check::at_least(std::string name, const Figure& f, double limit) {
    return judge(std::move(name), f, limit, f.value && *f.value >= limit);
}

const char* status_name(Check::Status s) {
    switch (s) {
    case Check::Status::passed: return "passed";
    case Check::Status::failed: return "failed";
    case Check::Status::not_measured: return "not measured";
    }
    return "?";
}

nlohmann::json to_json(const Check& c) {
    nlohmann::json j = {{"name", c.name},
                        {"passed", c.passed()},
                        {"status", status_name(c.status)},
                        {"value", c.figure.value ? nlohmann::json(*c.figure.value) : nlohmann::json(nullptr)},
                        {"limit", c.limit}};
    if (!c.figure.value) j["reason"] = c.figure.reason;
    if (!c.detail.is_null()) j["detail"] = c.detail;
    return j;
}

double char_latency_limit_us(const World& b, const Scenario& s, unsigned p) {
    if (s.checks.max_char_latency_us >= 0) return s.checks.max_char_latency_us;
    return b.ctl.comm.uart[p].config().fifo_depth * controller_char_us(b, p);
}

std::vector<Check> communication_checks(const World& b, const Scenario& s, const CheckFigures& f) {
    const CheckLimits& L = s.checks;
    auto count = [](std::uint64_t v) { return Figure::of(double(v)); };
    // With no explicit limit, every port whose host generates commands must deliver at least one.
    const double min_delivered = L.min_frames_delivered ? double(*L.min_frames_delivered) : double(f.traffic_ports);
    std::vector<Check> checks;
    checks.push_back(Check::at_most("overruns", count(f.overruns), double(L.max_overruns)));
    checks.push_back(Check::at_most("frames_failed", count(f.frames_failed), double(L.max_frames_failed)));
    // Both directions, from the line observers; one limit for both (`max_frame_mismatches`).
    for (const bool commands : {true, false}) {
        Check c = Check::at_most(commands ? "commands_delivered_exactly_once" : "responses_delivered_exactly_once",
                                 count(commands ? f.command_mismatches : f.response_mismatches),
                                 double(L.max_frame_mismatches));
        c.detail = exactly_once_detail(b, commands);
        checks.push_back(std::move(c));
    }
    Check malformed = Check::at_most("main_cpu_malformed_frames", count(f.malformed), 0);
    // Which frame and why: the first few the main CPU dropped (the log has them all).
    const auto& dropped = b.ctl.main.malformed();
    if (!dropped.empty()) {
        malformed.detail = nlohmann::json::array();
        for (std::size_t i = 0; i < dropped.size() && i < 3; ++i)
            malformed.detail.push_back({{"port", dropped[i].port},
                                        {"time_us", dropped[i].time.to_seconds() * 1e6},
                                        {"reason", dropped[i].reason}});
    }
    checks.push_back(std::move(malformed));
    checks.push_back(Check::at_least("frames_delivered", count(f.frames_delivered), min_delivered));
    if (!L.off.count("char_latency_max_us"))
        for (unsigned p = 0; p < World::kPorts; ++p)
            if (s.ports[p].host != PortScenario::Host::none)
                checks.push_back(Check::at_most("port" + std::to_string(p) + "_char_latency_max_us",
                                                f.char_latency_max_us[p], char_latency_limit_us(b, s, p)));
    checks.push_back(Check::at_least("table3_margin_us", f.table3_margin_us, L.min_margin_us));
    if (L.min_worst_margin_us)
        checks.push_back(Check::at_least("table3_worst_margin_us", f.table3_worst_margin_us, *L.min_worst_margin_us));
    for (unsigned p = 0; p < World::kPorts; ++p)
        if (const auto& h = b.replay[p]) {
            // The replayed session must draw the recorded answers: same bytes at the same times.
            const std::uint64_t bad = h->counters().out_mismatched + h->out_missing();
            checks.push_back(Check::at_most("replay_port" + std::to_string(p) + "_matches_record", count(bad), 0));
        }
    // A cycle nothing answered reads as an open bus or is dropped: firmware that makes one runs on,
    // wrongly and silently (report.json "bus_errors" says which).
    checks.push_back(Check::at_most("bus_errors", count(f.bus_errors), double(L.max_bus_errors)));
    checks.erase(std::remove_if(checks.begin(), checks.end(),
                                [&L](const Check& c) { return L.off.count(c.name) != 0; }),
                 checks.end());
    return checks;
}

} // namespace rcsim
