// rcsim — runs one scenario on the assembled controller and produces its report.
//
// The report (report.json) and the printed summary follow docs/scenarios.md. Everything in it is a
// function of the scenario and the seed, except `wall_time_s` and `rtf`, which measure the host
// (set `reproducible` to zero them for byte-identical comparisons).
#pragma once

#include "scenarios/config/scenario.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>

namespace rcsim {

class World;

struct RunOptions {
    std::string out_dir;                // "" = write no files
    std::optional<std::uint64_t> seed;  // overrides the scenario's
    std::optional<RomSource> rom;       // overrides the scenario's and the built firmware
    bool reproducible = false;          // wall_time_s = rtf = 0
    std::string vcd;                    // "" = no VCD trace
    /// interrupts.csv, a row per interrupt: plain, gzip-compressed (interrupts.csv.gz), none, or
    /// chosen by the run's length (docs/scenarios.md "Output files").
    enum class Rows { automatic, plain, gzip, none } interrupt_rows = Rows::automatic;
    /// Called with the assembled world (ROM loaded) just before the simulation starts: the gdb
    /// stub attaches here (scenarios/cli/gdb_run.h). Empty: nothing.
    std::function<void(World&)> on_world;
    /// Called with the world once the simulation and its drain are over, before the report is
    /// built: figures the report does not hold (`rcsim world system`). Empty: nothing.
    std::function<void(World&)> on_finished;
    std::string trace;                  // "" = no Trace Event Format file (scenarios/trace/perfetto_trace.h)
    bool profile = false;               // the cycle profiler (scenarios/trace/profile_run.h); needs out_dir
    std::string symbols;                // --symbols FILE[@SEG]: the ROM's symbols ("" = debug::rom_symbols decides)
    bool coverage = false;              // coverage.info of the comm ROM (scenarios/coverage/coverage_run.h); needs out_dir
    std::optional<std::string> monitor; // --monitor [HOST:]PORT: serve the remote monitor (docs/monitor.md)
    std::optional<std::string> modbus;  // --modbus [HOST:]PORT: serve Modbus TCP (docs/monitor.md)
    /// The progress line on stderr while it is a terminal (scenarios/run/run_progress.h): `rcsim
    /// run` only; the commands that run scenarios for figures of their own print theirs.
    bool progress = false;
    /// --bound: the static bound of the run's ROM (docs/tools.md "Bound") in report.json "bound",
    /// report.html and DIR/bound.json; a scenario's `checks: {bound_service_us: on}` implies it.
    bool bound = false;
    std::string annotations;            // --annotations FILE ("" = the built firmware's own, or none)
    std::string witness;                // --witness SEARCH_DIR/search.json: report.json bound.*.searched_us
};

/// Builds the system, runs it, fills `report`. Returns 0 when every check holds, 1 when one fails.
/// Throws ConfigError for bad input (exit code 2 at the CLI).
int run_scenario(Scenario scenario, const RunOptions& options, nlohmann::json& report);

/// The human-readable summary of a report.
void print_summary(const nlohmann::json& report, std::ostream& os);

/// The last lines of `rcsim run`'s output: where its reports are (report.json, report.html, a
/// motion run's included; bound.json with the bound). Nothing when the run wrote no files.
void print_report_paths(const nlohmann::json& report, const std::string& out_dir, std::ostream& os);

} // namespace rcsim
