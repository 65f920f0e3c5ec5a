// rcsim sweep | merge | compare: regression timing reports (docs/regression.md).
//   rcsim sweep SWEEP.yaml --out DIR [--jobs N] [--list] [--shard K/N] [--shards N] [--rom FILE] [--symbols FILE[@SEG]] [--coverage]
//   rcsim sweep SWEEP.yaml --out DIR --missing [--shards N]
//   rcsim merge DIR... [--out DIR]
//   rcsim compare BASELINE CURRENT [--tolerances FILE] [--junit FILE] [--html FILE] [--allow-missing]
#include "models/plumbing/cli_range.h"
#include "models/plumbing/config_error.h"
#include "models/plumbing/output_file.h"
#include "models/plumbing/stop_signal.h"
#include "scenarios/debug/rom_symbols.h"
#include "scenarios/sweep/compare.h"
#include "scenarios/sweep/expectation.h"
#include "scenarios/sweep/merge.h"
#include "scenarios/sweep/process_pool.h"
#include "scenarios/sweep/sweep.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <set>
#include <thread>

namespace rcsim {

namespace fs = std::filesystem;
using namespace sweep;

namespace {

std::string command_line(const std::vector<std::string>& argv) {
    std::string s;
    for (const auto& a : argv) s += (s.empty() ? "" : " ") + shell_quote(a);
    return s;
}

/// What the sweep holds against a finished run, "" when nothing. A run that wrote its report is
/// judged by the checks the sweep file expects it to fail; any other by its exit code.
std::string run_problem(const fs::path& run_dir, int exit_code) {
    const bool reported = exit_code == 0 || exit_code == 1 || exit_code == 4;
    if (!reported) return exit_code == 2 ? "bad input" : "exit " + std::to_string(exit_code);
    Expectation judged;
    try {
        const std::vector<RunRecord> runs = collect_runs({run_dir.string()});
        if (runs.empty()) return "neither run.json nor report.json in " + run_dir.string();
        judged = judge_run(runs.front());
    } catch (const ConfigError& e) { // a report cut short: a failed run, not a reason to stop the others
        return e.what();
    }
    if (judged.met()) return "";
    std::string why;
    for (const std::string& w : judged.why) why += (why.empty() ? "" : "; ") + w;
    return why;
}

struct SweepArgs {
    std::string file, out, shard, rom;
    std::string symbols;   // --symbols FILE[@SEG] for every run, absolute once checked
    std::size_t shards = 0;
    unsigned jobs = 0;
    bool list = false;
    bool missing = false;  // print the runs (or, with --shards, the shards) without a completed report
    bool coverage = false; // each run with --coverage; the merge writes DIR/coverage.info
};

/// The argv of one run of the sweep (run_argv), with the sweep's own run options.
std::vector<std::string> sweep_run_argv(const SweepArgs& a, const std::string& exe, const fs::path& dir, const SweepRun& run,
                                        const std::string& rom) {
    std::vector<std::string> argv = run_argv(exe, dir, run, rom);
    if (a.coverage && !run.search) argv.push_back("--coverage"); // a search's runs are many: no coverage
    if (!a.symbols.empty()) argv.insert(argv.end(), {"--symbols", a.symbols});
    return argv;
}

/// How the sweep's runs ended, each noted on stderr as it ends unless it met its expectation.
struct RunTally {
    std::size_t ended = 0, failed = 0, interrupted = 0;

