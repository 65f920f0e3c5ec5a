// rcsim — the runs of a sweep read back from their directories, and the summary of them all
// (summary.json, summary.csv, summary.html; docs/regression.md "Merging").
//
// Everything here depends only on the set of runs, never on the order the directories are named
// or read in, or on where they live: merging the same runs gives the same bytes.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rcsim::sweep {

/// One run directory: its id, run.json (absent for a plain `rcsim run --out` directory) and
/// report.json (absent when the run did not finish).
struct RunRecord {
    std::string id;
    std::filesystem::path dir;
    nlohmann::json meta;                  // run.json, or {}
    std::optional<nlohmann::json> report; // report.json
};

/// Reads a JSON file; a syntax error is a ConfigError naming the file and line.
nlohmann::json read_json_file(const std::filesystem::path& file);

/// The run directories under each of `dirs` (every subdirectory with a run.json or report.json),
/// sorted by id. The same id twice is a ConfigError naming both directories.
std::vector<RunRecord> collect_runs(const std::vector<std::string>& dirs);

/// The order of runs in every summary and comparison: ids compared as text, except that where
/// both have a number at the same place (`seed=2`, `x=-0.5`: digits with an optional sign after
/// `=`, fraction and exponent) the numbers compare by value: seed=1, 2, 10, 11; text axes as text.
bool run_id_less(const std::string& a, const std::string& b);

/// One figure: its path in report.json ("table3.margin_us", "ports[0].overruns") and value.
using Figures = std::vector<std::pair<std::string, nlohmann::json>>;

/// Every scalar figure of a report, flattened by path in the report's key order: numbers,
/// booleans and nulls ("not measured"). Strings (names, reasons, warnings), the checks (compared
/// by name, see report_checks) and the overall `passed` are left out.
Figures flatten_figures(const nlohmann::json& report);

/// The checks of a report by name: {passed, value, limit[, status]}.
std::vector<std::pair<std::string, nlohmann::json>> report_checks(const nlohmann::json& report);

/// The file an interrupted sweep leaves in the directory of each run it did not complete (never
/// started, or stopped before its report was written, whose outputs it removed): "not run".
extern const char* const kNotRunMarker;

/// The report's verdict ("passed", "failed" = a check failed, "inconclusive", "interrupted"),
/// else "not run" (kNotRunMarker) or "no report" (the run did not finish).
std::string run_status(const RunRecord& run);

/// summary.json: {runs, passed, failed, "no report", outcomes: {outcome: count}, "results": [{id, entry,
/// status, parameters, figures, checks, expected_failures, outcome, outcome_why}]}: `status` is the
/// run's own verdict, `outcome` the sweep's judgement of it (scenarios/sweep/expectation.h).
nlohmann::json summary_json(const std::vector<RunRecord>& runs);

/// summary.csv: one row per run: id, status, parameters, every figure, every check (PASS/FAIL),
/// expected_failures (space-separated), outcome.
std::string summary_csv(const nlohmann::json& summary);

/// summary.html: the runs table and, per numeric parameter, the headline figures against it.
std::string summary_html(const nlohmann::json& summary);

/// Writes OUT/summary.{json,csv,html} for the runs under `dirs`, and OUT/coverage.info, the runs'
/// coverage.info files merged (scenarios/coverage/tracefile.h), when any has one (a malformed one
/// is a ConfigError naming it). Returns the runs merged. `unfinished`, when given, receives one
/// line per run that did not complete ("run ID: not run (DIR)", interrupted, no report): what a
/// cancelled or failed cluster task left (docs/regression.md "On a cluster").
std::size_t merge_runs(const std::vector<std::string>& dirs, const std::filesystem::path& out,
                       std::vector<std::string>* unfinished = nullptr);

/// A number as the summaries print it: the shortest text that reads back as the same double.
std::string number_text(const nlohmann::json& v);

} // namespace rcsim::sweep
