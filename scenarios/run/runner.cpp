// rcsim — runs one scenario: assemble the world (world.h), run it, measure (measure.h), judge
// (checks.h), report (output.h, report_html.h). Each step has its own file; this one only orders
// them.
#include "scenarios/run/runner.h"

#include "scenarios/world/world.h"
#include "scenarios/verdict/checks.h"
#include "scenarios/verdict/judge.h"
#include "scenarios/verdict/measure.h"
#include "scenarios/verdict/latency_causes.h"
#include "scenarios/run/cause_symbols.h"
#include "scenarios/run/bound_inputs.h"
#include "scenarios/run/bound_report.h"
#include "scenarios/verdict/bound_check.h"
#include "scenarios/monitor/board_monitor.h"
#include "scenarios/modbus/modbus_bridge.h"
#include "scenarios/report/output.h"
#include "scenarios/report/report_html.h"
#include "models/plumbing/stop_signal.h"
#include "scenarios/run/motion_run.h"
#include "scenarios/run/run_progress.h"
#include "scenarios/verdict/motion_figures.h"
#include "scenarios/report/trajectory_report.h"
#include "scenarios/trace/vcd_trace.h"
#include "scenarios/trace/perfetto_trace.h"
#include "scenarios/trace/profile_run.h"
#include "scenarios/coverage/coverage_run.h"
#include "scenarios/debug/rom_symbols.h"
#include "models/plumbing/config_error.h"
#include "models/plumbing/gzip_stream.h"
#include "models/plumbing/output_file.h"

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>

#ifndef RCSIM_COMM_FW_ROM
#define RCSIM_COMM_FW_ROM ""
#endif

