// rcsim search: the worst case of one report figure over the axes a real installation leaves free,
// found by an optimiser instead of sampled (docs/search.md). Every point is one `rcsim run` child
// process on the sweep's pool; the best one is kept as a witness that reproduces it alone.
//
//   DIR/runs/<id>/   each run: scenario.yaml, run.json, its reports (as a sweep's run folders)
//   DIR/worst.yaml   the witness: `rcsim run DIR/worst.yaml` gives the same figure, same causes
//   DIR/search.json  {"figure", "direction", "best", "runs", "history": [...], ...}
//   DIR/search.html  best so far against runs, the figure over the two most influential axes, the
//                    witness's cause with a link to its report.html
//   DIR/summary.*    every run's figures (rcsim merge of DIR/runs)
#pragma once

#include "scenarios/search/axes.h"
#include "scenarios/search/optimiser.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace rcsim::search {

struct SearchOptions {
    std::string scenario;
    std::string figure;
    Direction direction = Direction::maximize;
    std::string out;
    std::size_t runs = 64;   // rcsim runs in all, the scenario as written (the base) included
    unsigned jobs = 0;       // at once (0: the number of cores)
    std::uint64_t seed = 1;  // the sample's and the random algorithms' seed
    std::string algorithm;   // "" = the section's, else subplex
    unsigned starts = 0;     // 0 = the section's, else 4
    std::vector<std::string> axes; // --axis PATH=LO..HI: these instead of the defaults
    std::string rom, symbols;      // for every run
    bool as_run = false;           // also put the witness's reports into DIR (a sweep's search entry)
    bool reproducible = false;     // wall time 0 in search.json, as `rcsim run --reproducible`
};

/// One run of the search.
struct Point {
    std::string id, stage;          // stage: base, sample, s1, s2, ...
    std::vector<double> values;     // per axis (none for the base)
    std::optional<double> figure;   // none: not measured, or no report
    std::string verdict;            // the run's verdict, or why it has none ("exit 3")
};

struct SearchResult {
    std::vector<Axis> axes;
    std::vector<Point> history;     // in the order asked: the base, the sample, the streams' rounds
    std::optional<std::size_t> best; // index into history
    double wall_s = 0;
    int stopped_by = 0;             // the signal that stopped it, 0 when it ran its budget
};

/// Runs the search and writes DIR. Throws ConfigError for bad input (exit 2). Returns the exit
/// code: 0, 1 when the witness failed its checks or a run ended without a report, 128 + signal.
int run_search(const SearchOptions& options);

/// The report's figure at `path` (a flattened path, as summary.json names it: dots for keys,
/// [n] for list items). None when it is null; throws ConfigError naming the paths that exist
/// when the report has no such number.
std::optional<double> figure_of(const nlohmann::json& report, const std::string& path);

/// Each axis's share of the figure's variance explained by it alone (the correlation ratio over
/// four equal cells of the axis), 0..1, in axis order; from the runs that have a figure.
std::vector<double> influence(const SearchResult& r);

} // namespace rcsim::search
