// rcsim bound ROM [--symbols MAP] [--annotations FILE] [--scenario SCENARIO] --out DIR
//
// The static bound of a ROM's interrupt paths (docs/tools.md "Bound"): runs SCENARIO with the ROM
// only until start-up has installed the interrupt vectors, bounds every source's service,
// blocking time and latency from the ROM's bytes, writes DIR/bound.json and DIR/bound.txt and
// prints the text. Exit 0 when every blocking bound fits the budget, 1 when one does not, 2 for
// bad input (an unbounded loop included: its message names the annotation line to add).
#include "models/plumbing/config_error.h"
#include "models/plumbing/output_file.h"
#include "scenarios/run/bound_inputs.h"
#include "scenarios/run/bound_report.h"
#include "scenarios/run/failure.h"
#include "scenarios/run/runner.h"
#include "scenarios/verdict/judge.h"
#include "scenarios/world/world.h"

#include <CLI/CLI.hpp>
#include <systemc>

#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#ifndef RCSIM_DEFAULT_SCENARIO
#define RCSIM_DEFAULT_SCENARIO "scenarios/three_ports_9600.yaml"
#endif

namespace rcsim {

namespace {

/// How long the scenario runs: the shipped firmware enables interrupts some milliseconds after
/// the reset; the vectors are read then, and the budget once every 82510 is programmed.
constexpr double kStartupS = 0.05;

struct BoundArgs {
    std::string rom, symbols, annotations, scenario = RCSIM_DEFAULT_SCENARIO, out;
};

/// Runs the scenario briefly for the vectors and the budget; bounds; writes and prints.
int bound_rom(const BoundArgs& a) {
    const RomSource rom{a.rom, ""};
    const debug::RomSymbols symbols = debug::rom_symbols(rom, a.symbols); // bad input before the run
    std::vector<bound::Annotation> annotations = run_annotations(rom, a.annotations, symbols);
    Scenario s = load_scenario(a.scenario);
    s.duration_s = kStartupS;
    s.drain_s = 0;
    s.checks.on.clear(); // the bound is this command's; the run is only for the vectors
    RunOptions opt;
    opt.rom = rom;
    opt.symbols = a.symbols;
    opt.interrupt_rows = RunOptions::Rows::none;
    std::shared_ptr<VectorCapture> vectors;
    Figure budget = Figure::none("the run did not end");
    opt.on_world = [&vectors](World& w) { vectors = std::make_shared<VectorCapture>(w); };
    opt.on_finished = [&budget, &s](World& w) { budget = budget_figure(w, s); };
    nlohmann::json report;
    run_scenario(s, opt, report);
    std::ostringstream ran;
    ran << kStartupS * 1e3 << " ms of " << a.scenario;
    if (!vectors || !vectors->captured()) throw ConfigError("the firmware never enabled interrupts in " + ran.str());
    if (!budget.value) throw ConfigError("the budget is not measured after " + ran.str() + ": " + budget.reason);
    const bound::Result result =
        bound::analyse(bound_inputs(rom, symbols, std::move(annotations), *vectors, s.board, *budget.value, ran.str()));
    std::ostringstream text;
    write_bound_text(result, text);
    const std::filesystem::path out = a.out;
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    if (!std::filesystem::is_directory(out)) throw ConfigError("--out '" + a.out + "': cannot create the folder");
    write_file(out / "bound.json", bound::to_json(result).dump(2) + "\n", "bound.json");
    write_file(out / "bound.txt", text.str(), "bound.txt");
    std::cout << text.str() << "bound: " << (out / "bound.json").string() << "\n";
    return result.fits() ? kExitPassed : kExitCheckFailed;
}

} // namespace

void add_bound_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("bound", "The static worst case of every interrupt path of a ROM, against the budget "
                                            "(DIR/bound.json, DIR/bound.txt; docs/tools.md \"Bound\")");
    auto a = std::make_shared<BoundArgs>();
    cmd->add_option("rom", a->rom, "ROM image: raw 8..64 KB, Intel HEX or Motorola S-records (docs/tools.md \"ROM images\")")->required();
    cmd->add_option("--symbols", a->symbols,
                    "The ROM's symbols (FILE[@SEG], docs/tools.md \"Symbols\"; default: the built firmware's)");
    cmd->add_option("--annotations", a->annotations,
                    "Loop bounds and transfer targets the code does not state (default for the built firmware: "
                    "comm_cpu/firmware/bound.annotations)");
    cmd->add_option("--scenario", a->scenario,
                    "The scenario whose start-up installs the vectors and sets the budget (default: "
                    "scenarios/three_ports_9600.yaml)");
    cmd->add_option("--out", a->out, "Output folder for bound.json and bound.txt")->required();
    cmd->callback([a] {
        int code = 0;
        sc_core::sc_report_handler::set_actions(sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
        try {
            if (a->rom.empty()) throw ConfigError("ROM '': an empty path");
            if (a->out.empty()) throw ConfigError("--out '': an empty path");
            code = bound_rom(*a);
        } catch (...) {
            code = report_exception("rcsim bound", a->rom);
        }
        set_command_exit_code(code);
    });
}

} // namespace rcsim