namespace rcsim {

namespace {

constexpr unsigned kPorts = World::kPorts;

/// What every report starts with. wall_time_s and rtf are the only host-dependent fields;
/// `reproducible` writes 0 for both.
nlohmann::json run_header(const Scenario& s, const RunOptions& opt, double wall) {
    const double sim_s = sc_core::sc_time_stamp().to_seconds();
    nlohmann::json h = {{"scenario", s.name},
                        {"seed", s.seed},
                        {"sim_time_s", sim_s},
                        {"wall_time_s", opt.reproducible ? 0.0 : wall},
                        {"rtf", opt.reproducible || wall <= 0 ? 0.0 : sim_s / wall}};
    if (stop_signal() != 0) h["interrupted"] = true; // by SIGINT/SIGTERM at sim_time_s
    return h;
}

/// The verdict of a motion run from report["checks"] into `report`; the exit code (verdict/checks.h).
int conclude(nlohmann::json& report) {
    const RunVerdict v = judge_run(report["checks"], stop_signal());
    put_verdict(report, v);
    return exit_code_of(v, stop_signal());
}

/// A scenario with a `motion:` section: the motion side alone (main_cpu/motion, docs/motion.md).
int run_motion_only(const Scenario& s, const RunOptions& opt, nlohmann::json& report) {
    const std::filesystem::path out = opt.out_dir.empty() ? std::filesystem::path(".") : std::filesystem::path(opt.out_dir);
    const auto wall0 = std::chrono::steady_clock::now();
    nlohmann::json motion_report;
    const int rc = run_motion_plan(*s.motion, s.name, out, s.seed, motion_report);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    const nlohmann::json& m = motion_report.contains("motion") ? motion_report["motion"] : motion_report;
    // The error names the file and line already (run/motion_run.h).
    if (rc == 2) throw ConfigError(m.value("error", s.file + ": bad motion section"));
    report = run_header(s, opt, wall);
    nlohmann::json motion = m;
    if (opt.reproducible) {
        // Output paths depend on where the run was started: keep the file names only.
        for (const char* k : {"trajectory_csv", "trajectory_svg", "trajectory_time_svg", "trajectory_pulses_csv"})
            if (motion.contains(k)) motion[k] = std::filesystem::path(motion[k].get<std::string>()).filename().string();
    }
    // The motion checks are report.json "checks", in the one schema of every run (checks.h).
    report["checks"] = motion.value("checks", nlohmann::json::array());
    motion.erase("checks");
    report["motion"] = motion;
    const int code = conclude(report);
    if (!opt.out_dir.empty()) {
        write_report_json(out, report);
        report::write_motion_report_html(out, report);
    }
    return code;
}

/// The remote monitor, when --monitor or the scenario's `monitor:` section asks for one
/// (docs/monitor.md).
/// A run with --modbus alone drives its slices through a monitor without the HTTP server.
std::unique_ptr<monitor::BoardMonitor> start_monitor(World& world, const Scenario& s, const RunOptions& opt) {
    if (!s.monitor && !opt.monitor && !opt.modbus) return nullptr;
    monitor::MonitorOptions mo = s.monitor.value_or(monitor::MonitorOptions{});
    if (opt.monitor) monitor::parse_listen(*opt.monitor, mo);
    const bool http = s.monitor || opt.monitor;
    auto m = std::make_unique<monitor::BoardMonitor>(world, mo, std::cerr, http);
    if (http) std::cout << "monitor: " << m->url() << " (live page; JSON API at /api/v1, docs/monitor.md)" << std::endl;
    return m;
}

/// The Modbus TCP server (--modbus, docs/monitor.md "Modbus TCP"), on the monitor's slices.
std::unique_ptr<modbus::ModbusBridge> start_modbus(monitor::BoardMonitor* mon, const RunOptions& opt) {
    if (!opt.modbus || !mon) return nullptr;
    // "--modbus" alone, or "HOST:", takes the default port.
    std::string text = opt.modbus->empty() ? std::to_string(modbus::kDefaultPort) : *opt.modbus;
    if (text.back() == ':') text += std::to_string(modbus::kDefaultPort);
    monitor::MonitorOptions where;
    try {
        monitor::parse_listen(text, where);
    } catch (const ConfigError&) {
        throw ConfigError("--modbus '" + *opt.modbus + "': not [HOST:]PORT (HOST a numeric IPv4 address, PORT 0..65535)");
    }
    auto b = std::make_unique<modbus::ModbusBridge>(*mon, where.host, where.port, std::cerr);
    std::cout << "modbus: " << where.host << ":" << b->port() << " (Modbus TCP, unit 1; rcsim modbus-map, docs/monitor.md)"
              << std::endl;
    return b;
}

/// A tcp client sent more than the line carried by the end of the run. Not a firmware defect (the
/// line's speed is the limit; the verdict stands), but never a silent pass: the report says so.
std::string unsent_warning(unsigned p, const nlohmann::json& tcp, const SerialFormat& f) {
    const double per_s = 1.0 / f.frame_time().to_seconds();
    std::ostringstream os;
    os << "port " << p << ": " << tcp["bytes_unsent"].get<std::uint64_t>() << " of the bytes the tcp client sent never "
       << "reached the line (" << tcp["bytes_sent"].get<std::uint64_t>() << " did; " << f.describe() << " carries "
       << static_cast<unsigned>(per_s) << " bytes/s; TCP flow control held the client back when the input queue was full, input_stalls "
       << tcp["input_stalls"].get<std::uint64_t>() << ")";
    return os.str();
}

/// report.json "ports", "main_cpu", "dpram", "realtime", "motion".
void report_world(const World& world, const Scenario& s, const RunOptions& opt, TrajectoryFiles* trajectory,
                  nlohmann::json& report) {
    report["ports"] = nlohmann::json::array();
    report["warnings"] = nlohmann::json::array();
    for (unsigned p = 0; p < kPorts; ++p) {
        nlohmann::json pj = port_json(world, p);
        if (s.ports[p].host != PortScenario::Host::none && !world.ctl.comm.uart[p].format_programmed())
            report["warnings"].push_back("port " + std::to_string(p) + ": the firmware never programmed its 82510's "
                                         "character format (it has the reset state's " +
                                         pj["controller_format"].get<std::string>() +
                                         "): the budget and the port's character-latency limit are not measured");
        if (pj.contains("host_format") && pj["host_format"] != pj["controller_format"])
            report["warnings"].push_back("port " + std::to_string(p) + ": the host sends " +
                                         pj["host_format"].get<std::string>() + " but the controller's 82510 is set to " +
                                         pj["controller_format"].get<std::string>());
        if (pj.contains("tcp") && pj["tcp"]["bytes_unsent"].get<std::uint64_t>() > 0)
            report["warnings"].push_back(unsent_warning(p, pj["tcp"], s.ports[p].format()));
        if (world.protocol[p] && s.ports[p].protocol.traffic.pattern == HostTraffic::Pattern::script)
            pj["script"] = script_json(world.protocol[p]->script_result());
        report["ports"].push_back(pj);
    }
    if (!world.probe.interrupts_enabled())
        report["warnings"].push_back("the comm CPU never enabled interrupts (IF stayed 0 from the reset on): "
                                     "no interrupt was taken, no interrupt figure is measured");
    report["main_cpu"] = world.ctl.main.report();
    if (world.program) report["main_cpu"]["program"] = world.program->report();
    report["dpram"] = {{"collisions", world.ctl.dpram.collisions()}};
    if (world.pacer) {
        const auto& ps_ = world.pacer->stats();
        const bool r = opt.reproducible; // the pacer's figures measure the host
        report["realtime"] = {{"rtf_target", ps_.rtf},
                              {"naps", r ? 0 : ps_.naps},
                              {"slept_s", r ? 0.0 : ps_.slept_s},
                              {"max_lag_ms", r ? 0.0 : ps_.max_lag_s * 1e3},
                              {"max_lead_ms", r ? 0.0 : ps_.max_lead_s * 1e3}};
    }
    if (world.motion) {
        report["motion"] = motion_system_json(world);
        if (trajectory)
            trajectory->finish(s.name, circle_overlay(world, s),
                               s.trajectory.pulse_trace ? &world.motion->chip().pulse_trace() : nullptr,
                               trajectory_marks(world));
    }
}

/// The static bound of the run's ROM from its own vectors: report.json "bound", DIR/bound.json
/// and, when the scenario switches it on, the check bound_service_us (docs/tools.md "Bound").
struct BoundRun {
    std::vector<bound::Annotation> annotations;
    nlohmann::json witness;
    std::unique_ptr<VectorCapture> vectors;
};

void add_bound(BoundRun& b, const RomSource& source, const debug::RomSymbols& symbols, const World& world,
               const Scenario& s, const RunOptions& opt, Judgement& judged, nlohmann::json& report) {
    if (!judged.budget.value)
        throw ConfigError("the bound is judged against the budget, which is not measured: " + judged.budget.reason);
    std::ostringstream ran;
    ran << s.duration_s << " s";
    const bound::Result result = bound::analyse(bound_inputs(source, symbols, std::move(b.annotations), *b.vectors,
                                                             s.board, *judged.budget.value, ran.str()));
    report["bound"] = bound_report(result, world, report["interrupts"], b.witness);
    if (!opt.out_dir.empty())
        write_file(std::filesystem::path(opt.out_dir) / "bound.json", bound::to_json(result).dump(2) + "\n", "bound.json");
    if (!s.checks.on.count("bound_service_us")) return;
    judged.checks.push_back(bound_service_check(bound_figures(result), judged.budget));
    judged.verdict = judge_run(judged.checks_json(), stop_signal(), why_no_traffic(world, s));
}

// A row per interrupt is some 350 kB a simulated second of three saturated ports: plain for a run
// of up to kPlainRowsS simulated seconds, to read at a glance; compressed for a longer run, or one
// that lasts until its hosts end it (duration_s 0).
constexpr double kPlainRowsS = 60;

RunOptions::Rows interrupt_rows(const Scenario& s, const RunOptions& opt) {
    if (opt.interrupt_rows != RunOptions::Rows::automatic) return opt.interrupt_rows;
    return s.duration_s > 0 && s.duration_s <= kPlainRowsS ? RunOptions::Rows::plain : RunOptions::Rows::gzip;
}

} // namespace

int run_scenario(Scenario s, const RunOptions& opt, nlohmann::json& report) {
    if (opt.seed) s.set_seed(*opt.seed);
    prepare_out_dir(opt.out_dir);
    // `rcsim run` on a terminal: the progress line, drawn at the stop poller's polls.
    std::optional<RunProgress> progress;
    if (opt.progress && RunProgress::wanted()) progress.emplace(s.duration_s);
    std::function<void()> draw_progress;
    if (progress) draw_progress = [&progress] { progress->poll(); };
    StopPoller stop("stop", draw_progress);
    if (s.has_motion && (!opt.trace.empty() || opt.profile))
        throw ConfigError(s.file + ": a motion scenario runs no communication board: --trace and --profile do not apply");
    // Not an error: a sweep with --coverage may hold motion runs, which have no comm ROM to cover.
    if (s.has_motion && opt.coverage)
        std::cerr << "note: " << s.file << ": a motion scenario runs no communication board: no coverage.info\n";
    if (s.has_motion && opt.modbus)
        throw ConfigError("--modbus: '" + s.file + "' has a 'motion:' section, which runs the motion side alone; "
                          "Modbus TCP serves the whole board (main_cpu: {motion: true}, docs/monitor.md)");
    if (s.has_motion && (opt.monitor || s.monitor))
        throw ConfigError("--monitor: '" + s.file + "' has a 'motion:' section, which runs the motion side alone; "
                          "the monitor watches the whole board (main_cpu: {motion: true}, docs/monitor.md)");
    if (s.has_motion) return run_motion_only(s, opt, report);
    // Logs, records and port files the scenario names relatively land in the run's folder.
    s.place_outputs(opt.out_dir.empty() ? std::filesystem::path(".") : std::filesystem::path(opt.out_dir));
    prepare_output_folders(s.output_files());
    RomSource source = opt.rom ? *opt.rom : s.rom;
    if (source.file.empty()) source.file = RCSIM_COMM_FW_ROM;
    const std::string& rom = source.file; // the image, or the even EPROM
    // Read before the run, so that a bad --symbols file is bad input at once; the causes, the
    // profile, coverage and report.json all name addresses from this one table.
    const debug::RomSymbols symbols = debug::rom_symbols(source, opt.symbols);

    // The probe's records as rows: interrupts.csv (streamed) and report.html's histograms and
    // timeline windows.
    report::InterruptLog interrupts;
    // The bound's inputs that are not the run's: read first, so that bad ones are bad input at once.
    BoundRun bounding;
    const bool bounded = opt.bound || s.checks.on.count("bound_service_us");
    if (!bounded && (!opt.annotations.empty() || !opt.witness.empty()))
        throw ConfigError(std::string(opt.annotations.empty() ? "--witness" : "--annotations") +
                          " needs --bound (or a scenario's checks: {bound_service_us: on})");
    if (bounded) {
        bounding.annotations = run_annotations(source, opt.annotations, symbols);
        if (!opt.witness.empty()) bounding.witness = read_witness(opt.witness);
    }
    World world("world", s);
    world.set_interrupt_sink(&interrupts);
    world.ctl.comm.load_rom(source);
    if (bounded) bounding.vectors = std::make_unique<VectorCapture>(world);
    if (opt.on_world) opt.on_world(world);
    std::unique_ptr<VcdTrace> vcd; // --vcd (vcd_trace.h)
    if (!opt.vcd.empty()) vcd = std::make_unique<VcdTrace>("vcd", world, opt.vcd);
    std::unique_ptr<trace::PerfettoTrace> perfetto;
    if (!opt.trace.empty()) perfetto = std::make_unique<trace::PerfettoTrace>(world, opt.trace);
    std::unique_ptr<trace::ProfileRun> profile;
    if (opt.profile) {
        if (opt.out_dir.empty()) throw ConfigError("--profile needs --out DIR (profile.txt, profile.folded, report.html)");
        profile = std::make_unique<trace::ProfileRun>(world, symbols.table);
    }
    // After the profiler and the debugger: its hook calls theirs (coverage_run.h).
    std::unique_ptr<coverage::CoverageRun> cover;
    if (opt.coverage) {
        if (opt.out_dir.empty()) throw ConfigError("--coverage needs --out DIR (coverage.info, report.html)");
        cover = std::make_unique<coverage::CoverageRun>(world, coverage::run_code_map(symbols, rom, opt.out_dir));
    }
    // interrupts.csv is written as the interrupts complete: a long run keeps none of its rows.
    std::optional<OutputFile> csv;
    std::optional<GzipWriter> gzip;
    const RunOptions::Rows rows = interrupt_rows(s, opt);
    if (!opt.out_dir.empty() && rows != RunOptions::Rows::none) {
        const bool compress = rows == RunOptions::Rows::gzip;
        csv.emplace(std::filesystem::path(opt.out_dir) / (compress ? "interrupts.csv.gz" : "interrupts.csv"));
        if (compress) gzip.emplace(csv->stream());
        interrupts.write_csv_to(gzip ? &*gzip : &csv->stream());
    }

    // trajectory.csv, streamed likewise (report/trajectory_report.h).
    std::optional<TrajectoryFiles> trajectory;
    if (world.motion && !opt.out_dir.empty()) trajectory.emplace(world.motion->recorder(), opt.out_dir, s.trajectory);

    std::unique_ptr<monitor::BoardMonitor> mon = start_monitor(world, s, opt);
    const std::unique_ptr<modbus::ModbusBridge> modbus = start_modbus(mon.get(), opt);
    const auto wall0 = std::chrono::steady_clock::now();
    if (mon) mon->run_until(s.duration_s > 0 ? ps(static_cast<std::uint64_t>(s.duration_s * 1e12 + 0.5)) : sc_core::sc_max_time());
    else if (s.duration_s > 0) world.start_for(ps(static_cast<std::uint64_t>(s.duration_s * 1e12 + 0.5)));
    else sc_core::sc_start(); // duration_s 0: until a tcp client disconnects / a replay log ends (sc_pause)
    if (stop_signal() == 0) world.drain(s.drain_s);
    if (progress) progress->finish(); // before the warnings of the report's making, and the summary
    world.finish_observers();
    world.finish();
    if (opt.on_finished) opt.on_finished(world);
    if (perfetto) perfetto->finish();
    const std::string flame_svg = profile ? profile->finish(opt.out_dir) : std::string();
    const std::string coverage_html = cover ? cover->finish(opt.out_dir) : std::string();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    if (vcd) vcd->close();
    world.finish_files();

    report = run_header(s, opt, wall);
    report["rom"] = std::filesystem::path(rom).filename().string() +
                    (source.odd.empty() ? "" : " + " + std::filesystem::path(source.odd).filename().string());
    report["rom_format"] = world.ctl.comm.rom_format();
    const debug::RomSymbolsSummary named = debug::summary(symbols);
    report["symbols"] = {{"origin", named.origin}, {"file", named.file}, {"count", named.count}};
    report["comm_cpu"] = {{"cycles", world.ctl.comm.cpu.cycles()},
                          {"instructions", world.ctl.comm.cpu.instructions()},
                          {"clock_hz", s.board.comm.cpu_hz},
                          {"quantum_us", to_us(s.board.comm.quantum)}};
    // The one judge (verdict/judge.h): the same figures and verdict the live page and Modbus show.
    const SymbolOf symbol = cause_symbols(symbols.table);
    Judgement judged = judge(world, s, Moment::end, stop_signal(), symbol);
    report["interrupts"] = judged.interrupts.interrupts;
    report["bus_errors"] = to_json(world.ctl.comm.cpu.bus_errors());
    report["table3"] = judged.table3;
    add_latency_causes(report["interrupts"], world, judged.budget.value, symbol);
    report_world(world, s, opt, trajectory ? &*trajectory : nullptr, report);
    if (bounded) add_bound(bounding, source, symbols, world, s, opt, judged, report);
    report["checks"] = judged.checks_json();
    report["checks_off"] = s.checks.off;
    put_verdict(report, judged.verdict);
    const int code = exit_code_of(judged.verdict, stop_signal());

    if (!opt.out_dir.empty()) {
        write_report_json(opt.out_dir, report);
        if (gzip) gzip->finish();
        if (csv) csv->close();
        report::write_report_html(opt.out_dir, report, interrupts, flame_svg, coverage_html);
    }
    return code;
}

} // namespace rcsim
