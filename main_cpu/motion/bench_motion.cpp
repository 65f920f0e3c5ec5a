// rcsim — `rcsim bench motion`: four axes moving continuously for a simulated time with the
// control cycle at 1 ms (back-and-forth moves on every axis), wall time measured around sc_start.
#include "main_cpu/motion/motion_controller.h"
#include "models/plumbing/cli_range.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>

namespace rcsim::motion {
namespace {
struct BenchDriver : sc_core::sc_module {
    MotionController& mc;
    std::uint64_t cycles;
    std::uint64_t moves = 0, refused = 0;
    SC_HAS_PROCESS(BenchDriver);
    BenchDriver(sc_core::sc_module_name n, MotionController& m, std::uint64_t c) : sc_module(n), mc(m), cycles(c) {
        SC_THREAD(run);
    }
    void run() {
        const sc_core::sc_time cycle(1, sc_core::SC_MS);
        mc.command("SV", "1");
        for (std::uint64_t k = 0; k <= cycles; ++k) {
            mc.control_cycle(sc_core::sc_time_stamp());
            // Keep every axis moving: a new 1-2 s move as soon as the last one is done (after
            // MC_Power's enable sequence of the first cycles).
            for (unsigned a = 0; a < MotionController::axes && k >= 10; ++a) {
                if (mc.axis(a).state() != AxisState::standstill) continue;
                const long target = (mc.chip().command_position(a) > 0 ? -1 : 1) * (20000 + 5000 * static_cast<long>(a));
                const MotionReply r =
                    mc.command("MA", std::to_string(a) + "," + std::to_string(target) + ",30000,100000,100000");
                if (r.bch == 0) ++moves;
                else ++refused;
            }
            wait(cycle);
        }
        sc_core::sc_stop();
    }
};
} // namespace

void register_bench_motion(CLI::App& bench) {
    auto* cmd = bench.add_subcommand("motion", "4 axes moving continuously, 1 ms control cycle");
    auto seconds = std::make_shared<double>(60.0);
    cmd->add_option("--seconds", *seconds, "simulated seconds")->check(real_in(0.001, 36000.0));
    cmd->callback([seconds] {
        // The kernel's "Simulation stopped by user" note would interleave with the figures.
        sc_core::sc_report_handler::set_actions(sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
        MotionController mc("motion");
        BenchDriver drv("bench_driver", mc, static_cast<std::uint64_t>(*seconds * 1000));
        const auto t0 = std::chrono::steady_clock::now(); // wall clock for the report only
        sc_core::sc_start();
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("bench motion: %.0f s simulated, 4 axes, 1 ms cycle, %llu moves (%llu refused), %zu samples: %.3f s wall "
                    "(%.1fx real time)\n",
                    *seconds, static_cast<unsigned long long>(drv.moves),
                    static_cast<unsigned long long>(drv.refused), mc.recorder().count(), wall,
                    *seconds / wall);
    });
}

} // namespace rcsim::motion

namespace rcsim {
void add_bench_motion(CLI::App& bench) { motion::register_bench_motion(bench); }
} // namespace rcsim
