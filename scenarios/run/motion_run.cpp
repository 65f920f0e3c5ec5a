// rcsim — the motion scenario runner. See motion_run.h and docs/motion.md.
#include "scenarios/run/motion_run.h"

#include "main_cpu/dispatcher.h"
#include "main_cpu/motion/motion_controller.h"
#include "main_cpu/st/program.h"
#include "models/clock.h"
#include "models/plumbing/config_error.h"
#include "scenarios/verdict/motion_checks.h"
#include "scenarios/report/trajectory_report.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>

namespace rcsim {
namespace {

using motion::MotionController;

/// Drives the control cycle and the timed commands, and watches every function-block command
/// for its outcome after each cycle.
struct MotionDriver : sc_core::sc_module {
    MotionController& mc;
    std::vector<TimedCommand> cmds;
    sc_core::sc_time cycle;
    std::uint64_t cycles;
    nlohmann::json log = nlohmann::json::array();
    std::vector<FbCommand> fbs;           // every function-block command issued, in order
    std::vector<std::size_t> fb_log;      // its entry in `log`
    std::optional<ArcRun> arc;            // the MC_CircleCenterMove, if any
    std::size_t arc_fb = 0;               // its entry in `fbs`
    std::vector<std::pair<std::size_t, Watch>> pending; // fbs entries without an outcome yet
    MotionObserver on_cycle;
    Dispatcher* dispatcher = nullptr;      // with a program: the tokens go through it (RN, SP, ST)
    st::StProgram* program = nullptr;      // run once per cycle after the motion layer's

    SC_HAS_PROCESS(MotionDriver);
    MotionDriver(sc_core::sc_module_name n, MotionController& m, sc_core::sc_time c, std::uint64_t count)
        : sc_module(n), mc(m), cycle(c), cycles(count) {
        SC_THREAD(run);
    }

    void issue(TimedCommand& c, double now) {
        Issued is = c.issue(mc);
        // A new command on a block instance takes it over: the block reports on it alone now.
        for (auto it = pending.begin(); it != pending.end();)
            if (is.watch.block && it->second.block == is.watch.block) {
                set_outcome(it->first, FbOutcome::superseded, 0, now);
                it = pending.erase(it);
            } else {
                ++it;
            }
        fbs.push_back(c.fb);
        fb_log.push_back(log.size());
        log.push_back(nullptr); // filled with the outcome after the run
        if (is.arc) {
            arc = ArcRun{*is.arc, now, -1};
            arc_fb = fbs.size() - 1;
            mc.recorder().start_window(); // the checks judge its samples, every one
        }
        pending.emplace_back(fbs.size() - 1, std::move(is.watch));
    }

    void token(const TimedCommand& c) {
        const Outcome o = dispatcher->execute(c.token, c.data);
        log.push_back({{"token", c.token}, {"data", c.data}, {"bch", o.bch}, {"reply", o.data}});
        if (!o.note.empty()) log.back()["note"] = o.note;
    }

    void set_outcome(std::size_t i, FbOutcome o, std::uint16_t id, double now) {
        fbs[i].outcome = o;
        fbs[i].error_id = id;
        fbs[i].outcome_s = now;
    }

    void poll(double now) {
        for (auto it = pending.begin(); it != pending.end();)
            if (const auto r = it->second.poll()) {
                set_outcome(it->first, r->first, r->second, now);
                it = pending.erase(it);
            } else {
                ++it;
            }
    }

