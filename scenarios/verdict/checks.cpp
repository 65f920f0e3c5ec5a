#include "scenarios/verdict/checks.h"

#include "scenarios/verdict/measure.h"

#include "models/plumbing/sim_time_text.h"

#include <algorithm>
#include <iomanip>
#include <sstream>

namespace rcsim {

namespace {

Check judge(std::string name, Check::Relation rel, const Figure& f, double limit, bool holds) {
    Check c;
    c.name = std::move(name);
    c.relation = rel;
    c.status = Check::Status::not_measured;
    c.figure = f;
    c.limit = limit;
    if (f.value) c.status = holds ? Check::Status::passed : Check::Status::failed;
    return c;
}

/// A simulated instant as the explanations print it, as the summaries do (sim_time_text).
std::string at_text(const sc_core::sc_time& t) { return sim_time_text(t.to_seconds()); }

std::string us(double v) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(1) << v << " us";
    return os.str();
}

std::string joined(const std::vector<std::string>& parts) {
    std::string s;
    for (const std::string& p : parts) s += (s.empty() ? "" : "; ") + p;
    return s;
}

/// overruns: per port, how many characters were lost and when the first was.
std::string why_overruns(const World& w) {
    std::vector<std::string> v;
    for (unsigned p = 0; p < World::kPorts; ++p) {
        const auto& u = w.ctl.comm.uart[p];
        if (u.stats().overruns == 0) continue;
        v.push_back("port " + std::to_string(p) + " (host to controller): " + std::to_string(u.stats().overruns) +
                    " character(s) lost, the first arriving at " + at_text(*u.first_overrun()) +
                    " with the RX FIFO full");
    }
    return joined(v);
}

/// frames_failed: per port, the commands the host gave up after its retries.
std::string why_frames_failed(const World& w) {
    std::vector<std::string> v;
    for (unsigned p = 0; p < World::kPorts; ++p) {
        const auto& h = w.protocol[p];
        if (!h || !h->first_failure()) continue;
        v.push_back("port " + std::to_string(p) + " (host to controller): " + std::to_string(h->counters().frames_failed) +
                    " command(s) given up after their retries, the first (" + h->first_failure()->token + ") at " +
                    at_text(h->first_failure()->at));
    }
    return joined(v);
}

/// frames_delivered: what each port whose host generates commands delivered.
std::string why_frames_delivered(const World& w, const Scenario& s) {
    std::vector<std::string> v;
    for (unsigned p = 0; p < World::kPorts; ++p)
        if (w.protocol[p] && s.ports[p].protocol.traffic.pattern != HostTraffic::Pattern::none)
            v.push_back("port " + std::to_string(p) + " (host to controller): " +
                        std::to_string(w.protocol[p]->counters().frames_delivered) + " of " +
                        std::to_string(w.protocol[p]->counters().frames_sent) + " commands delivered");
    return joined(v);
}

/// portN_char_latency_max_us: the character that waited longest.
std::string why_char_latency(const World& w, unsigned p) {
    const World::CharWait& worst = w.char_latency_worst[p];
    return "port " + std::to_string(p) + " (host to controller): a character waited " + us(worst.wait_us) +
           " in the RX FIFO, from its stop bit at " + at_text(worst.stop) + " to its RXD read at " + at_text(worst.read);
}

/// table3_worst_margin_us: the longest RS-232 receive interrupt and its place in the sum.
std::string why_worst_margin(const World& w, const CheckFigures& f, double budget) {
    if (w.rs232_rx_service_us().count() == 0) return "";
    const InterruptRecord& r = w.rs232_rx_longest();
    const double sum = budget - *f.table3_worst_margin_us.value; // longest + DP-RAM per byte
    return "the longest RS-232 receive interrupt, " + source_name(r.level) + " entered at " + at_text(r.first_isr) +
           ", took " + us(r.service_us()) + "; with the DP-RAM time per byte that is " + us(sum) + " against the " +
           us(budget) + " budget";
}

/// The service of any source that blocked other requests longest (the first of equals, lowest
/// level first); nullptr when no interrupt completed after start-up.
const InterruptRecord* longest_blocking(const World& w) {
    const InterruptRecord* worst = nullptr;
    for (unsigned level = 0; level < 8; ++level)
        if (const InterruptRecord* r = w.probe.longest_blocking(level); r && (!worst || r->blocking > worst->blocking))
            worst = r;
    return worst;
}

/// interrupt_blocking_max_us: which service, when, for how long, and what ran meanwhile.
std::string why_blocking(const InterruptRecord& r, const SymbolOf& symbol) {
    std::string path;
    for (const std::string& name : path_names(r.path.data(), r.path_len, symbol))
        path += (path.empty() ? "" : " > ") + name;
    return source_name(r.level) + " entered at " + at_text(r.first_isr) + " kept other requests waiting " +
           us(r.blocking_us()) + " (IF = 0, or its level in service before its EOI) of its " + us(r.service_us()) +
           " service" + (path.empty() ? std::string() : "; what ran: " + path);
}

/// table3_margin_us: the mean sum against the budget.
std::string why_margin(const CheckFigures& f, double budget) {
    return "RS-232 receive interrupt mean + DP-RAM time per byte = " + us(budget - *f.table3_margin_us.value) +
           " against the " + us(budget) + " budget (mean request period of the active ports)";
}

/// bus_errors: the first cycle nothing answered.
std::string why_bus_errors(const World& w) {
    const auto& first = w.ctl.comm.cpu.bus_errors().first();
    if (first.empty()) return "";
    const nlohmann::json e = to_json(w.ctl.comm.cpu.bus_errors())["first"][0];
    return "the first: " + e.value("kind", std::string("?")) + " " + e.value("cycle", std::string("?")) + " at " +
           e.value("address", std::string("?")) + ", at " + us(e.value("time_us", 0.0));
}

/// Sets c.why from `why()` when c failed (the explanations read figures only a failure has), and
/// c.at to `at` (the first offending event's time; none: no single time).
template <class Why> void explain(Check& c, Why why, std::optional<sc_core::sc_time> at = std::nullopt) {
    if (c.status != Check::Status::failed) return;
    c.why = why();
    c.at = at;
}

/// The time of the first frame an exactly-once check counts (its detail's "unexplained" list).
std::optional<sc_core::sc_time> first_unexplained(const nlohmann::json& detail) {
    if (!detail.is_object() || !detail.contains("unexplained") || detail["unexplained"].empty()) return std::nullopt;
    return sc_core::sc_time(detail["unexplained"][0].value("time_us", 0.0), sc_core::SC_US);
}

/// The earliest first overrun over the ports.
std::optional<sc_core::sc_time> first_overrun(const World& w) {
    std::optional<sc_core::sc_time> t;
    for (unsigned p = 0; p < World::kPorts; ++p)
        if (const auto& f = w.ctl.comm.uart[p].first_overrun(); f && (!t || *f < *t)) t = f;
    return t;
}

/// The earliest command given up over the ports.
std::optional<sc_core::sc_time> first_failure(const World& w) {
    std::optional<sc_core::sc_time> t;
    for (unsigned p = 0; p < World::kPorts; ++p)
        if (w.protocol[p] && w.protocol[p]->first_failure() && (!t || w.protocol[p]->first_failure()->at < *t))
            t = w.protocol[p]->first_failure()->at;
    return t;
}

/// The detail of an exactly-once check (docs/scenarios.md "Expected drops"): the first frames that
/// count against it, earliest first, with port, direction and simulated time; how many drops the
/// scenario caused and how many frames were in flight at an interrupted stop. Null (no detail)
/// when all three are nothing, so a clean run's report is unchanged.
nlohmann::json exactly_once_detail(const World& w, bool commands) {
    constexpr std::size_t kShown = 5;
    const unsigned dir = commands ? LineObserver::host_to_controller : LineObserver::controller_to_host;
    std::vector<std::pair<unsigned, const FrameEvent*>> events;
    std::uint64_t expected = 0, in_flight = 0, counted = 0;
    for (unsigned p = 0; p < World::kPorts; ++p) {
        const SequenceMatcher& m = commands ? w.observers[p].command_books() : w.observers[p].response_books();
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
    return judge(std::move(name), Relation::at_most, f, limit, f.value && *f.value <= limit);
}

Check Check::at_least(std::string name, const Figure& f, double limit) {
    return judge(std::move(name), Relation::at_least, f, limit, f.value && *f.value >= limit);
}

const char* status_name(Check::Status s) {
    switch (s) {
    case Check::Status::passed: return "passed";
    case Check::Status::failed: return "failed";
    case Check::Status::not_measured: return "not measured";
    }
    return "?";
}

const char* relation_symbol(Check::Relation r) { return r == Check::Relation::at_least ? ">=" : "<="; }

nlohmann::json to_json(const Check& c) {
    nlohmann::json j = {{"name", c.name},
                        {"passed", c.passed()},
                        {"status", status_name(c.status)},
                        {"value", c.figure.value ? nlohmann::json(*c.figure.value) : nlohmann::json(nullptr)},
                        {"relation", relation_symbol(c.relation)},
                        {"limit", c.limit}};
    if (!c.figure.value) j["reason"] = c.figure.reason;
    if (c.status == Check::Status::failed && !c.why.empty()) j["why"] = c.why;
    if (c.status == Check::Status::failed && c.at) j["at_us"] = exact_us(*c.at);
    if (!c.detail.is_null()) j["detail"] = c.detail;
    return j;
}

const char* verdict_name(Verdict v) {
    switch (v) {
    case Verdict::passed: return "passed";
    case Verdict::failed: return "failed";
    case Verdict::inconclusive: return "inconclusive";
    case Verdict::interrupted: return "interrupted";
    }
    return "?";
}

RunVerdict judge_run(const nlohmann::json& checks, int stop_signal, const std::string& idle) {
    std::vector<std::string> failed, unmeasured;
    std::string first_reason;
    for (const auto& c : checks) {
        const std::string status = c.value("status", "failed");
        if (status == "failed") failed.push_back(c.value("name", "?"));
        if (status != "not measured") continue;
        unmeasured.push_back(c.value("name", "?"));
        if (first_reason.empty()) first_reason = c.value("name", "?") + ": " + c.value("reason", "no samples");
    }
    auto list = [](const std::vector<std::string>& v, const char* sep) {
        std::string s;
        for (const std::string& x : v) s += (s.empty() ? "" : sep) + x;
        return s;
    };
    RunVerdict v{Verdict::passed, ""};
    if (!failed.empty()) v = {Verdict::failed, "failed: " + list(failed, ", ")};
    else if (!unmeasured.empty())
        v = {Verdict::inconclusive, (idle.empty() ? first_reason : idle) + "; not measured: " + list(unmeasured, ", ")};
    if (stop_signal == 0) return v;
    const std::string by = stop_signal == 2 ? "SIGINT" : stop_signal == 15 ? "SIGTERM" : "signal " + std::to_string(stop_signal);
    return {Verdict::interrupted, "stopped by " + by + "; what completed: " + verdict_name(v.verdict) +
                                      (v.reason.empty() ? "" : " (" + v.reason + ")")};
}

int exit_code_of(const RunVerdict& v, int stop_signal) {
    switch (v.verdict) {
    case Verdict::passed: return 0;
    case Verdict::failed: return 1;
    case Verdict::inconclusive: return 4;
    case Verdict::interrupted: return 128 + stop_signal;
    }
    return 1;
}

void put_verdict(nlohmann::json& report, const RunVerdict& v) {
    report["verdict"] = verdict_name(v.verdict);
    report["verdict_reason"] = v.reason;
    report["passed"] = v.verdict == Verdict::passed;
}

Figure char_latency_limit_us(const World& w, const Scenario& s, unsigned p) {
    if (s.checks.max_char_latency_us >= 0) return Figure::of(s.checks.max_char_latency_us);
    if (!w.ctl.comm.uart[p].format_programmed())
        return Figure::none("the firmware never programmed the character format of port " + std::to_string(p) +
                            "'s 82510: its character time, and so the limit, is unknown");
    return Figure::of(w.ctl.comm.uart[p].config().fifo_depth * controller_char_us(w, p));
}

std::vector<Check> communication_checks(const World& w, const Scenario& s, const CheckFigures& f,
                                        const SymbolOf& symbol) {
    const CheckLimits& L = s.checks;
    auto count = [](std::uint64_t v) { return Figure::of(double(v)); };
    // With no explicit limit, every port whose host generates commands must deliver at least one.
    const double min_delivered = L.min_frames_delivered ? double(*L.min_frames_delivered) : double(f.traffic_ports);
    std::vector<Check> checks;
    checks.push_back(Check::at_most("overruns", count(f.overruns), double(L.max_overruns)));
    explain(checks.back(), [&] { return why_overruns(w); }, first_overrun(w));
    checks.push_back(Check::at_most("frames_failed", count(f.frames_failed), double(L.max_frames_failed)));
    explain(checks.back(), [&] { return why_frames_failed(w); }, first_failure(w));
    // Both directions, from the line observers; one limit for both (`max_frame_mismatches`).
    for (const bool commands : {true, false}) {
        Check c = Check::at_most(commands ? "commands_delivered_exactly_once" : "responses_delivered_exactly_once",
                                 count(commands ? f.command_mismatches : f.response_mismatches),
                                 double(L.max_frame_mismatches));
        c.detail = exactly_once_detail(w, commands);
        explain(c, [&] {
            const nlohmann::json& first = c.detail["unexplained"];
            if (first.empty()) return std::string();
            const nlohmann::json& e = first[0];
            std::string dir = e.value("direction", std::string());
            for (char& ch : dir)
                if (ch == '_') ch = ' ';
            // A give-up says what the protocol still owed (docs/scenarios.md "Expected drops").
            std::string attempts;
            if (e.contains("attempts"))
                attempts = " after " + std::to_string(e.value("attempts", 0u)) + " attempt(s), " +
                           std::to_string(e.value("hit", 0u)) + " hit by a cause, " +
                           std::to_string(e.value("owed_retries", 0u)) + " retr" +
                           (e.value("owed_retries", 0u) == 1 ? "y" : "ies") + " still owed";
            return "port " + std::to_string(e.value("port", 0u)) + " (" + dir + "): " + e.value("frame", std::string()) +
                   " " + e.value("what", std::string()) + " at " + us(e.value("time_us", 0.0)) + attempts +
                   (first.size() > 1 ? " (and more in the detail)" : "");
        }, first_unexplained(c.detail));
        checks.push_back(std::move(c));
    }
    Check malformed = Check::at_most("main_cpu_malformed_frames", count(f.malformed), 0);
    // Which frame and why: the first few the main CPU dropped (the log has them all).
    const auto& dropped = w.ctl.main.malformed();
    if (!dropped.empty()) {
        malformed.detail = nlohmann::json::array();
        for (std::size_t i = 0; i < dropped.size() && i < 3; ++i)
            malformed.detail.push_back({{"port", dropped[i].port},
                                        {"time_us", dropped[i].time.to_seconds() * 1e6},
                                        {"reason", dropped[i].reason}});
    }
    if (!dropped.empty())
        explain(malformed, [&] {
            return "port " + std::to_string(dropped[0].port) + " (host to controller): the first at " +
                   at_text(dropped[0].time) + ": " + dropped[0].reason;
        }, dropped[0].time);
    checks.push_back(std::move(malformed));
    checks.push_back(Check::at_least("frames_delivered", count(f.frames_delivered), min_delivered));
    explain(checks.back(), [&] { return why_frames_delivered(w, s); });
    if (!L.off.count("char_latency_max_us"))
        for (unsigned p = 0; p < World::kPorts; ++p)
            if (s.ports[p].host != PortScenario::Host::none)
            {
                const Figure limit = char_latency_limit_us(w, s, p);
                checks.push_back(Check::at_most("port" + std::to_string(p) + "_char_latency_max_us",
                                                limit.value ? f.char_latency_max_us[p] : limit, limit.value.value_or(0)));
                explain(checks.back(), [&] { return why_char_latency(w, p); }, w.char_latency_worst[p].stop);
            }
    const double budget = f.budget.value.value_or(0); // the margins are measured only with a budget
    // The paper's rule on every interrupt (section 4-2): every service of every source, on every
    // path, judged on the time it keeps other requests waiting.
    {
        const InterruptRecord* worst = longest_blocking(w);
        const Figure blocking = !f.budget.value ? f.budget
                                : worst         ? Figure::of(worst->blocking_us())
                                                : Figure::none("no interrupt was serviced after start-up");
        checks.push_back(Check::at_most("interrupt_blocking_max_us", blocking, f.budget.value.value_or(0)));
        if (worst) explain(checks.back(), [&] { return why_blocking(*worst, symbol); }, worst->first_isr);
        // Per source: its longest blocking, when, its service, what ran.
        nlohmann::json detail = nlohmann::json::object();
        for (unsigned level = 0; level < 8; ++level)
            if (const InterruptRecord* r = w.probe.longest_blocking(level))
                detail[source_name(level)] = {{"blocking_us", r->blocking_us()},
                                              {"service_us", r->service_us()},
                                              {"first_isr_us", exact_us(r->first_isr)},
                                              {"path", path_names(r->path.data(), r->path_len, symbol)}};
        if (!detail.empty()) checks.back().detail = detail;
    }
    checks.push_back(Check::at_least("table3_margin_us", f.table3_margin_us, L.min_margin_us));
    explain(checks.back(), [&] { return why_margin(f, budget); });
    // The paper's rule (section 4-2): the longest interrupt processing must be shorter than the
    // mean request period. Judged by default; a scenario relaxes it by name or a limit.
    checks.push_back(Check::at_least("table3_worst_margin_us", f.table3_worst_margin_us, L.min_worst_margin_us));
    explain(checks.back(), [&] { return why_worst_margin(w, f, budget); },
            w.rs232_rx_service_us().count() ? std::optional(w.rs232_rx_longest().first_isr) : std::nullopt);
    for (unsigned p = 0; p < World::kPorts; ++p)
        if (const auto& h = w.replay[p]) {
            // The replayed session must draw the recorded answers: same bytes at the same times.
            const std::uint64_t bad = h->counters().out_mismatched + h->out_missing();
            checks.push_back(Check::at_most("replay_port" + std::to_string(p) + "_matches_record", count(bad), 0));
        }
    // A cycle nothing answered reads as an open bus or is dropped: firmware that makes one runs on,
    // wrongly and silently (report.json "bus_errors" says which).
    checks.push_back(Check::at_most("bus_errors", count(f.bus_errors), double(L.max_bus_errors)));
    explain(checks.back(), [&] { return why_bus_errors(w); },
            w.ctl.comm.cpu.bus_errors().first().empty() ? std::nullopt
                                                         : std::optional(w.ctl.comm.cpu.bus_errors().first()[0].time));
    checks.erase(std::remove_if(checks.begin(), checks.end(),
                                [&L](const Check& c) { return L.off.count(c.name) != 0; }),
                 checks.end());
    return checks;
}

} // namespace rcsim
