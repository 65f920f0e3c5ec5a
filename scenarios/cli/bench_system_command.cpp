// rcsim bench system — the whole controller (real firmware, three saturated ports, main CPU)
// running a scenario: simulated seconds per host second, with every speed-up of the comm CPU
// on and with each one off, side by side in one run (alternating rounds, best of each), and the
// same scenario without traffic. The speed-ups do not change results (tests/speed).
// Then what bounds these figures, measured in the same run: the cost of one SystemC wait()
// and libx86emu's instruction rate on the anchor image, and for each run the kernel waits of
// the comm CPU and the instructions it executed one by one: the RTF the run could reach if
// each wait cost only a bare wait() and the core ran at libx86emu's rate, everything else free.
// Host time is measured here only, for the report; nothing of it enters the model.
// With --coverage: the cost of `rcsim run --coverage` instead, the run with its files written
// (--out) against the same with --coverage, side by side.
#include "comm_cpu/tools/x86emu_anchor.h"
#include "models/plumbing/child_process.h"
#include "models/plumbing/cli_range.h"
#include "scenarios/world/world.h"
#include "scenarios/run/runner.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace rcsim {
namespace {

double cpu_now() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + double(t.tv_nsec) * 1e-9;
}

struct Sample {
    double cpu_s = 0, wall_s = 0, sim_s = 0, cycles = 0;
    // the comm CPU's: Cpu8086::kernel_waits, access_waits, the instructions not forwarded
    double kernel_waits = 0, access_waits = 0, executed = 0;
    int status = 0; // 0: ran; else the child failed
};

struct Variant {
    std::string name;
    std::function<void(Scenario&)> apply;
    int baseline = -1; // the variant it differs from by one switch off (-1: none)
    bool coverage = false; // with --coverage (RunOptions::coverage)
    double best_cpu_s = 0, wall_s = 0; // of the fastest round
    Sample last{};                     // the last round's: its simulated figures are every round's
};

// SystemC elaborates once per process: each measurement runs in a child process
// (models/plumbing/child_process.h) that sends its figures back. `measure` fills them; a child that
// failed (an exception) gives figures with `status` 1.
template <class Figures>
Figures in_child(const std::function<void(Figures&)>& measure) {
    static_assert(std::is_trivially_copyable_v<Figures>, "the figures cross the pipe as bytes");
    const std::optional<std::string> bytes = run_in_child_process(
        [&] {
            Figures out;
            measure(out);
            return std::string(reinterpret_cast<const char*>(&out), sizeof out);
        },
        "bench system");
    Figures in;
    in.status = 1;
    if (bytes && bytes->size() == sizeof in) std::memcpy(&in, bytes->data(), sizeof in);
    return in;
}

/// `out_dir` "" = no files written.
Sample run_child(const Scenario& s, const std::string& out_dir, bool coverage) {
    return in_child<Sample>([&](Sample& out) {
        nlohmann::json r;
        RunOptions opt;
        opt.out_dir = out_dir;
        opt.coverage = coverage;
        opt.on_finished = [&out](World& w) {
            Cpu8086& cpu = w.ctl.comm.cpu;
            out.kernel_waits = double(cpu.kernel_waits());
            out.access_waits = double(cpu.access_waits());
            out.executed = double(cpu.instructions() - cpu.core().forwarded_instructions());
        };
        const double t0 = cpu_now();
        run_scenario(s, opt, r);
        out.cpu_s = cpu_now() - t0;
        out.wall_s = r["wall_time_s"].get<double>();
        out.sim_s = r["sim_time_s"].get<double>();
        out.cycles = r["comm_cpu"]["cycles"].get<double>();
    });
}

void run_variant(const Scenario& base, Variant& v, bool first, const std::string& out_dir) {
    Scenario s = base;
    v.apply(s);
    const Sample r = run_child(s, out_dir, v.coverage);
    if (r.status != 0) throw std::runtime_error("bench system: the run '" + v.name + "' failed");
    if (first || r.cpu_s < v.best_cpu_s) {
        v.best_cpu_s = r.cpu_s;
        v.wall_s = r.wall_s;
    }
    v.last = r;
}

// The scenario without its hosts: the firmware's idle loop and the timer interrupts only.
void no_traffic(Scenario& s) {
    for (auto& p : s.ports) p.host = PortScenario::Host::none;
    s.checks.min_frames_delivered.reset();
}

std::vector<Variant> variants() {
    std::vector<Variant> v;
    v.push_back({"all speed-ups on", [](Scenario&) {}});
    v.push_back({"fast_sync off", [](Scenario& s) { s.board.comm.fast_sync = false; }, 0});
    v.push_back({"fast_forward off", [](Scenario& s) { s.board.comm.fast_forward = false; }, 0});
    v.push_back({"no traffic, all on", no_traffic});
    v.push_back({"no traffic, fast_forward off", [](Scenario& s) {
                     no_traffic(s);
                     s.board.comm.fast_forward = false;
                 }, 3});
    v.push_back({"no traffic, stable_reads off", [](Scenario& s) {
                     no_traffic(s);
                     s.board.comm.stable_reads = false;
                 }, 3});
    v.push_back({"no traffic, slice_chain off", [](Scenario& s) {
                     no_traffic(s);
                     s.board.comm.slice_chain = false;
                 }, 3});
    return v;
}

/// bench system --coverage: the run with its files, without and with coverage.
std::vector<Variant> coverage_variants() {
    std::vector<Variant> v;
    v.push_back({"files written (--out)", [](Scenario&) {}});
    v.push_back({"files written, --coverage", [](Scenario&) {}, 0, true});
    return v;
}

// ---------------------------------------------------------------------------------------------
// What bounds the figures.

