// rcsim — command-line entry point.
#include "scenarios/run/failure.h"
#include "scenarios/modbus/register_map.h"

#include <CLI/CLI.hpp>
#include <systemc>

#include <cstdlib>
#include <iostream>
#include <string>

namespace rcsim {
void add_cputest_command(CLI::App& app);
void add_bench_cpu(CLI::App& bench);
void add_demo_command(CLI::App& app);
void add_run_command(CLI::App& app);
void add_bench_system(CLI::App& bench);
void add_bench_serial(CLI::App& bench);
void add_bench_motion(CLI::App& bench);
void add_bench_soak(CLI::App& bench);
void add_sweep_commands(CLI::App& app); // sweep, merge, compare
void add_search_command(CLI::App& app);
void add_bound_command(CLI::App& app);
}

namespace {
/// CLI11 answers "A subcommand is required" to `rcsim frobnicate`: name the word it did not know.
/// Returns "" when argv[i..] starts with a known command (or an option, or `app` has no commands).
std::string unknown_command(const CLI::App& app, int argc, char* argv[], int i) {
    const auto subs = app.get_subcommands([](const CLI::App*) { return true; });
    if (i >= argc || argv[i][0] == '-' || subs.empty()) return "";
    std::string names;
    for (const CLI::App* sub : subs) {
        if (sub->get_name() == argv[i]) return unknown_command(*sub, argc, argv, i + 1);
        names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    return "unknown command '" + std::string(argv[i]) + "' (" + names + ")";
}
} // namespace

#ifndef RCSIM_VERSION
#define RCSIM_VERSION "0.1.0"
#endif

int sc_main(int argc, char* argv[]) {
    CLI::App app{"rcsim — cycle-accurate co-simulation of a two-CPU robot controller"};
    app.require_subcommand(1);
    app.footer(rcsim::kExitCodesHelp);
    // One line per error (issue #48): CLI11's own adds "Run with --help for more information."
    app.failure_message([](const CLI::App*, const CLI::Error& e) { return "rcsim: " + std::string(e.what()) + "\n"; });

    auto* version = app.add_subcommand("version", "Print the rcsim and SystemC versions");
    version->callback([] {
        std::cout << "rcsim " << RCSIM_VERSION << "\n"
                  << "SystemC " << sc_core::sc_release() << "\n";
    });

    // `rcsim bench <what>`: benchmarks register themselves under this group.
    auto* bench = app.add_subcommand("bench", "Run a benchmark and print its figures");
    bench->require_subcommand(1);
    (void)bench;
    rcsim::add_cputest_command(app);
    rcsim::add_bench_cpu(*bench);
    rcsim::add_demo_command(app);
    rcsim::add_run_command(app);
    rcsim::add_bench_system(*bench);
    rcsim::add_bench_serial(*bench);
    rcsim::add_bench_motion(*bench);
    rcsim::add_bench_soak(*bench);
    rcsim::add_sweep_commands(app);
    rcsim::add_search_command(app);
    rcsim::add_bound_command(app);
    auto* modbus_map = app.add_subcommand("modbus-map", "Print the Modbus TCP register map of --modbus as CSV (docs/monitor.md)");
    modbus_map->callback([] { rcsim::modbus::write_map_csv(std::cout); });

    try {
        app.parse(argc, argv);
    } catch (const CLI::RuntimeError& e) {
        return e.get_exit_code(); // a subcommand's own exit code (rcsim::kExitCodesHelp)
    } catch (const CLI::ParseError& e) {
        const std::string unknown = unknown_command(app, argc, argv, 1);
        if (!unknown.empty()) {
            std::cerr << "rcsim: " << unknown << "\n";
            return 2;
        }
        return app.exit(e) == 0 ? 0 : rcsim::kExitBadInput;
    } catch (...) {
        // One clear message and its exit code, never an abort (scenarios/run/failure.h).
        std::string args;
        for (int i = 1; i < argc; ++i) args += (i > 1 ? " " : "") + std::string(argv[i]);
        return rcsim::report_exception("rcsim", "rcsim " + args);
    }
    return rcsim::command_exit_code();
}

#ifdef RCSIM_SANITIZE_BUILD
// LeakSanitizer cannot walk SystemC's coroutine stacks and aborts at exit (CMakeLists.txt).
extern "C" const char* __asan_default_options() { return "detect_leaks=0"; }
#endif

// Our own main, so the SystemC banner is off before the kernel prints it (rcsim's output is
// meant to be read and diffed); SystemC then runs sc_main as usual.
int main(int argc, char* argv[]) {
    setenv("SC_COPYRIGHT_MESSAGE", "DISABLE", 0);
    return sc_core::sc_elab_and_sim(argc, argv);
}
