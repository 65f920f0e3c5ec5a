// rcsim — the pass/fail checks of a communication run (docs/scenarios.md "Checks"): one place
// where each check is named, given its figure and its limit, and judged.
//
// A check judges a measured figure. A figure with no samples behind it (no RS-232 receive
// interrupt, no DP-RAM chunk, no character) is "not measured": its value is null in report.json
// and the check FAILS with the reason, because a run that measured nothing proves nothing. A
// scenario may switch a check off by name (`checks: {NAME: off}`); switched-off checks are listed in
// report.json "checks_off" and judge nothing.
#pragma once

#include "scenarios/config/check_names.h"
#include "scenarios/world/world.h"
#include "scenarios/config/scenario.h"

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
/// measured), "limit", "reason" (not measured only), "detail" (only when the check has more to
/// say than one figure: the motion checks' wanted and seen states, positions, commands)}.
struct Check {
    enum class Status { passed, failed, not_measured };
    std::string name;
    Status status = Status::failed;
    Figure figure;
    double limit = 0;
    nlohmann::json detail; // null: none

    bool passed() const { return status == Status::passed; }
    static Check at_most(std::string name, const Figure& f, double limit);
    static Check at_least(std::string name, const Figure& f, double limit);
};

nlohmann::json to_json(const Check& c);
const char* status_name(Check::Status s);

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
};

/// Port p's character-latency limit: a character may wait in the RX FIFO; it is lost only when
/// its read comes later than the FIFO can hold the characters behind it (fifo_depth of the
/// port's own character times, as its 82510 is programmed), unless the scenario sets one.
double char_latency_limit_us(const World& b, const Scenario& s, unsigned p);

/// Every communication check that is not switched off, in report order.
std::vector<Check> communication_checks(const World& b, const Scenario& s, const CheckFigures& f);

} // namespace rcsim
