// rcsim run SCENARIO [--out DIR] [--rom FILE] [--seed N] [--reproducible] [--vcd FILE] [--trace FILE]
//           [--profile] [--coverage] [--gdb [HOST:]PORT [--gdb-wait]] [--symbols FILE[@SEG]] [--monitor [HOST:]PORT]
//           [--modbus [[HOST:]PORT]] [--bound [--annotations FILE] [--witness SEARCH_DIR/search.json]]
//           [--duration S] [--realtime [FACTOR]]
#include "models/plumbing/cli_range.h"
#include "models/plumbing/config_error.h"
#include "scenarios/cli/gdb_run.h"
#include "scenarios/report/output.h"
#include "scenarios/run/failure.h"
#include "scenarios/run/runner.h"
#include "models/plumbing/stop_signal.h"

#include <CLI/CLI.hpp>

#include <systemc>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>

namespace rcsim {

namespace {
/// --seed: a decimal number 0 .. 2^64-1, all of it (CLI11 would wrap "-5" and saturate an overflow).
std::uint64_t parse_seed(const std::string& text) {
    std::uint64_t v = 0;
    const char* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, v);
    if (text.empty() || r.ec != std::errc() || r.ptr != end)
        throw ConfigError("--seed '" + text + "' is not a number 0 .. 18446744073709551615");
    return v;
}

// The bounds a scenario file has for the same keys (scenarios/config/scenario.cpp, docs/scenarios.md
// "Limits"): an hour is the longest run; slower pacing than 1/100 would stretch a run without bound.
constexpr double kMinDurationS = 1e-6, kMaxDurationS = 3600;
constexpr double kMinRealtime = 0.01, kMaxRealtime = 1e6;

/// --realtime's FACTOR: "" (the option alone) is 1, wall-clock pace; 0 is off; else [0.01, 1e6].
double parse_realtime(const std::string& text) {
    if (text.empty()) return 1.0;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0' || !std::isfinite(v) || !(v == 0 || (v >= kMinRealtime && v <= kMaxRealtime)))
        throw ConfigError("--realtime '" + text + "' must be 0 (off) or a factor in [0.01, 1e6] (1: wall-clock pace)");
    return v;
}

/// --duration and --realtime over what the scenario file says (issue #51 item 2: watch any
/// scenario live with --monitor or --modbus without writing YAML).
void override_pacing(Scenario& s, std::optional<double> duration_s, std::optional<double> realtime) {
    if (duration_s) {
        s.duration_s = *duration_s;
        if (s.motion) s.motion->duration_s = *duration_s; // a motion run's length is its plan's
        // A file's duration_s 0 ran until its tcp/pty/replay host ended it; a duration ends it now.
        for (auto& p : s.ports) p.tcp.end_on_disconnect = p.pty.end_on_disconnect = p.replay.end_at_log_end = false;
    }
    if (realtime) {
        if (s.has_motion)
            throw ConfigError("--realtime: '" + s.file + "' has a 'motion:' section, which runs the motion side alone, unpaced");
        s.realtime = *realtime;
    }
}
} // namespace

