// rcsim — a current set of runs against a baseline, figure by figure and check by check, under
// tolerances (docs/regression.md "Comparing").
//
// Default rule: a figure that is a function of the simulation alone must be identical; the
// host-dependent ones (wall_time_s, rtf, realtime.*) are ignored unless a tolerance names them.
// A check that passed and now fails is a regression whatever the tolerances.
#pragma once

#include "scenarios/sweep/merge.h"

#include <nlohmann/json.hpp>

#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace rcsim::sweep {

/// One rule of a tolerances file; the first rule whose patterns match a figure applies.
struct Tolerance {
    std::string figure = "*"; // glob over the figure path: * any run of characters, ? one
    std::string run = "*";    // glob over the run id
    double abs = 0;           // |current - baseline| <= abs passes
    double rel = 0;           // or |current - baseline| <= rel * |baseline|
    enum class Better { none, lower, higher } better = Better::none; // a change beyond tolerance this way
                                                                     // is an improvement
    bool ignore = false;
    std::string origin; // "tolerances.yaml:12", or "default"
};

/// Reads a tolerances file (`tolerances: [{figure, run, abs, rel, better, ignore}]`), then adds the
/// default rules. Throws ConfigError naming file and line.
std::vector<Tolerance> load_tolerances(const std::string& path);
/// The default rules alone: host-dependent figures ignored, everything else exact.
std::vector<Tolerance> default_tolerances();

/// Which way a figure is better when no tolerance says: the direction of the check that limits it
/// (scenarios/verdict/checks.cpp: `<=` lower, `>=` higher) or of the time it measures (a Table 3
/// time, a latency, a service time: lower; a margin: higher); none for every other figure.
Tolerance::Better figure_direction(const std::string& key);

/// `*` matches any run of characters (dots and brackets too), `?` one; everything else itself.
bool glob_match(const std::string& pattern, const std::string& text);

/// How a figure or a check changed against the baseline; not the run's own Verdict
/// (scenarios/verdict/checks.h). change_name() is what the reports print for it.
enum class Change { same, within, ignored, improvement, regression, added };
const char* change_name(Change v);

struct FigureDiff {
    std::string key;
    nlohmann::json baseline, current; // absent side: discarded json (see has_*)
    bool has_baseline = true, has_current = true;
    std::optional<double> delta, rel; // numbers on both sides; rel when baseline != 0
    Change change = Change::same;
    std::string rule; // where the tolerance came from
    // Which way is better, for colouring the delta: the rule's `better`, else figure_direction().
    Tolerance::Better better = Tolerance::Better::none;
};

struct CheckDiff {
    std::string name;
    std::optional<bool> baseline, current; // passed; absent when the report has no such check
    Change change = Change::same;
};

struct RunDiff {
    std::string id;
    enum class State { matched, missing, extra, no_report } state = State::matched;
    std::vector<FigureDiff> figures;
    std::vector<CheckDiff> checks;
    bool regression = false; // any figure or check regressed, or the run is missing/extra/unfinished
};

struct Comparison {
    std::vector<RunDiff> runs;
    bool allow_missing = false;
    std::map<Change, std::size_t> figure_counts, check_counts;
    std::size_t missing = 0, extra = 0, no_report = 0;
    bool regression() const;
};

/// A set of runs by id: a report.json file (one run, its id the report's scenario name), a run
/// directory, or a sweep output directory (one run per subdirectory). Throws ConfigError.
std::map<std::string, RunRecord> load_run_set(const std::string& path);

Comparison compare_runs(const std::map<std::string, RunRecord>& baseline, const std::map<std::string, RunRecord>& current,
                        const std::vector<Tolerance>& tolerances, bool allow_missing);

/// The family a figure is grouped in: `interrupts.<source>`, `ports[<n>]`, else its first name
/// (`table3`, `comm_cpu`, `main_cpu`, ...).
std::string figure_family(const std::string& key);

/// Where a change ranks for a reader, most telling first (docs/regression.md "Comparing"): a run
/// missing or unfinished, a check that flipped, the budget (Table 3), interrupt latency and
/// service per source (max, p99, mean), delivery counts, then every other figure.
enum class Rank { run, check, budget, latency, delivery, other };
Rank rank_of(const std::string& figure_key);

/// The console report: counts, then the regressions and improvements ranked (Rank): the rows
/// above Rank::other one per figure or check (at most `rows`), the other figures one line per
/// family with their count.
void print_comparison(const Comparison& c, std::ostream& os, std::size_t rows = 25);
/// JUnit XML: one testsuite per run; in it one testcase for the run's presence, one per check, and
/// one per figure family (failing with the family's regressions listed).
std::string junit_xml(const Comparison& c);
/// One self-contained HTML page: the console report, the regressions and improvements ranked
/// (the other figures collapsed per family), histograms of the worst-changed figures, every run
/// side by side.
std::string compare_html(const Comparison& c);

} // namespace rcsim::sweep
