// rcsim — the pass/fail checks of a communication run (docs/scenarios.md "Checks"): one place
// where each check is named, given its figure and its limit, and judged.
#pragma once

#include "scenarios/bench.h"
#include "scenarios/scenario.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace rcsim {

/// One verdict as report.json shows it: {"name", "passed", "value", "limit"}.
struct Check {
    std::string name;
    bool passed = false;
    double value = 0;
    double limit = 0;
};

nlohmann::json to_json(const Check& c);

/// The figures the communication checks judge, gathered from the bench and the report.
struct CheckFigures {
    std::uint64_t overruns = 0, frames_failed = 0, frames_delivered = 0, frame_mismatches = 0;
    std::uint64_t malformed = 0;   // frames the main CPU could not decode
    double char_latency_max_us = 0; // over all ports
    double char_latency_limit_us = 0;
    double table3_margin_us = 0;
};

/// The character-latency limit: a character may wait in the RX FIFO; it is lost only when its read
/// comes later than the FIFO can hold the characters behind it (fifo_depth character times).
double char_latency_limit_us(const Bench& b, const Scenario& s);

/// Every communication check, in report order.
std::vector<Check> communication_checks(const Bench& b, const Scenario& s, const CheckFigures& f);

} // namespace rcsim
