// rcsim search: the worst case of a report figure, searched over what a real installation leaves
// free (docs/search.md).
//   rcsim search SCENARIO --maximize FIGURE | --minimize FIGURE --out DIR [--runs N] [--jobs J]
//                [--seed S] [--algorithm NAME] [--starts K] [--axis PATH=LO..HI]... [--rom FILE]
//                [--symbols FILE[@SEG]] [--reproducible] [--as-run]
#include "models/plumbing/cli_range.h"
#include "models/plumbing/config_error.h"
#include "scenarios/debug/rom_symbols.h"
#include "scenarios/search/search.h"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>
#include <memory>

namespace rcsim {

namespace fs = std::filesystem;

void add_search_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("search", "Search the axes a real installation leaves free for the worst case of a "
                                             "report figure; keep the witness (docs/search.md)");
    auto o = std::make_shared<search::SearchOptions>();
    auto maximize = std::make_shared<std::string>(), minimize = std::make_shared<std::string>();
    cmd->add_option("scenario", o->scenario, "Scenario file (YAML, docs/scenarios.md)")->required();
    auto* max = cmd->add_option("--maximize", *maximize, "The report.json figure to make as large as possible, "
                                                        "e.g. interrupts.rs232_0.latency_us.max");
    auto* min = cmd->add_option("--minimize", *minimize, "The figure to make as small as possible, e.g. table3.worst_margin_us");
    max->excludes(min);
    cmd->add_option("--out", o->out, "Output directory: DIR/runs/<id>/, worst.yaml, search.json, search.html")->required();
    cmd->add_option("--runs", o->runs, "Runs in all, the scenario as written included (default 64)")->check(whole_in(2, 100000));
    cmd->add_option("--jobs,-j", o->jobs, "Runs in parallel (default: the number of cores)")->check(whole_in(1, 1024));
    cmd->add_option("--seed", o->seed, "Seed of the sample and the random algorithms (default 1)");
    std::string names;
    for (const auto& a : search_algorithms()) names += (names.empty() ? "" : ", ") + a;
    cmd->add_option("--algorithm", o->algorithm, "NLopt algorithm: " + names + " (default: subplex)")
        ->check(CLI::IsMember(search_algorithms()));
    cmd->add_option("--starts", o->starts, "Optimiser streams after the sample (default 4)")->check(whole_in(1, 64));
    cmd->add_option("--axis", o->axes, "PATH=LO..HI: search this axis (repeatable; replaces the default axes)");
    cmd->add_option("--rom", o->rom, "ROM image for every run (instead of the scenario's)");
    cmd->add_option("--symbols", o->symbols, "The ROM's symbols for every run (FILE[@SEG], docs/tools.md \"Symbols\")");
    cmd->add_flag("--reproducible", o->reproducible, "Wall time 0 in search.json and every run's report");
    cmd->add_flag("--as-run", o->as_run, "Also put the witness's reports into DIR (a sweep's search entry)");
    cmd->callback([o, maximize, minimize, max, min] {
        int code = 0;
        try {
            if (!*max && !*min) throw ConfigError("give the figure to search: --maximize FIGURE or --minimize FIGURE");
            o->figure = *max ? *maximize : *minimize;
            o->direction = *max ? search::Direction::maximize : search::Direction::minimize;
            if (o->figure.empty()) throw ConfigError("the figure path is empty");
            if (!o->symbols.empty()) {
                debug::rom_symbols(RomSource{o->rom, ""}, o->symbols); // a bad file: one message, not one per run
                o->symbols = fs::absolute(o->symbols).lexically_normal().string();
            }
            code = search::run_search(*o);
        } catch (const ConfigError& e) {
            std::cerr << "rcsim search: " << e.what() << "\n";
            code = 2;
        }
        throw CLI::RuntimeError(code);
    });
}

} // namespace rcsim
