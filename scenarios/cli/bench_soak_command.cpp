// rcsim bench soak — the fault soak of issue 33: the whole controller with three saturated ports
// and faults on every port (scenarios/soak.yaml, an hour by default), reporting per port and
// direction what became of every frame (matched, expected drops, and everything that counts
// against the exactly-once checks) and the process's memory: its resident size sampled through
// the run (flat, or the soak fails its purpose) and its peak. The interrupt rows are not written
// (--interrupts-csv none): the soak measures the model, not the disk.
//
// --motion: the motion soak instead (scenarios/soak_motion.yaml, issue #48 item 3): a motion run
// whose program draws circles for the whole run, its trajectory files written as any run's; the
// same memory figures, and the motion run's own.
#include "models/plumbing/cli_range.h"
#include "models/plumbing/config_error.h"
#include "scenarios/run/failure.h"
#include "scenarios/run/runner.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <systemc>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

namespace rcsim {
namespace {

constexpr std::uint64_t kFaultEvery = 2000; // characters of one side between two faults
constexpr double kBreakEverySec = 60;

/// Faults spread over `seconds` on every port: each side's every kFaultEvery-th character, the
/// kinds in turn, and a BREAK from each side every kBreakEverySec (the host's at the middle of
/// each period, the controller's a quarter later).
void add_faults(Scenario& s, double seconds) {
    static const char* kinds[] = {"drop", "flip_data_bit", "corrupt_stop", "flip_cell"};
    for (std::size_t p = 0; p < s.ports.size(); ++p) {
        const SerialFormat fmt = s.ports[p].format();
        // The most characters one side can send in `seconds`, back to back.
        const auto chars = static_cast<std::uint64_t>(seconds / fmt.frame_time().to_seconds());
        auto& faults = s.ports[p].faults;
        for (const auto from : {LineFault::From::host, LineFault::From::controller}) {
            unsigned n = 0;
            for (std::uint64_t i = kFaultEvery + 7 * p; i < chars; i += kFaultEvery, ++n) {
                LineFault f;
                f.from = from;
                f.kind = kinds[n % 4];
                f.index = i;
                const unsigned data_bit = n % fmt.data_bits;
                f.bit = f.kind == std::string("flip_cell") ? 1 + data_bit : data_bit; // cell 0 is START
                faults.push_back(f);
            }
            for (double t = kBreakEverySec / 2; t < seconds; t += kBreakEverySec) {
                LineFault f;
                f.from = from;
                f.kind = "break";
                f.at = sc_core::sc_time(t + (from == LineFault::From::host ? 0.0 : kBreakEverySec / 4) + 0.1 * double(p),
                                        sc_core::SC_SEC);
                f.duration = sc_core::sc_time(5, sc_core::SC_MS);
                faults.push_back(f);
            }
        }
    }
}

/// The resident set of this process in kB (/proc/self/statm).
long rss_kb() {
    std::ifstream statm("/proc/self/statm");
    long size = 0, resident = 0;
    statm >> size >> resident;
    return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

/// Samples the resident size on a thread of its own (it reads /proc, nothing of the model).
class RssSampler {
public:
    RssSampler() : thread_([this] {
        while (!stop_) {
            samples_.push_back(rss_kb());
            for (int i = 0; i < 10 && !stop_; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
    }) {}
    std::vector<long> stop() {
        stop_ = true;
        thread_.join();
        return samples_;
    }

private:
    std::atomic<bool> stop_{false};
    std::vector<long> samples_;
    std::thread thread_;
};

void print_books(const nlohmann::json& report) {
    // "after fault": of the duplicates and unexpected, those whose transfer a fault hit.
    std::cout << "  port  frames      sent  matched  expected  lost  dropped  dup  unexp  reord  after fault  mismatches\n";
    std::uint64_t total = 0;
    for (std::size_t p = 0; p < report["ports"].size(); ++p)
        for (const char* k : {"commands", "responses"}) {
            const auto& b = report["ports"][p][k];
            auto u = [&b](const char* key) { return b.value(key, std::uint64_t{0}); };
            const std::uint64_t dropped = b.contains("dropped") ? b["dropped"].value("gave_up", std::uint64_t{0}) +
                                                                      b["dropped"].value("port_reset", std::uint64_t{0})
                                                                : 0;
            const std::uint64_t sent = std::string(k) == "commands" ? u("host_eot") : u("main_cpu_handed");
            std::cout << "  " << std::setw(4) << p << "  " << std::left << std::setw(10) << k << std::right
                      << std::setw(6) << sent << std::setw(9) << u("matched") << std::setw(10) << u("expected")
                      << std::setw(6) << u("lost") << std::setw(9) << dropped << std::setw(5) << u("duplicates")
                      << std::setw(7) << u("unexpected") << std::setw(7) << u("reordered") << std::setw(13)
                      << u("after_fault") << std::setw(12) << u("mismatches") << "\n";
            total += u("mismatches");
        }
    std::cout << "  frames not delivered exactly once, expected drops aside: " << total << "\n";
}

} // namespace

void print_motion(const nlohmann::json& report) {
    const nlohmann::json& m = report["motion"];
    std::cout << "  motion: " << m.value("samples", std::uint64_t{0}) << " trajectory samples, state "
              << m.value("state", std::string("?")) << ", largest following error "
              << m.value("max_following_error_pulses", 0.0) << " pulses\n";
}

void add_bench_soak(CLI::App& bench) {
    auto* cmd = bench.add_subcommand("soak", "Three saturated ports with faults on every port; frame books and memory "
                                             "(--motion: the motion soak)");
    auto file = std::make_shared<std::string>();
    auto seconds = std::make_shared<double>(3600);
    auto out = std::make_shared<std::string>();
    auto motion = std::make_shared<bool>(false);
    cmd->add_option("scenario", *file,
                    "Scenario file (its ports, seed and noise; the bench adds the faults) [scenarios/soak.yaml, "
                    "with --motion scenarios/soak_motion.yaml]");
    cmd->add_flag("--motion", *motion, "The motion soak: a motion scenario run for --seconds, its memory");
    cmd->add_option("--seconds", *seconds, "Simulated seconds (1 .. 36000)")->capture_default_str()->check(real_in(1, 36000));
    cmd->add_option("--out", *out, "Output folder for report.json and report.html [rcsim-out/soak, with --motion "
                                   "rcsim-out/soak_motion]");
    cmd->callback([file, seconds, out, motion] {
        sc_core::sc_report_handler::set_actions(sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
        if (file->empty()) *file = *motion ? "scenarios/soak_motion.yaml" : "scenarios/soak.yaml";
        if (out->empty()) *out = *motion ? "rcsim-out/soak_motion" : "rcsim-out/soak";
        Scenario s = load_scenario(*file);
        if (*motion != s.has_motion)
            throw ConfigError(*file + (*motion ? ": --motion needs a scenario with a 'motion:' section"
                                               : ": a 'motion:' scenario is soaked with --motion"));
        s.duration_s = *seconds;
        if (s.motion) s.motion->duration_s = *seconds;
        else add_faults(s, *seconds);
        RunOptions opt;
        opt.out_dir = *out;
        opt.interrupt_rows = RunOptions::Rows::none;
        nlohmann::json report;
        RssSampler sampler;
        const int code = run_scenario(std::move(s), opt, report);
        const std::vector<long> rss = sampler.stop();
        rusage ru{};
        getrusage(RUSAGE_SELF, &ru);
        std::cout << "soak: " << report["scenario"].get<std::string>() << ", " << report["sim_time_s"].get<double>()
                  << " s simulated in " << report["wall_time_s"].get<double>() << " s (RTF " << report["rtf"].get<double>()
                  << "x); verdict " << report["verdict"].get<std::string>() << "\n";
        if (*motion) print_motion(report);
        else print_books(report);
        // Flat memory: the resident size after the first tenth of the samples against the last.
        const std::size_t settled = rss.size() / 10;
        std::cout << "  resident memory: " << (rss.empty() ? 0 : rss[settled]) / 1024 << " MB after a tenth of the run, "
                  << (rss.empty() ? 0 : rss.back()) / 1024 << " MB at its end, peak " << ru.ru_maxrss / 1024 << " MB ("
                  << rss.size() << " samples, one a second)\n"
                  << "  report: " << *out << "/report.json\n";
        set_command_exit_code(code);
    });
}

} // namespace rcsim
