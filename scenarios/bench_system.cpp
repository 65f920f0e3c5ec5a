// rcsim bench system — the whole controller (real firmware, three saturated ports, main CPU)
// running a scenario: simulated seconds per host second, with every speed-up of the comm CPU
// on and with each one off, side by side in one run (alternating rounds, best of each), and the
// same scenario without traffic. The speed-ups do not change results (tests/speed).
// Host time is measured here only, for the report; nothing of it enters the model.
#include "scenarios/runner.h"

#include <CLI/CLI.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <ctime>
#include <functional>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace rcsim {
namespace {

double cpu_now() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + double(t.tv_nsec) * 1e-9;
}

struct Variant {
    std::string name;
    std::function<void(Scenario&)> apply;
    int baseline = -1; // the variant it differs from by one switch off (-1: none)
    double best_cpu_s = 0, wall_s = 0, sim_s = 0, cycles = 0;
};

struct Sample {
    double cpu_s = 0, wall_s = 0, sim_s = 0, cycles = 0;
    int status = 0; // 0: ran; else the child failed
};

// SystemC elaborates once per process: each run is a child process that reports its figures
// through a pipe.
Sample run_child(const Scenario& s) {
    int fd[2];
    if (pipe(fd) != 0) throw std::runtime_error("bench system: pipe() failed");
    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error("bench system: fork() failed");
    if (pid == 0) {
        close(fd[0]);
        Sample out;
        try {
            nlohmann::json r;
            const double t0 = cpu_now();
            run_scenario(s, RunOptions{}, r);
            out.cpu_s = cpu_now() - t0;
            out.wall_s = r["wall_time_s"].get<double>();
            out.sim_s = r["sim_time_s"].get<double>();
            out.cycles = r["comm_cpu"]["cycles"].get<double>();
        } catch (const std::exception& e) {
            std::cerr << "bench system: " << e.what() << "\n";
            out.status = 1;
        }
        const ssize_t n = write(fd[1], &out, sizeof out);
        _exit(n == ssize_t(sizeof out) ? 0 : 1);
    }
    close(fd[1]);
    Sample in;
    in.status = 1;
    const ssize_t n = read(fd[0], &in, sizeof in);
    close(fd[0]);
    int st = 0;
    waitpid(pid, &st, 0);
    if (n != ssize_t(sizeof in) || st != 0) in.status = 1;
    return in;
}

void run_variant(const Scenario& base, Variant& v, bool first) {
    Scenario s = base;
    v.apply(s);
    const Sample r = run_child(s);
    if (r.status != 0) throw std::runtime_error("bench system: the run '" + v.name + "' failed");
    if (first || r.cpu_s < v.best_cpu_s) {
        v.best_cpu_s = r.cpu_s;
        v.wall_s = r.wall_s;
    }
    v.sim_s = r.sim_s;
    v.cycles = r.cycles;
}

std::vector<Variant> variants() {
    std::vector<Variant> v;
    v.push_back({"all speed-ups on", [](Scenario&) {}});
    v.push_back({"fast_sync off", [](Scenario& s) { s.board.comm.fast_sync = false; }, 0});
    v.push_back({"fast_forward off", [](Scenario& s) { s.board.comm.fast_forward = false; }, 0});
    v.push_back({"no traffic, all on", [](Scenario& s) {
                     for (auto& p : s.ports) p.host = PortScenario::Host::none;
                     s.checks.min_frames_delivered.reset();
                 }});
    v.push_back({"no traffic, fast_forward off", [](Scenario& s) {
                     for (auto& p : s.ports) p.host = PortScenario::Host::none;
                     s.checks.min_frames_delivered.reset();
                     s.board.comm.fast_forward = false;
                 }, 3});
    return v;
}

} // namespace

void add_bench_system(CLI::App& bench) {
    auto* cmd = bench.add_subcommand("system", "Whole controller on a scenario (default: three saturated ports)");
    auto file = std::make_shared<std::string>("scenarios/three_ports_9600.yaml");
    auto rounds = std::make_shared<unsigned>(3);
    cmd->add_option("scenario", *file, "Scenario file")->capture_default_str();
    cmd->add_option("--rounds", *rounds, "Alternating rounds per variant (best of each)")->check(CLI::Range(1u, 100u));
    cmd->callback([file, rounds] {
        sc_core::sc_report_handler::set_actions(sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
        const Scenario base = load_scenario(*file);
        std::vector<Variant> list = variants();
        for (unsigned i = 0; i < *rounds; ++i)
            for (Variant& v : list) run_variant(base, v, i == 0);
        std::cout << "system: " << base.name << ", best of " << *rounds
                  << " alternating rounds; RTF = simulated s / host CPU s\n";
        for (const Variant& v : list)
            std::cout << "  " << v.name << ": " << v.sim_s << " s simulated, RTF " << v.sim_s / v.best_cpu_s
                      << "x (wall " << v.wall_s << " s), " << v.cycles / v.best_cpu_s / 1e6
                      << " M 8086 cycles per host CPU second\n";
        for (const Variant& v : list)
            if (v.baseline >= 0)
                std::cout << "  speed-up: '" << list[std::size_t(v.baseline)].name << "' vs '" << v.name
                          << "': " << v.best_cpu_s / list[std::size_t(v.baseline)].best_cpu_s << "x\n";
    });
}

} // namespace rcsim
