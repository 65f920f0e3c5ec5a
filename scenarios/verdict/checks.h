// rcsim — the pass/fail checks of a communication run (docs/scenarios.md "Checks"): one place
// where each check is named, given its figure, its relation and limit, and judged; and the run's
// verdict from its checks.
//
// A check judges a measured figure. A figure with no samples behind it (no RS-232 receive
// interrupt, no DP-RAM chunk, no character) is "not measured": its value is null in report.json,
// with the reason. It is neither a pass nor a failure: a run where no check failed but one was not
// measured is INCONCLUSIVE (exit 4), because a run that measured nothing proves nothing either
// way. A scenario may switch a check off by name (`checks: {NAME: off}`); switched-off checks are
// listed in report.json "checks_off" and judge nothing.
#pragma once

#include "scenarios/config/check_names.h"
#include "scenarios/world/world.h"
#include "scenarios/config/scenario.h"
#include "scenarios/verdict/latency_causes.h"

#include <nlohmann/json.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace rcsim {

/// A figure as the checks see it: a value, or the reason there is none.
struct Figure {
    std::optional<double> value;
    std::string reason; // why it is not measured (value empty)

    static Figure of(double v) { return {v, {}}; }
    static Figure none(std::string why) { return {std::nullopt, std::move(why)}; }
};

/// One verdict as report.json shows it:
/// {"name", "passed", "status": "passed"|"failed"|"not measured", "value" (null when not
/// measured), "relation": "<="|">=", "limit", "reason" (not measured only), "why" and "at_us"
/// (failed, when the check can say where and when), "detail" (only when the check has more to say than one
/// figure: the offending events, the motion checks' wanted and seen states)}.
struct Check {
    enum class Status { passed, failed, not_measured };
    /// value <= limit (at_most) or value >= limit (at_least).
    enum class Relation { at_most, at_least };
    std::string name;
    Status status = Status::failed;
    Relation relation = Relation::at_most;
    Figure figure;
    double limit = 0;
    nlohmann::json detail; // null: none
    /// A failed check in words: what, where (port, direction) and when (simulated time) of the
    /// first offending events; "" when the figure says it all. report.json "why".
    std::string why;
    /// When the first offending event happened (report.json "at_us"; report.html draws the
    /// interrupt timeline around it); none when the check has no single time.
    std::optional<sc_core::sc_time> at;

    bool passed() const { return status == Status::passed; }
    static Check at_most(std::string name, const Figure& f, double limit);
    static Check at_least(std::string name, const Figure& f, double limit);
};

nlohmann::json to_json(const Check& c);
const char* status_name(Check::Status s);
/// "<=" or ">=", as the summary and report.html print the relation.
const char* relation_symbol(Check::Relation r);

/// The verdict of a run: FAILED when a check failed; else INCONCLUSIVE when a check was not
/// measured; else PASSED. A run a signal stopped is INTERRUPTED whatever its checks say (they
/// judge what completed).
enum class Verdict { passed, failed, inconclusive, interrupted };
struct RunVerdict {
    Verdict verdict = Verdict::passed;
    std::string reason; // one line: what failed, or what was not measured and why; "" when passed
};
/// `checks` as report.json holds them (each with "name", "status", "reason"); `stop_signal` the
/// signal that stopped the run, 0 when none; `idle` why the scenario gave the controller nothing
/// to measure, if it did not ("no host sent traffic"), which leads an INCONCLUSIVE reason.
RunVerdict judge_run(const nlohmann::json& checks, int stop_signal, const std::string& idle = "");
const char* verdict_name(Verdict v); // "passed", "failed", "inconclusive", "interrupted"
/// 0 passed, 1 failed, 4 inconclusive, 128 + the signal when interrupted.
int exit_code_of(const RunVerdict& v, int stop_signal);
/// report.json's "verdict", "verdict_reason" and "passed" (true only for PASSED).
void put_verdict(nlohmann::json& report, const RunVerdict& v);

/// The figures the communication checks judge, gathered from the world and the report.
struct CheckFigures {
    std::uint64_t overruns = 0, frames_failed = 0, frames_delivered = 0;
    // The line observers' sequence comparisons, all ports (LineObserver, SequenceMatcher).
    std::uint64_t command_mismatches = 0, response_mismatches = 0;
    std::uint64_t malformed = 0; // frames the main CPU could not decode
    std::uint64_t bus_errors = 0; // 8086 bus cycles that found no memory or device (Cpu8086::bus_errors())
    std::uint64_t traffic_ports = 0; // ports whose host generates commands by itself
    std::array<Figure, World::kPorts> char_latency_max_us; // per port; only ports with a host
    Figure table3_margin_us, table3_worst_margin_us;
    Figure budget; // the Table 3 budget, us: not measured before the firmware programmed its 82510s
};

/// Port p's character-latency limit: a character may wait in the RX FIFO; it is lost only when
/// its read comes later than the FIFO can hold the characters behind it (fifo_depth of the
/// port's own character times, as its 82510 is programmed), unless the scenario sets one. None
/// (the reason) while the firmware has not programmed the port's character format.
Figure char_latency_limit_us(const World& w, const Scenario& s, unsigned p);

/// Every communication check that is not switched off, in report order. `symbol` names the code
/// addresses in the explanations (may be empty: addresses).
std::vector<Check> communication_checks(const World& w, const Scenario& s, const CheckFigures& f,
                                        const SymbolOf& symbol = {});

} // namespace rcsim