    void count(const std::string& id, const std::string& log, int exit_code, const fs::path& run_dir, Progress& progress) {
        ++ended;
        // One caught in its start-up dies of the signal without a report: that is mark_not_run's.
        if (stop_signal() != 0 && exit_code == 128 + stop_signal() && fs::exists(run_dir / "report.json")) {
            ++interrupted;
            progress.note("run " + id + ": interrupted (" + log + ")");
            return;
        }
        const std::string why = run_problem(run_dir, exit_code);
        if (!why.empty()) {
            ++failed;
            progress.note("run " + id + ": " + why + " (" + log + ")");
        } else if (exit_code == 4) {
            // Nothing judged either way: the summary says which; the sweep does not fail on it.
            progress.note("run " + id + ": inconclusive, a check was not measured (" + log + ")");
        }
    }
};

/// After a stop signal: a run without a report.json either never started or was stopped before
/// its report was written (it died in its start-up, say). Its directory goes back to the inputs
/// the sweep wrote (no half-written outputs), with the marker that says "not run".
void mark_not_run(const Sweep& sweep, const SweepRun& run, const fs::path& dir, bool started) {
    const fs::path run_dir = dir / run.id;
    if (fs::exists(run_dir / "report.json")) return; // completed, or interrupted and says so
    if (started) materialise(sweep, run, dir);
    write_file(run_dir / kNotRunMarker, "not run: the sweep was interrupted before this run completed\n",
               "the not-run marker");
}

/// Whether DIR/<id> holds a completed run: a report with a verdict other than "interrupted".
/// A report cut short is not one either: the run is to be run again.
bool completed(const fs::path& run_dir) {
    std::error_code ec;
    if (!fs::is_regular_file(run_dir / "report.json", ec)) return false;
    try {
        const std::vector<RunRecord> runs = collect_runs({run_dir.string()});
        const std::string status = runs.empty() ? "no report" : run_status(runs.front());
        return status == "passed" || status == "failed" || status == "inconclusive";
    } catch (const ConfigError&) {
        return false;
    }
}

/// --missing: the runs of the sweep that DIR does not hold completed (never run, interrupted,
/// cancelled, or stopped by bad input), one id a line; with --shards N, the shard indices that
/// hold them, comma-separated: the list `sbatch --array=` takes to run just those again. Reads
/// DIR, writes nothing (a shard may still be running there).
int print_missing(const Sweep& sweep, const fs::path& dir, std::size_t shards) {
    std::vector<std::size_t> missing;
    for (std::size_t i = 0; i < sweep.runs.size(); ++i)
        if (!completed(dir / sweep.runs[i].id)) missing.push_back(i);
    if (shards == 0) {
        for (std::size_t i : missing) std::cout << sweep.runs[i].id << "\n";
        return 0;
    }
    std::set<std::size_t> indices; // run i is in shard i mod N (shard_runs)
    for (std::size_t i : missing) indices.insert(i % shards);
    std::string line;
    for (std::size_t k : indices) line += (line.empty() ? "" : ",") + std::to_string(k);
    if (!line.empty()) std::cout << line << "\n";
    return 0;
}

/// Runs this shard's runs `jobs` at a time; returns the sweep's exit code.
int run_sweep(SweepArgs a, bool shards_given) {
    const Sweep sweep = load_sweep(a.file);
    if (a.missing) return print_missing(sweep, fs::absolute(a.out).lexically_normal(), shards_given ? a.shards : 0);
    const Shard shard = shard_from(a.shard, shards_given ? std::optional<std::size_t>(a.shards) : std::nullopt,
                                   [](const char* v) { return std::getenv(v); });
    std::string rom;
    if (!a.rom.empty()) {
        std::error_code ec;
        if (!fs::is_regular_file(a.rom, ec)) throw ConfigError(a.rom, 0, "--rom: no such ROM image");
        rom = fs::absolute(a.rom).lexically_normal().string();
    }
    if (!a.symbols.empty()) {
        // Read once here, as each run would: a bad file is one message, not one failed run each.
        debug::rom_symbols(RomSource{rom, ""}, a.symbols);
        a.symbols = fs::absolute(a.symbols).lexically_normal().string(); // the runs start elsewhere
    }
    const fs::path dir = fs::absolute(a.out).lexically_normal();
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (!fs::is_directory(dir)) throw ConfigError(a.out, 0, "--out: cannot create the directory");
    const auto mine = shard_runs(sweep.runs.size(), shard);
    if (shard.count == 1) remove_stale_runs(sweep, dir);
    for (std::size_t i : mine) materialise(sweep, sweep.runs[i], dir);
    const std::string exe = self_executable();
    if (a.list) {
        for (std::size_t i : mine)
            std::cout << sweep.runs[i].id << "\t" << command_line(sweep_run_argv(a, exe, dir, sweep.runs[i], rom)) << "\n";
        return 0;
    }
    std::vector<Job> jobs;
    for (std::size_t i : mine)
        jobs.push_back({sweep_run_argv(a, exe, dir, sweep.runs[i], rom), (dir / sweep.runs[i].id / "run.log").string()});
    const unsigned parallel = a.jobs ? a.jobs : std::max(1u, std::thread::hardware_concurrency());
    Progress progress(jobs.size(), Progress::interactive_default());
    const auto t0 = std::chrono::steady_clock::now();
    auto elapsed = [&t0] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    RunTally tally;
    install_stop_handlers(); // SIGINT/SIGTERM: start no more runs, stop the running ones (stop_signal.h)
    const auto results = run_jobs(
        jobs, parallel,
        [&](std::size_t j, const JobResult& r, std::size_t done) {
            const SweepRun& run = sweep.runs[mine[j]];
            tally.count(run.id, jobs[j].log, r.exit_code, dir / run.id, progress);
            progress.update(done, tally.failed, elapsed());
        },
        [] { return stop_signal(); });
    const int stopped_by = stop_signal();
    if (stopped_by != 0) {
        const std::size_t completed = tally.ended - tally.interrupted;
        progress.interrupted(stopped_by == SIGINT ? "SIGINT" : "SIGTERM", completed, tally.interrupted, tally.failed,
                             elapsed());
        for (std::size_t j = 0; j < jobs.size(); ++j) mark_not_run(sweep, sweep.runs[mine[j]], dir, results[j].started);
    } else {
        progress.finish(tally.failed, elapsed());
    }
    if (shard.count == 1) {
        merge_runs({dir.string()}, dir);
        std::cout << "summary: " << (dir / "summary.html").string() << "\n";
        if (fs::exists(dir / "coverage.info")) std::cout << "coverage: " << (dir / "coverage.info").string() << "\n";
    } else if (stopped_by == 0) {
        std::cout << "shard " << shard.index << "/" << shard.count << " done; merge when every shard is: rcsim merge "
                  << shell_quote(dir.string()) << "\n";
    }
    if (stopped_by != 0) return 128 + stopped_by; // the shell's "ended by a signal", as `rcsim run`
    return tally.failed ? 1 : 0;
}

void add_sweep(CLI::App& app) {
    auto* cmd = app.add_subcommand("sweep", "Run every combination of a sweep file's axes; merge the reports");
    auto a = std::make_shared<SweepArgs>();
    cmd->add_option("sweep", a->file, "Sweep file (YAML, see docs/regression.md)")->required();
    cmd->add_option("--out", a->out, "Output directory: one DIR/<id>/ per run, DIR/summary.*")->required();
    cmd->add_option("--jobs,-j", a->jobs, "Runs in parallel (default: the number of cores)")->check(whole_in(1, 1024));
    auto* list = cmd->add_flag("--list", a->list, "Write the runs' scenario files and print one line per run: id, command");
    auto* missing = cmd->add_flag("--missing", a->missing,
                                  "Print the runs DIR lacks a completed report of (with --shards N: their shard "
                                  "indices, for sbatch --array); run nothing, write nothing");
    cmd->add_option("--shard", a->shard, "Run every N-th run starting at K (0-based), e.g. 2/8");
    auto* shards = cmd->add_option("--shards", a->shards, "Shard count with JOB_COMPLETION_INDEX (Kubernetes)")
                       ->check(whole_in(1, 1000000));
    cmd->add_option("--rom", a->rom, "ROM image for every run (instead of the built firmware)");
    cmd->add_option("--symbols", a->symbols,
                    "The ROM's symbols for every run: its latency causes, --coverage (FILE[@SEG], docs/tools.md \"Symbols\")");
    cmd->add_flag("--coverage", a->coverage,
                  "Every run with --coverage; their tracefiles merged into DIR/coverage.info (docs/tools.md \"Coverage\")");
    missing->excludes(list);
    cmd->callback([a, shards] {
        int code = 0;
        try {
            code = run_sweep(*a, static_cast<bool>(*shards));
        } catch (const ConfigError& e) {
            std::cerr << "rcsim sweep: " << e.what() << "\n";
            code = 2;
        }
        throw CLI::RuntimeError(code);
    });
}

void add_merge(CLI::App& app) {
    auto* cmd = app.add_subcommand("merge", "Merge sweep run directories into summary.json, summary.csv, summary.html "
                                            "(and their coverage.info files into coverage.info)");
    auto dirs = std::make_shared<std::vector<std::string>>();
    auto out = std::make_shared<std::string>();
    cmd->add_option("dirs", *dirs, "Sweep output directories (their run subdirectories are merged)")->required();
    cmd->add_option("--out", *out, "Where the summary files go (default: the first DIR)");
    cmd->callback([dirs, out] {
        int code = 0;
        try {
            const fs::path o = out->empty() ? fs::path(dirs->front()) : fs::path(*out);
            std::error_code ec;
            if (!out->empty()) fs::create_directories(o, ec);
            std::vector<std::string> unfinished;
            const std::size_t n = merge_runs(*dirs, o, &unfinished);
            // Said, not fatal: the summary lists them too; a cluster task cancelled or failed left them.
            for (const std::string& u : unfinished) std::cerr << "rcsim merge: " << u << "\n";
            std::cout << "merged " << n << " runs: " << (o / "summary.json").string() << ", summary.csv, summary.html"
                      << (fs::exists(o / "coverage.info") ? ", coverage.info" : "") << "\n";
            if (!unfinished.empty())
                std::cout << "incomplete: " << unfinished.size() << " of " << n
                          << " runs did not complete; rcsim sweep SWEEP --out DIR --missing lists what to run again\n";
        } catch (const ConfigError& e) {
            std::cerr << "rcsim merge: " << e.what() << "\n";
            code = 2;
        } catch (const fs::filesystem_error& e) {
            std::cerr << "rcsim merge: " << e.what() << "\n";
            code = 2;
        }
        throw CLI::RuntimeError(code);
    });
}

struct CompareArgs {
    std::string baseline, current, tolerances, junit, html;
    bool allow_missing = false;
};

int run_compare(const CompareArgs& a) {
    const auto rules = a.tolerances.empty() ? default_tolerances() : load_tolerances(a.tolerances);
    auto base = load_run_set(a.baseline);
    auto cur = load_run_set(a.current);
    // Two report.json files are one run each, whatever their scenario names.
    std::error_code ec;
    if (fs::is_regular_file(a.baseline, ec) && fs::is_regular_file(a.current, ec) && base.begin()->first != cur.begin()->first) {
        auto node = cur.extract(cur.begin());
        node.key() = base.begin()->first;
        cur.insert(std::move(node));
    }
    const Comparison c = compare_runs(base, cur, rules, a.allow_missing);
    print_comparison(c, std::cout);
    if (!a.junit.empty()) write_file(a.junit, junit_xml(c));
    if (!a.html.empty()) write_file(a.html, compare_html(c));
    // The summary ends with the paths of what it wrote (issue #51 item 7).
    if (!a.junit.empty()) std::cout << "junit: " << a.junit << "\n";
    if (!a.html.empty()) std::cout << "html:  " << a.html << "\n";
    return c.regression() ? 1 : 0;
}

void add_compare(CLI::App& app) {
    auto* cmd = app.add_subcommand("compare", "Compare runs with a baseline; exit 1 on a regression");
    auto a = std::make_shared<CompareArgs>();
    cmd->add_option("baseline", a->baseline, "Baseline: a report.json or a sweep output directory")->required();
    cmd->add_option("current", a->current, "Current: a report.json or a sweep output directory")->required();
    cmd->add_option("--tolerances", a->tolerances, "Tolerances file (YAML, docs/regression.md)");
    cmd->add_option("--junit", a->junit, "Write JUnit XML here");
    cmd->add_option("--html", a->html, "Write the comparison page here");
    cmd->add_flag("--allow-missing", a->allow_missing, "Runs in only one of the two sets are not regressions");
    cmd->callback([a] {
        int code = 0;
        try {
            code = run_compare(*a);
        } catch (const ConfigError& e) {
            std::cerr << "rcsim compare: " << e.what() << "\n";
            code = 2;
        } catch (const fs::filesystem_error& e) {
            std::cerr << "rcsim compare: " << e.what() << "\n";
            code = 2;
        }
        throw CLI::RuntimeError(code);
    });
}

} // namespace

void add_sweep_commands(CLI::App& app) {
    add_sweep(app);
    add_merge(app);
    add_compare(app);
}

} // namespace rcsim
