// rcsim bench system — the whole controller (real firmware, three saturated ports, main CPU)
// running a scenario: simulated seconds per host second, 8086 cycles per host second.
#include "scenarios/runner.h"

#include <CLI/CLI.hpp>

#include <iostream>

namespace rcsim {

void add_bench_system(CLI::App& bench) {
    auto* cmd = bench.add_subcommand("system", "Whole controller on a scenario (default: three saturated ports)");
    auto file = std::make_shared<std::string>("scenarios/three_ports_9600.yaml");
    cmd->add_option("scenario", *file, "Scenario file")->capture_default_str();
    cmd->callback([file] {
        sc_core::sc_report_handler::set_actions(sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
        nlohmann::json r;
        run_scenario(load_scenario(*file), RunOptions{}, r);
        const double wall = r["wall_time_s"].get<double>();
        const double cycles = r["comm_cpu"]["cycles"].get<double>();
        std::cout << "system: " << r["scenario"].get<std::string>() << ", " << r["sim_time_s"].get<double>()
                  << " s simulated in " << wall << " s wall: " << r["rtf"].get<double>() << "x real time, "
                  << cycles / wall / 1e6 << " M 8086 cycles per host second\n";
    });
}

} // namespace rcsim
