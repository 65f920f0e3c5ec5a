// rcsim — a sweep file: one base scenario (or several) and the axes to vary over it; each
// combination is one run with a stable id (docs/regression.md "Sweep files").
//
// A run is materialised as a plain scenario file, DIR/<id>/scenario.yaml, beside DIR/<id>/run.json
// (its id and parameters), so that `rcsim run DIR/<id>/scenario.yaml --out DIR/<id>` reproduces
// it alone: on this machine, under GNU parallel or on a cluster node.
#pragma once

#include <yaml-cpp/yaml.h>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rcsim::sweep {

/// A sweep entry's `search:` (docs/regression.md "Searched worst cases"): the entry's one run is
/// `rcsim search` for this figure; its witness's reports stand for the run.
struct SearchSpec {
    std::string figure;
    bool maximize = true;
    std::size_t runs = 16;
    std::uint64_t seed = 1;
    std::string algorithm; // "" = search's default
};

/// One run of a sweep.
struct SweepRun {
    std::string id;       // stable: entry name, then `label=value` for each axis
    std::string entry;    // the sweep entry it came from
    /// The axis values that made it, in axis order: path -> value (`base` for a list of files).
    std::vector<std::pair<std::string, YAML::Node>> parameters;
    YAML::Node scenario;  // the materialised scenario document
    int line = 0;         // the sweep entry's line, for errors
    /// Every key the sweep set in this run (set: and axes) with the line that set it, so that a
    /// value the scenario refuses is reported at that line.
    std::vector<std::pair<std::string, int>> sources;
    /// The checks this run is expected to fail (`expect_fail`, and `expect_fail_when` for its axis
    /// values), sorted: the sweep judges the run by them, the run's own report does not know them.
    std::vector<std::string> expect_fail;
    std::optional<SearchSpec> search; // the run is a search (an entry with `search:`)
};

struct Sweep {
    std::string file;
    std::string name;
    std::vector<SweepRun> runs;
};

/// Reads a sweep file and expands it into its runs. Throws ConfigError naming file and line.
Sweep load_sweep(const std::string& path);

/// Sets the key `path` ("board.wait_states.rom", "ports[1].data_size", "ports[*].count") of the
/// mapping `doc` to `value`: intermediate mappings are created, list elements must exist, `[*]`
/// sets every element. Throws std::invalid_argument saying why the path does not fit `doc`.
void set_path(YAML::Node doc, const std::string& path, const YAML::Node& value);

/// Input files a scenario names are relative to the scenario file (in `dir`); a materialised copy
/// lives elsewhere, so they become absolute. Output files (logs, records) stay relative: they land
/// in the run's directory.
void absolutise_inputs(YAML::Node doc, const std::filesystem::path& dir);

/// The scenario file text of a run (its materialised document).
std::string scenario_text(const SweepRun& run);

/// run.json: {"id", "entry", "parameters": {path: value}} with numbers and booleans typed, and
/// "expect_fail": [check, ...] when the run expects checks to fail.
nlohmann::json run_json(const SweepRun& run);

/// A YAML scalar as JSON: integer, number, boolean, null or string.
nlohmann::json scalar_json(const YAML::Node& scalar);

/// Writes DIR/<id>/scenario.yaml and run.json (replacing whatever a previous run left there) and
/// checks that the scenario loads. Throws ConfigError naming the sweep file and the run.
void materialise(const Sweep& sweep, const SweepRun& run, const std::filesystem::path& dir);

/// Removes the run directories under `dir` (those with a run.json) that are not runs of `sweep`:
/// what an earlier version of the sweep left, which a merge would otherwise pick up. Only an
/// unsharded sweep does this; a shard touches nothing but its own runs.
void remove_stale_runs(const Sweep& sweep, const std::filesystem::path& dir);

/// Which runs this process runs: every `count`-th, starting at `index` (0-based).
struct Shard {
    std::size_t index = 0, count = 1;
};

/// The shard from `--shard K/N`, else from SLURM_ARRAY_TASK_ID (less SLURM_ARRAY_TASK_MIN) and
/// SLURM_ARRAY_TASK_COUNT, else JOB_COMPLETION_INDEX (a Kubernetes Indexed Job) with `--shards N`,
/// else 0/1. `env` looks a variable up (std::getenv in the program). Throws ConfigError for a
/// malformed value, naming it.
Shard shard_from(const std::string& arg, std::optional<std::size_t> shards,
                 const std::function<const char*(const char*)>& env);

/// The run indices of `total` that belong to `shard`.
std::vector<std::size_t> shard_runs(std::size_t total, const Shard& shard);

/// A shell word: as is when it holds only safe characters, else in single quotes.
std::string shell_quote(const std::string& word);

/// The argv that runs `run` alone: EXE run DIR/<id>/scenario.yaml --out DIR/<id> --reproducible
/// [--rom ROM]; for a search entry EXE search DIR/<id>/scenario.yaml --maximize FIGURE --runs N
/// --seed S --jobs 1 --out DIR/<id> --reproducible --as-run [--algorithm A] [--rom ROM].
std::vector<std::string> run_argv(const std::string& exe, const std::filesystem::path& dir, const SweepRun& run,
                                  const std::string& rom);

} // namespace rcsim::sweep