void add_run_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("run", "Run a scenario file; print its summary and write DIR/report.json");
    struct Args {
        std::string scenario, out, rom, rom_odd, vcd, seed, trace, symbols, monitor, modbus, annotations, witness;
        double duration_s = 0;
        std::string realtime;
        bool bound = false;
        RunOptions::Rows rows = RunOptions::Rows::automatic;
        bool reproducible = false;
        bool verbose = false;
        debug::GdbOptions gdb;
        bool profile = false;
        bool coverage = false;
    };
    auto args = std::make_shared<Args>();
    cmd->add_option("scenario", args->scenario, "Scenario file (YAML, see docs/scenarios.md)")->required();
    auto* out = cmd->add_option("--out", args->out,
                                "Output folder for report.json, report.html and every file the run writes "
                                "(default: rcsim-out/<scenario>)");
    auto* seed = cmd->add_option("--seed", args->seed, "Seed (overrides the scenario's)");
    auto* rom = cmd->add_option("--rom", args->rom,
                                "ROM image to run instead of the built firmware: raw 8..64 KB (mirrored when smaller), "
                                "Intel HEX or Motorola S-records; with --rom-odd, the even EPROM of a pair (docs/tools.md \"ROM images\")");
    auto* rom_odd = cmd->add_option("--rom-odd", args->rom_odd, "The odd EPROM (D8-D15) of an even/odd pair; --rom is the even one");
    cmd->add_flag("--reproducible", args->reproducible, "Write 0 for wall_time_s and rtf (byte-identical reports)");
    cmd->add_option("--vcd", args->vcd, "Write interrupt lines to this VCD file (its name ends in .vcd)")
        ->check(CLI::Validator(
            [](std::string& path) {
                // SystemC's VCD writer appends ".vcd" to any name: /dev/null would become /dev/null.vcd.
                return is_vcd_name(path) ? std::string() : "'" + path + "': a VCD file's name ends in .vcd";
            },
            "FILE.vcd"));
    static const std::map<std::string, RunOptions::Rows> kRows = {{"auto", RunOptions::Rows::automatic},
                                                                   {"plain", RunOptions::Rows::plain},
                                                                   {"gz", RunOptions::Rows::gzip},
                                                                   {"none", RunOptions::Rows::none}};
    cmd->add_option("--interrupts-csv", args->rows,
                    "A row per interrupt: plain interrupts.csv, gz (interrupts.csv.gz), none, or auto (plain up to "
                    "60 simulated seconds, gz beyond)")
        ->transform(CLI::CheckedTransformer(kRows, CLI::ignore_case));
    auto* trace = cmd->add_option("--trace", args->trace, "Write a Trace Event Format file (ui.perfetto.dev, chrome://tracing)");
    cmd->add_flag("--profile", args->profile,
                  "Profile the comm CPU per function: DIR/profile.txt, DIR/profile.folded, a flame graph in report.html");
    cmd->add_flag("--coverage", args->coverage,
                  "Coverage of the comm CPU's ROM: DIR/coverage.info (lcov), DIR/coverage/ (genhtml, when installed), "
                  "a section in report.html (docs/tools.md \"Coverage\")");
    auto* symbols = cmd->add_option("--symbols", args->symbols,
                                    "The ROM's symbols, for the latency causes, --profile, --coverage and --gdb (ld86 -M map, nasm map, a linker's Publics "
                                    "by Value map or NAME ADDRESS lines; FILE@SEG loads a map's image at SEG:0000; "
                                    "default: the built firmware's; docs/tools.md)");
    cmd->add_flag("-v,--verbose", args->verbose, "Print the models' informational notes");
    auto* gdb = cmd->add_option("--gdb", args->gdb.listen,
                                "Serve gdb's remote protocol on [HOST:]PORT (127.0.0.1 unless HOST; docs/tools.md)");
    auto* gdb_wait = cmd->add_flag("--gdb-wait", args->gdb.wait,
                                   "With --gdb: hold the board before the first instruction until a debugger attaches");
    auto* monitor = cmd->add_option("--monitor", args->monitor,
                                    "Serve the live page and JSON API on [HOST:]PORT (127.0.0.1 unless given; docs/monitor.md)");
    auto* modbus = cmd->add_option("--modbus", args->modbus,
                                   "Serve Modbus TCP on [HOST:]PORT (127.0.0.1 unless given, port 1502 unless given; docs/monitor.md)")
                       ->expected(0, 1);
    auto* duration = cmd->add_option("--duration", args->duration_s,
                                     "Simulated seconds to run, over the scenario's duration_s (1e-6 .. 3600)")
                         ->check(real_in(kMinDurationS, kMaxDurationS));
    auto* realtime = cmd->add_option("--realtime", args->realtime,
                                     "Pace simulated time to wall time x FACTOR (alone: 1), over the scenario's "
                                     "realtime; 0 runs as fast as it can (docs/scenarios.md)")
                         ->expected(0, 1);
    cmd->add_flag("--bound", args->bound,
                  "The static bound of the ROM's interrupt paths beside this run's figures: report.json \"bound\", "
                  "report.html, DIR/bound.json (docs/tools.md \"Bound\")");
    auto* annotations = cmd->add_option("--annotations", args->annotations,
                                        "With --bound: loop bounds and transfer targets the code does not state "
                                        "(default: the built firmware's comm_cpu/firmware/bound.annotations)");
    auto* witness = cmd->add_option("--witness", args->witness,
                                    "With --bound: a search's SEARCH_DIR/search.json, its worst figure beside the bound");
    cmd->callback([args, out, seed, rom, rom_odd, trace, gdb, gdb_wait, symbols, monitor, modbus, annotations, witness,
                   duration, realtime] {
        RunOptions opt;
        // Every run writes its files somewhere it says: without --out, a folder named after the
        // scenario under ./rcsim-out (docs/scenarios.md "Output files").
        const bool default_out = !*out;
        if (default_out) args->out = (std::filesystem::path("rcsim-out") / std::filesystem::path(args->scenario).stem()).string();
        opt.out_dir = args->out;
        if (*rom) opt.rom = RomSource{args->rom, args->rom_odd};
        // The input a run that exhausts memory is blamed on.
        const std::string input = args->scenario + (*rom ? " with ROM " + args->rom : std::string()) +
                                  (*rom_odd ? " and " + args->rom_odd : std::string());
        opt.reproducible = args->reproducible;
        opt.progress = true; // on a terminal only (docs/scenarios.md "Progress")
        opt.vcd = args->vcd;
        opt.interrupt_rows = args->rows;
        opt.trace = args->trace;
        opt.profile = args->profile;
        opt.symbols = args->symbols;
        opt.coverage = args->coverage;
        if (*monitor) opt.monitor = args->monitor;
        if (*modbus) opt.modbus = args->modbus;
        opt.bound = args->bound;
        opt.annotations = args->annotations;
        opt.witness = args->witness;
        int code = 0;
        // Model notes (SC_INFO) go to the log only with --verbose; warnings and errors always show.
        if (!args->verbose) sc_core::sc_report_handler::set_actions(sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
        try {
            if (*out && args->out.empty()) throw ConfigError("--out '': an empty path (leave --out out for rcsim-out/<scenario>)");
            if (*seed) opt.seed = parse_seed(args->seed);
            if (*trace && args->trace.empty()) throw ConfigError("--trace '': an empty path (leave --trace out for no trace)");
            if (*rom && args->rom.empty()) throw ConfigError("--rom '': an empty path (leave --rom out for the built firmware)");
            if (*rom_odd && !*rom) throw ConfigError("--rom-odd needs --rom (the even EPROM of the pair)");
            if (*rom_odd && args->rom_odd.empty()) throw ConfigError("--rom-odd '': an empty path");
            if (!*gdb && *gdb_wait) throw ConfigError("--gdb-wait needs --gdb");
            if (*annotations && args->annotations.empty()) throw ConfigError("--annotations '': an empty path");
            if (*witness && args->witness.empty()) throw ConfigError("--witness '': an empty path");
            if (*symbols && args->symbols.empty())
                throw ConfigError("--symbols '': an empty path (leave --symbols out for the built firmware's own)");
            // Both sit on the core's one instruction-boundary hook (i8086::StepHook).
            if (*gdb && args->profile) throw ConfigError("--gdb and --profile cannot be used together");
            args->gdb.symbols = args->symbols;
            install_stop_handlers();
            nlohmann::json report;
            const std::optional<double> realtime_factor =
                *realtime ? std::optional<double>(parse_realtime(args->realtime)) : std::nullopt;
            Scenario scenario = load_scenario(args->scenario);
            override_pacing(scenario, *duration ? std::optional<double>(args->duration_s) : std::nullopt, realtime_factor);
            if (default_out) std::cout << "output: " << args->out << " (no --out given)" << std::endl;
            std::unique_ptr<debug::GdbRun> debugger; // outlives the run: it tells gdb how it ended
            if (*gdb) debugger = std::make_unique<debug::GdbRun>(args->gdb, scenario, opt, std::cout, std::cerr);
            code = run_scenario(std::move(scenario), opt, report);
            if (debugger) debugger->finish(code);
            print_summary(report, std::cout);
            print_report_paths(report, args->out, std::cout);
        } catch (...) {
            code = report_exception("rcsim run", input);
        }
        set_command_exit_code(code);
    });
}

} // namespace rcsim