struct Floor {
    double value = 0;
    int status = 0;
};

// One thread alone in the kernel, waiting one clock period at a time: the cost of the round
// trip every kernel wait of the comm CPU makes at least (its context switches and the timed
// event), in host CPU ns.
struct LoneWaiter : sc_core::sc_module {
    std::uint64_t waits = 0;
    SC_HAS_PROCESS(LoneWaiter);
    explicit LoneWaiter(sc_core::sc_module_name name, std::uint64_t n) : sc_module(name), waits(n) { SC_THREAD(run); }
    void run() {
        const sc_core::sc_time clock(125, sc_core::SC_NS);
        for (std::uint64_t i = 0; i < waits; ++i) wait(clock);
    }
};

double bare_wait_ns() {
    const Floor f = in_child<Floor>([](Floor& out) {
        constexpr std::uint64_t kWaits = 2'000'000;
        LoneWaiter w("waiter", kWaits);
        const double t0 = cpu_now();
        sc_core::sc_start();
        out.value = (cpu_now() - t0) * 1e9 / double(kWaits);
    });
    if (f.status != 0) throw std::runtime_error("bench system: the wait() measurement failed");
    return f.value;
}

// libx86emu's instruction rate on the anchor image (`rcsim bench cpu --anchor`), in a child
// process like the runs.
double x86emu_rate() {
    const Floor f = in_child<Floor>([](Floor& out) {
        const anchor::Outcome o = anchor::run_x86emu(anchor::read_image(RCSIM_BENCH_LOOP_IMAGE));
        out.value = double(o.instructions) / o.cpu_seconds;
    });
    if (f.status != 0) throw std::runtime_error("bench system: the libx86emu run failed");
    return f.value;
}

// Both measured in every round beside the runs, the best of each kept.
struct Floors {
    double wait_ns = 0, rate = 0;
    void measure(bool first) {
        const double w = bare_wait_ns(), r = x86emu_rate();
        if (first || w < wait_ns) wait_ns = w;
        if (first || r > rate) rate = r;
    }
};

void print_floors(const std::vector<Variant>& list, const Floors& floors) {
    const double wait_ns = floors.wait_ns, rate = floors.rate;
    std::printf("  what bounds them, measured in this run: one SystemC wait() of a thread alone %.1f ns;\n"
                "  libx86emu on the anchor image %.1f M instructions/s (instruction level, not cycle-exact).\n"
                "  The RTF of each run if every kernel wait of the comm CPU cost one such wait() and the\n"
                "  instructions it executed (not forwarded) ran at libx86emu's rate, everything else free:\n",
                wait_ns, rate / 1e6);
    for (const Variant& v : list) {
        const Sample& r = v.last;
        const double waits_s = r.kernel_waits * wait_ns * 1e-9, exec_s = r.executed / rate;
        std::printf("    %s: %.0f kernel waits (%.0f before accesses) %.1f ms + %.3f M instructions %.1f ms"
                    " -> at most %.1fx\n",
                    v.name.c_str(), r.kernel_waits, r.access_waits, waits_s * 1e3, r.executed / 1e6, exec_s * 1e3,
                    r.sim_s / (waits_s + exec_s));
    }
}

} // namespace

void add_bench_system(CLI::App& bench) {
    auto* cmd = bench.add_subcommand("system", "Whole controller on a scenario (default: three saturated ports)");
    auto file = std::make_shared<std::string>("scenarios/three_ports_9600.yaml");
    auto rounds = std::make_shared<unsigned>(3);
    auto coverage = std::make_shared<bool>(false);
    cmd->add_option("scenario", *file, "Scenario file")->capture_default_str();
    cmd->add_option("--rounds", *rounds, "Alternating rounds per variant (best of each)")->check(whole_in(1, 100));
    cmd->add_flag("--coverage", *coverage,
                  "Measure --coverage instead: the run writing its files into a temporary folder, without and with it");
    cmd->callback([file, rounds, coverage] {
        sc_core::sc_report_handler::set_actions(sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
        const Scenario base = load_scenario(*file);
        std::vector<Variant> list = *coverage ? coverage_variants() : variants();
        // The --coverage runs' files: a temporary folder of their own, removed at the end.
        std::string out_dir;
        if (*coverage) {
            std::string tmpl = (std::filesystem::temp_directory_path() / "rcsim-bench-XXXXXX").string();
            if (!mkdtemp(tmpl.data())) throw std::runtime_error("bench system: cannot create a temporary folder");
            out_dir = tmpl;
        }
        Floors floors;
        for (unsigned i = 0; i < *rounds; ++i) {
            for (Variant& v : list) run_variant(base, v, i == 0, out_dir);
            floors.measure(i == 0);
        }
        if (!out_dir.empty()) std::filesystem::remove_all(out_dir);
        std::cout << "system: " << base.name << ", best of " << *rounds
                  << " alternating rounds; RTF = simulated s / host CPU s\n";
        for (const Variant& v : list)
            std::cout << "  " << v.name << ": " << v.last.sim_s << " s simulated, RTF " << v.last.sim_s / v.best_cpu_s
                      << "x (wall " << v.wall_s << " s), " << v.last.cycles / v.best_cpu_s / 1e6
                      << " M 8086 cycles per host CPU second\n";
        for (const Variant& v : list)
            if (v.baseline >= 0)
                std::cout << (*coverage ? "  cost: '" : "  speed-up: '") << list[std::size_t(v.baseline)].name << "' vs '"
                          << v.name << "': " << v.best_cpu_s / list[std::size_t(v.baseline)].best_cpu_s
                          << (*coverage ? "x the host CPU time\n" : "x\n");
        print_floors(list, floors);
    });
}

} // namespace rcsim