    void run() {
        std::size_t next = 0;
        for (std::uint64_t k = 0; k <= cycles; ++k) {
            const sc_core::sc_time now = sc_core::sc_time_stamp();
            while (next < cmds.size() && cmds[next].at_s <= now.to_seconds() + 1e-12) {
                TimedCommand& c = cmds[next++];
                if (c.issue) issue(c, now.to_seconds());
                else if (dispatcher && !c.token.empty()) token(c);
                else c.run(mc, log);
            }
            mc.control_cycle(now);
            if (program) program->cycle(now);
            poll(now.to_seconds());
            if (arc && fbs[arc_fb].outcome_s >= 0) mc.recorder().end_window();
            if (on_cycle) on_cycle(mc.snapshot());
            if (k < cycles) wait(cycle);
        }
        const double end = sc_core::sc_time_stamp().to_seconds();
        for (std::size_t i = 0; i < fbs.size(); ++i) log[fb_log[i]] = fbs[i].to_json();
        if (arc) arc->t1_s = fbs[arc_fb].outcome_s < 0 ? end : fbs[arc_fb].outcome_s;
        sc_core::sc_stop();
    }
};

/// The verdicts of the finished run, in report order.
std::vector<Check> judge(const CheckPlan& p, MotionController& mc, const MotionDriver& d) {
    std::vector<Check> checks{fb_outcome_check(d.fbs)};
    if (!p.final_state.empty()) checks.push_back(final_state_check(p.final_state, mc.state()));
    if (p.has_final_positions) {
        std::vector<std::int64_t> got;
        for (unsigned a = 0; a < MotionController::axes; ++a) got.push_back(mc.chip().command_position(a));
        checks.push_back(final_positions_check(p.final_positions, got, p.position_tolerance));
    }
    if (d.program) checks.push_back(program_check(*d.program));
    if (p.circle)
        for (Check& c : circle_checks(*p.circle, d.arc, mc.recorder().window(),
                                      "the scenario has no MC_CircleCenterMove command"))
            checks.push_back(std::move(c));
    return checks;
}

/// The figures of the finished run into `rep`.
void report_run(MotionController& mc, const MotionPlan& p, const MotionDriver& driver,
                const std::vector<Check>& checks, nlohmann::json& rep) {
    std::vector<std::int64_t> cmd(4), act(4);
    for (unsigned a = 0; a < 4; ++a) {
        cmd[a] = mc.chip().command_position(a);
        act[a] = mc.chip().encoder_position(a);
    }
    rep["control_cycle_ms"] = p.cycle_ms;
    rep["duration_s"] = p.duration_s;
    rep["final_cmd_pulses"] = cmd;
    rep["final_act_pulses"] = act;
    rep["state"] = mc.state();
    rep["max_following_error_pulses"] = mc.recorder().max_following_error();
    rep["samples"] = mc.recorder().count();
    rep["commands"] = driver.log;
    if (driver.program) rep["program"] = driver.program->report();
    rep["checks"] = nlohmann::json::array();
    for (const Check& c : checks) rep["checks"].push_back(to_json(c));
}

} // namespace

int run_motion_scenario(const YAML::Node& root, const std::string& file, const std::filesystem::path& out_dir,
                        std::uint64_t seed, nlohmann::json& report, const MotionObserver& on_cycle) {
    MotionPlan plan;
    try {
        plan = read_motion_plan(root, file);
    } catch (const ConfigError& e) {
        report["motion"] = {{"seed", seed}, {"error", e.what()}};
        return 2;
    } catch (const YAML::Exception& e) {
        report["motion"] = {{"seed", seed}, {"error", file + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg}};
        return 2;
    }
    // The pictures' title: the scenario's name (as rcsim run reports it), not its path.
    const std::string name = root["name"] && root["name"].IsScalar() ? root["name"].Scalar()
                                                                     : std::filesystem::path(file).stem().string();
    return run_motion_plan(std::move(plan), name, out_dir, seed, report, on_cycle);
}

int run_motion_plan(MotionPlan plan, const std::string& name, const std::filesystem::path& out_dir,
                    std::uint64_t seed, nlohmann::json& report, const MotionObserver& on_cycle) {
    nlohmann::json& rep = report["motion"];
    rep["seed"] = seed; // the motion layer draws no random numbers; recorded for the report
    const auto cycle = ps(static_cast<std::uint64_t>(std::llround(plan.cycle_ms * 1e9)));
    const auto count = static_cast<std::uint64_t>(std::llround(plan.duration_s * 1000 / plan.cycle_ms));
    MotionController mc("motion", plan.cfg);
    if (plan.trajectory.pulse_trace)
        for (unsigned a = 0; a < MotionController::axes; ++a) mc.chip().trace_pulses(a, true);
    MotionDriver driver("motion_runner", mc, cycle, count);
    driver.cmds = std::move(plan.cmds);
    driver.on_cycle = on_cycle;
    std::unique_ptr<st::StProgram> program;
    Dispatcher dispatcher;
    if (!plan.program_text.empty()) {
        std::vector<motion::McAxis*> axes;
        std::vector<motion::MC_Power*> power;
        for (unsigned a = 0; a < MotionController::axes; ++a) {
            axes.push_back(&mc.axis(a));
            power.push_back(&mc.power(a));
        }
        try {
            program = std::make_unique<st::StProgram>(plan.program_text, plan.program_path, axes, power,
                                                      st::StProgram::Config{plan.program_budget});
        } catch (const st::CompileError& e) {
            rep["error"] = e.what(); // file:line:column of the .st file
            return 2;
        }
        dispatcher.set_motion(&mc);
        dispatcher.set_program(program.get());
        driver.dispatcher = &dispatcher;
        driver.program = program.get();
    }
    // trajectory.csv streams as the run goes (memory stays flat over any run's length).
    std::optional<TrajectoryFiles> files;
    try {
        std::filesystem::create_directories(out_dir);
        files.emplace(mc.recorder(), out_dir, plan.trajectory);
    } catch (const std::exception& e) {
        rep["error"] = e.what();
        return 2;
    }
    sc_core::sc_start();

    const std::vector<Check> checks = judge(plan.checks, mc, driver);
    const bool ok = std::all_of(checks.begin(), checks.end(), [](const Check& c) { return c.passed(); });
    report_run(mc, plan, driver, checks, rep);
    try {
        std::optional<CircleOverlay> circle;
        if (plan.checks.circle && driver.arc)
            circle = CircleOverlay{plan.checks.circle->center_x, plan.checks.circle->center_y,
                                   plan.checks.circle->radius, driver.arc->t0_s, driver.arc->t1_s,
                                   plan.checks.circle->max_radial_error};
        files->finish(name, circle, plan.trajectory.pulse_trace ? &mc.chip().pulse_trace() : nullptr);
        rep["trajectory_csv"] = (out_dir / "trajectory.csv").string();
        rep["trajectory_svg"] = (out_dir / "trajectory.svg").string();
        rep["trajectory_time_svg"] = (out_dir / "trajectory_time.svg").string();
        if (plan.trajectory.pulse_trace) rep["trajectory_pulses_csv"] = (out_dir / "trajectory_pulses.csv").string();
    } catch (const std::exception& e) {
        rep["error"] = e.what();
        return 2;
    }
    return ok ? 0 : 1;
}

} // namespace rcsim
