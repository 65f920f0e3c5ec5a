// rcsim — `rcsim cputest`: runs SingleStepTests 8086 vectors against the core (see comm_cpu/i8086/sst.h).
#include "comm_cpu/i8086/sst.h"
#include "models/plumbing/cli_range.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace rcsim {
namespace {

struct CputestOptions {
    int level = 1;
    std::string json_out;
    std::string status;   // only files whose metadata status is this (empty: all)
    std::string metadata; // metadata.json (default: beside the first input)
    std::vector<std::string> paths;
    double min_rate = 100.0; // percent of tests that must pass at `level` for exit code 0
    std::size_t diff = 0;    // side-by-side traces of this many failing tests per file
    bool quiet = false;      // totals only
};

int run_cputest(const CputestOptions& o) {
    using namespace rcsim::i8086::sst;
    std::vector<std::string> files;
    Metadata meta;
    try {
        files = collect(o.paths);
        // An empty or wrong folder must not pass as "0 passed, 0 failed".
        if (files.empty()) {
            std::string where;
            for (const auto& p : o.paths) where += (where.empty() ? "" : ", ") + p;
            throw InputError(where + ": no SingleStepTests files (*.json, *.json.gz) found");
        }
        std::string mpath = o.metadata;
        if (mpath.empty() && !o.paths.empty()) {
            namespace fs = std::filesystem;
            fs::path p = o.paths.front();
            fs::path dir = fs::is_directory(p) ? p : p.parent_path();
            if (fs::exists(dir / "metadata.json")) mpath = (dir / "metadata.json").string();
        }
        if (!mpath.empty()) meta = Metadata::load(mpath);
        else if (!o.status.empty()) throw InputError("--status needs metadata.json (none found; use --metadata)");
    } catch (const InputError& e) {
        std::cerr << "cputest: " << e.what() << "\n";
        return 2;
    }
    Runner runner;
    runner.set_diff(o.diff, o.level >= 2 ? o.level : 3);
    std::size_t passed = 0, failed = 0;
    nlohmann::json report = nlohmann::json::array();
    std::size_t tot[4] = {0, 0, 0, 0}, total = 0;
    for (const auto& f : files) {
        FileResult r;
        try {
            // Files with no test of the status asked for are not even read.
            if (!o.status.empty() && !meta.lookup_file(f).has(o.status)) continue;
            r = runner.run_file(f, meta, o.status);
        } catch (const InputError& e) {
            std::cerr << "cputest: " << e.what() << "\n";
            return 2;
        }
        // (a file whose status is by reg and has no test of the one asked for: nothing ran)
        if (!o.status.empty() && (r.status != o.status || r.tests == 0)) continue;
        total += r.tests;
        for (int l = 1; l <= 3; ++l) tot[l] += r.pass[l];
        if (!o.quiet) {
            std::printf("%-8s %-12s L1 %4zu/%-4zu L2 %4zu/%-4zu L3 %4zu/%-4zu\n", r.stem.c_str(), r.status.c_str(),
                        r.pass[1], r.tests, r.pass[2], r.tests, r.pass[3], r.tests);
            if (r.pass[o.level] != r.tests)
                std::printf("         first failure: %s\n", r.first_failure[o.level].c_str());
            for (const auto& d : r.diffs) std::printf("%s", d.c_str());
        }
        passed += r.pass[o.level];
        failed += r.tests - r.pass[o.level];
        report.push_back({{"file", r.stem}, {"status", r.status}, {"tests", r.tests},
                          {"level1", r.pass[1]}, {"level2", r.pass[2]}, {"level3", r.pass[3]},
                          {"first_failure", {r.first_failure[1], r.first_failure[2], r.first_failure[3]}}});
    }
    auto pct = [&](std::size_t n) { return total ? 100.0 * double(n) / double(total) : 0.0; };
    std::printf("totals: L1 %zu/%zu (%.2f%%)  L2 %zu/%zu (%.2f%%)  L3 %zu/%zu (%.2f%%)\n", tot[1], total,
                pct(tot[1]), tot[2], total, pct(tot[2]), tot[3], total, pct(tot[3]));
    if (!o.json_out.empty()) {
        std::ofstream out(o.json_out);
        if (!out) {
            std::cerr << "cputest: cannot write " << o.json_out << "\n";
            return 2;
        }
        out << nlohmann::json{{"level", o.level}, {"passed", passed}, {"failed", failed}, {"files", report}}.dump(1)
            << "\n";
    }
    std::printf("%zu passed, %zu failed\n", passed, failed);
    const double rate = passed + failed ? 100.0 * double(passed) / double(passed + failed) : 100.0;
    return rate + 1e-9 >= o.min_rate ? 0 : 1;
}

} // namespace

void add_cputest_command(CLI::App& app) {
    auto o = std::make_shared<CputestOptions>();
    auto* cmd = app.add_subcommand("cputest", "Run SingleStepTests 8086 vectors (.json/.json.gz files or folders)");
    cmd->add_option("--level", o->level, "1 registers+RAM, 2 cycle count, 3 per-cycle trace")
        ->check(whole_in(1, 3));
    cmd->add_option("--json", o->json_out, "Write per-file results as JSON");
    cmd->add_option("--status", o->status, "Only files whose metadata.json status is this (e.g. normal)");
    cmd->add_option("--metadata", o->metadata, "metadata.json (default: beside the first PATH)");
    cmd->add_option("--min-rate", o->min_rate, "Pass rate in percent needed for exit code 0 (default 100)")
        ->check(real_in(0.0, 100.0));
    cmd->add_option("--diff", o->diff,
                    "Print expected | emulated per-cycle traces of the first N failing tests per file "
                    "(at --level 2 or 3; first differing cycle marked)");
    cmd->add_flag("--quiet", o->quiet, "Print only the totals");
    cmd->add_option("PATH", o->paths, "Test files or folders")->required();
    cmd->callback([o] {
        const int rc = run_cputest(*o);
        std::fflush(stdout);
        // rcsim_main maps every parse-time error to 2; the documented 1/2 codes exit here.
        if (rc != 0) std::exit(rc);
    });
}

} // namespace rcsim
