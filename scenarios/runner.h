// rcsim — runs one scenario on the assembled controller and produces its report.
//
// The report (report.json) and the printed summary follow docs/scenarios.md. Everything in it is a
// function of the scenario and the seed, except `wall_time_s` and `rtf`, which measure the host
// (set `reproducible` to zero them for byte-identical comparisons).
#pragma once

#include "scenarios/scenario.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>

namespace rcsim {

struct RunOptions {
    std::string out_dir;                // "" = write no files
    std::optional<std::uint64_t> seed;  // overrides the scenario's
    std::optional<std::string> rom;     // overrides the scenario's and the built firmware
    bool reproducible = false;          // wall_time_s = rtf = 0
    std::string vcd;                    // "" = no VCD trace
    std::optional<std::string> monitor; // --monitor [HOST:]PORT: serve the remote monitor (docs/monitor.md)
};

/// Builds the system, runs it, fills `report`. Returns 0 when every check holds, 1 when one fails.
/// Throws ConfigError for bad input (exit code 2 at the CLI).
int run_scenario(Scenario scenario, const RunOptions& options, nlohmann::json& report);

/// The human-readable summary of a report.
void print_summary(const nlohmann::json& report, std::ostream& os);

} // namespace rcsim
