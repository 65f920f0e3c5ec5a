// rcsim — the motion scenario runner. See motion_scenario.h and docs/motion.md.
#include "scenarios/motion_scenario.h"

#include "main_cpu/dispatcher.h"
#include "main_cpu/motion/motion_controller.h"
#include "main_cpu/st/program.h"
#include "models/clock.h"
#include "models/config_error.h"
#include "scenarios/motion_checks.h"
#include "scenarios/trajectory_report.h"
#include "scenarios/yaml_map.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>

namespace rcsim {
namespace {

using motion::BufferMode;
using motion::MotionController;

/// How an issued function-block command is watched: its block's outputs after every cycle.
struct Watch {
    const void* block = nullptr; // the block instance (nullptr: an input change, nothing to supersede)
    std::function<std::optional<std::pair<FbOutcome, std::uint16_t>>()> poll;
};

/// A function-block command as issued: the watch, and for MC_CircleCenterMove its arc in
/// absolute pulses (the block takes centre and end relative to where the axes are).
struct Issued {
    Watch watch;
    std::optional<CommandedArc> arc;
};

struct TimedCommand {
    double at_s = 0;
    std::function<void(MotionController&, nlohmann::json&)> run; // tokens and faults: log entry
    std::function<Issued(MotionController&)> issue;              // function blocks
    FbCommand fb;                                                // function blocks: the expectation
    std::string token, data;                                     // tokens: through the dispatcher with a program
};

/// `motion.checks`, judged after the run.
struct CheckPlan {
    std::string final_state; // "" = no check
    std::vector<std::int64_t> final_positions;
    bool has_final_positions = false;
    double position_tolerance = 0;
    std::optional<CircleLimits> circle;
};

/// Everything the `motion:` section asks for.
struct MotionPlan {
    motion::MotionConfig cfg;
    double cycle_ms = 1, duration_s = 0;
    std::vector<TimedCommand> cmds;
    CheckPlan checks;
    TrajectoryOptions trajectory; // motion.trajectory
    // `motion.program`: a Structured Text file (docs/st.md), started and stopped by RN/SP tokens.
    std::string program_path, program_text;
    std::uint64_t program_budget = 100000;
};

constexpr double big = 1e9;

BufferMode buffer_of(YamlMap& f) {
    return f.choice("buffer", "aborting", {"aborting", "buffered"}) == "buffered" ? BufferMode::buffered
                                                                                  : BufferMode::aborting;
}

/// Watches an Execute-type block: Done, Error (with ErrorID) or CommandAborted, each visible for
/// at least the call that set it, that is, after the control cycle in which it appeared.
Watch watch_execute(motion::McExecuteFb& fb) {
    return {&fb, [&fb]() -> std::optional<std::pair<FbOutcome, std::uint16_t>> {
                if (fb.Done) return std::make_pair(FbOutcome::done, std::uint16_t{0});
                if (fb.Error) return std::make_pair(FbOutcome::error, fb.ErrorID);
                if (fb.CommandAborted) return std::make_pair(FbOutcome::aborted, std::uint16_t{0});
                return std::nullopt;
            }};
}

/// Sets a block's inputs and raises Execute (a new edge if it was already high); the token
/// program drops Execute again once the block reports its outcome.
template <typename Fb> Issued trigger(MotionController& mc, Fb& fb) {
    fb.Execute = false; // a falling edge first, so that Execute rises again
    fb.call();
    fb.Execute = true;
    mc.auto_release(fb);
    return {watch_execute(fb), std::nullopt};
}

/// MC_Power: done once Status follows Enable (the drive in Operation enabled, or off), error
/// with the block's ErrorID (power_timeout).
Issued power_command(MotionController& mc, unsigned a, bool en) {
    motion::MC_Power& p = mc.power(a);
    p.Enable = en;
    return {{&p, [&p, en]() -> std::optional<std::pair<FbOutcome, std::uint16_t>> {
                 if (p.Error) return std::make_pair(FbOutcome::error, p.ErrorID);
                 if (p.Status == en) return std::make_pair(FbOutcome::done, std::uint16_t{0});
                 return std::nullopt;
             }},
            std::nullopt};
}

/// MC_Stop holds the axis in Stopping while Execute is high: `execute: 1` raises it (done when
/// the axis has stopped), `execute: 0` drops it, an input change that is done at once.
Issued stop_command(MotionController& mc, unsigned a, double dec, bool exec) {
    motion::MC_Stop& b = mc.blocks(a).stop;
    b.Deceleration = dec;
    if (!exec) {
        b.Execute = false;
        return {{nullptr, [] { return std::make_optional(std::make_pair(FbOutcome::done, std::uint16_t{0})); }},
                std::nullopt};
    }
    b.Execute = false; // a falling edge first, so that Execute rises again
    b.call();
    b.Execute = true;
    return {watch_execute(b), std::nullopt};
}

/// Positions, distances and centres are whole pulses in the chip's range (+-(2^30 - 1)): a
/// fraction is refused, not truncated on its way to the block's integer input. `what` names the
/// value in the message.
std::int32_t whole_pulses(const YamlMap& f, const YAML::Node& at, double x, const std::string& what) {
    constexpr double lim = double((1 << 30) - 1);
    if (x != std::floor(x)) f.fail(at, "'" + what + "' must be a whole number of pulses");
    if (std::fabs(x) > lim)
        f.fail(at, "'" + what + "' = " + std::to_string(static_cast<std::int64_t>(x)) +
                       " pulses is out of the chip's range [-1073741823, 1073741823]");
    return static_cast<std::int32_t>(x);
}

/// MC_LineMove over 2-4 axes of the chip: `axes: [i, ...]` (distinct) and `distances: [...]`, one
/// whole-pulse distance per axis relative to its position when the command runs.
template <typename Number>
std::function<Issued(MotionController&)> read_line_move(YamlMap& f, Number v) {
    const std::vector<double> axes = f.list<double>("axes", MotionController::axes + 1);
    const std::vector<double> dist = f.list<double>("distances", MotionController::axes + 1);
    if (axes.size() < 2 || axes.size() > MotionController::axes)
        f.fail(f.has("axes") ? f.child("axes") : f.child("fb"), "'" + f.context() + "axes' must list 2 to 4 axes");
    if (dist.size() != axes.size())
        f.fail(f.has("distances") ? f.child("distances") : f.child("axes"),
               "'" + f.context() + "distances' must hold one distance per axis (" + std::to_string(axes.size()) + ")");
    std::vector<unsigned> ids;
    std::vector<std::int32_t> d;
    for (std::size_t i = 0; i < axes.size(); ++i) {
        const std::string at = f.context() + "axes[" + std::to_string(i) + "]";
        if (axes[i] != std::floor(axes[i]) || axes[i] < 0 || axes[i] >= MotionController::axes)
            f.fail(f.child("axes")[i], "'" + at + "' must be an axis 0 to 3");
        const auto a = static_cast<unsigned>(axes[i]);
        if (std::find(ids.begin(), ids.end(), a) != ids.end())
            f.fail(f.child("axes")[i], "'" + f.context() + "axes' names axis " + std::to_string(a) + " twice");
        ids.push_back(a);
        d.push_back(whole_pulses(f, f.child("distances")[i], dist[i],
                                 f.context() + "distances[" + std::to_string(i) + "]"));
    }
    const double vel = v("velocity"), acc = v("acceleration"), dec = v("deceleration");
    const BufferMode m = buffer_of(f);
    return [=](MotionController& mc) {
        auto& b = mc.line_move_n();
        b.Axes.clear();
        for (unsigned a : ids) b.Axes.push_back(&mc.axis(a));
        b.Distances = d;
        b.Velocity = vel, b.Acceleration = acc, b.Deceleration = dec, b.Mode = m;
        return trigger(mc, b);
    };
}

/// The inputs of the PLCopen block `fb`, read from its command, applied when the command runs.
std::function<Issued(MotionController&)> read_block(YamlMap& f, const std::string& fb) {
    auto axis_of = [&]() { return static_cast<unsigned>(f.require_number("axis", 0, 3)); };
    auto v = [&](const char* k) { return f.require_number(k, -big, big); };
    auto pulses = [&](const char* k, std::optional<double> fallback = std::nullopt) {
        const double x = fallback ? f.number(k, *fallback, -big * 10, big * 10) : f.require_number(k, -big * 10, big * 10);
        return whole_pulses(f, f.child(k), x, f.context() + k);
    };
    if (fb == "MC_Power") {
        const unsigned a = axis_of();
        const bool en = f.number("enable", 1, 0, 1) != 0;
        return [a, en](MotionController& mc) { return power_command(mc, a, en); };
    }
    if (fb == "MC_Reset") {
        const unsigned a = axis_of();
        return [a](MotionController& mc) { return trigger(mc, mc.blocks(a).reset); };
    }
    if (fb == "MC_Home") {
        const unsigned a = axis_of();
        const std::int32_t pos = pulses("position", 0.0);
        const double dir = f.number("direction", -1, -1, 1);
        const double vel = f.number("velocity", 10000, -big, big);
        const bool z = f.get<bool>("z_phase", false);
        const double zvel = f.number("z_velocity", motion::MC_Home{}.ZVelocity, 1, big);
        return [a, pos, dir, vel, z, zvel](MotionController& mc) {
            auto& b = mc.blocks(a).home;
            b.Position = pos, b.Direction = dir < 0 ? -1 : 1, b.Velocity = vel, b.ZPhase = z, b.ZVelocity = zvel;
            return trigger(mc, b);
        };
    }
    if (fb == "MC_MoveAbsolute" || fb == "MC_MoveRelative") {
        const unsigned a = axis_of();
        const bool absolute = fb == "MC_MoveAbsolute";
        const std::int32_t p = pulses(absolute ? "position" : "distance");
        const double vel = v("velocity"), acc = v("acceleration"), dec = v("deceleration");
        const BufferMode m = buffer_of(f);
        return [=](MotionController& mc) {
            if (absolute) {
                auto& b = mc.blocks(a).move_abs;
                b.Position = p, b.Velocity = vel, b.Acceleration = acc, b.Deceleration = dec, b.Mode = m;
                return trigger(mc, b);
            }
            auto& b = mc.blocks(a).move_rel;
            b.Distance = p, b.Velocity = vel, b.Acceleration = acc, b.Deceleration = dec, b.Mode = m;
            return trigger(mc, b);
        };
    }
    if (fb == "MC_Halt") {
        const unsigned a = axis_of();
        const double dec = f.number("deceleration", 0, 0, big);
        return [=](MotionController& mc) {
            mc.blocks(a).halt.Deceleration = dec;
            return trigger(mc, mc.blocks(a).halt);
        };
    }
    if (fb == "MC_Stop") {
        const unsigned a = axis_of();
        const double dec = f.number("deceleration", 0, 0, big);
        const bool exec = f.number("execute", 1, 0, 1) != 0;
        return [=](MotionController& mc) { return stop_command(mc, a, dec, exec); };
    }
    if (fb == "MC_LineMove2") {
        const std::int32_t x = pulses("x"), y = pulses("y");
        const double vel = v("velocity"), acc = v("acceleration"), dec = v("deceleration");
        const BufferMode m = buffer_of(f);
        return [=](MotionController& mc) {
            auto& b = mc.line_move();
            b.X = x, b.Y = y, b.Velocity = vel, b.Acceleration = acc, b.Deceleration = dec, b.Mode = m;
            return trigger(mc, b);
        };
    }
    if (fb == "MC_LineMove") return read_line_move(f, v);
    if (fb == "MC_CircleCenterMove") {
        const std::int32_t cx = pulses("center_x"), cy = pulses("center_y"), ex = pulses("end_x"), ey = pulses("end_y");
        const bool cw = f.choice("direction", "ccw", {"cw", "ccw"}) == "cw";
        const double vel = v("velocity"), acc = v("acceleration"), dec = v("deceleration");
        const BufferMode m = buffer_of(f);
        return [=](MotionController& mc) {
            auto& b = mc.circle_move();
            b.CenterX = cx, b.CenterY = cy, b.EndX = ex, b.EndY = ey, b.Direction = cw ? motion::dir_cw : motion::dir_ccw;
            b.Velocity = vel, b.Acceleration = acc, b.Deceleration = dec, b.Mode = m;
            // Centre and end are relative to the command position of axes 0/1 now.
            const double x = double(mc.chip().command_position(0)), y = double(mc.chip().command_position(1));
            Issued is = trigger(mc, b);
            is.arc = CommandedArc{x, y, x + cx, y + cy, x + ex, y + ey, !cw};
            return is;
        };
    }
    f.fail(f.child("fb"), "unknown function block '" + fb + "'");
}

/// `expect` and `error_id` of a function-block command: the outcome the scenario expects.
void read_expectation(YamlMap& f, FbCommand& c) {
    const std::string e = f.choice("expect", "done", {"done", "error", "aborted"});
    c.expect = e == "done" ? FbOutcome::done : e == "error" ? FbOutcome::error : FbOutcome::aborted;
    if (!f.has("error_id")) return;
    if (c.expect != FbOutcome::error)
        f.fail(f.child("error_id"), "'" + f.context() + "error_id' is the ErrorID of 'expect: error'");
    c.expect_error_id = f.require<std::uint16_t>("error_id");
}

/// One entry of `motion.commands`: a motion token, a drive fault, or a PLCopen block.
TimedCommand read_command(YamlMap f) {
    TimedCommand c;
    c.at_s = f.require_number("at_ms", 0, big) / 1000.0;
    if (f.has("token")) {
        const std::string tok = f.require<std::string>("token"), data = f.get<std::string>("data", "");
        c.token = tok;
        c.data = data;
        c.run = [tok, data](MotionController& mc, nlohmann::json& log) {
            const MotionReply r = mc.command(tok, data);
            log.push_back({{"token", tok}, {"data", data}, {"bch", r.bch}, {"reply", r.data}});
        };
    } else if (f.has("inject_fault")) {
        const unsigned axis = static_cast<unsigned>(f.require_number("inject_fault", 0, 3));
        // An integer, so that the hex CiA402 codes read as written: code: 0x7500.
        const std::uint16_t code = f.get<std::uint16_t>("code", 0x7500);
        const bool clear = f.choice("clear_after", "no", {"yes", "no"}) == "yes";
        c.run = [axis, code, clear](MotionController& mc, nlohmann::json& log) {
            mc.drive(axis).inject_fault(code);
            if (clear) mc.drive(axis).clear_fault_cause();
            log.push_back({{"inject_fault", axis}, {"code", code}});
        };
    } else {
        c.fb.fb = f.require<std::string>("fb");
        c.fb.at_s = c.at_s;
        c.issue = read_block(f, c.fb.fb);
        read_expectation(f, c.fb);
    }
    f.finish();
    return c;
}

CircleLimits read_circle(YamlMap cc) {
    CircleLimits c;
    c.center_x = cc.require_number("center_x", -big, big);
    c.center_y = cc.require_number("center_y", -big, big);
    c.radius = cc.require_number("radius", 0, big);
    c.max_radial_error = cc.number("max_radial_error", 1, 0, big);
    c.max_end_error = cc.number("max_end_error", 0, 0, big);
    cc.finish();
    return c;
}

/// `motion.checks`. `circles` is the number of MC_CircleCenterMove commands: the circle check
/// judges one.
CheckPlan read_checks(YamlMap c, std::size_t circles) {
    CheckPlan p;
    p.final_state = c.get<std::string>("final_state", "");
    p.has_final_positions = c.has("final_positions");
    if (p.has_final_positions) {
        p.final_positions = c.list<std::int64_t>("final_positions", motion::MotionController::axes);
        p.position_tolerance = c.number("position_tolerance", 0, 0, 1e9);
    }
    if (c.has("circle")) {
        if (circles > 1)
            c.fail(c.child("circle"), "'" + c.context() + "circle' judges one MC_CircleCenterMove; the scenario has " +
                                          std::to_string(circles));
        p.circle = read_circle(c.map("circle"));
    }
    c.finish();
    return p;
}

/// `motion.program` (a file relative to the scenario's folder) and `motion.statement_budget`.
void read_program(YamlMap& m, const std::string& file, MotionPlan& p) {
    const std::filesystem::path rel = m.require<std::string>("program");
    const std::filesystem::path path = rel.is_absolute() ? rel : std::filesystem::path(file).parent_path() / rel;
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    if (!in) m.fail(m.child("program"), "cannot read the Structured Text program '" + path.string() + "'");
    p.program_path = path.string();
    p.program_text = text.str();
    p.program_budget = static_cast<std::uint64_t>(m.number("statement_budget", 100000, 1, 1e9));
}

/// The whole `motion:` section; throws ConfigError naming file and line.
MotionPlan read_plan(const YAML::Node& root, const std::string& file) {
    if (!root["motion"]) throw ConfigError(file, 0, "no 'motion:' section");
    YamlMap m(root["motion"], file, "motion.");
    MotionPlan p;
    p.cycle_ms = m.number("control_cycle_ms", 1, 0.01, 1000);
    p.duration_s = m.require_number("duration_s", 0, 3600);
    p.cfg.drive.following_lag_s = m.number("following_lag_ms", 2, 0, 1000) / 1000.0;
    p.cfg.start_speed = m.number("start_speed", 100, 1, 1e6);
    if (m.has("program")) read_program(m, file, p);
    std::size_t i = 0;
    for (YamlMap& a : m.maps("axes", motion::MotionController::axes)) {
        auto opt = [&](const char* k) -> std::optional<std::int64_t> {
            if (!a.has(k)) return std::nullopt;
            return std::llround(a.number(k, 0, -big, big));
        };
        p.cfg.zphase[i] = {static_cast<std::int64_t>(a.integer("z_pitch", 0, 0, 1u << 30)), opt("z_offset").value_or(0)};
        p.cfg.switches[i++] = {opt("pelm"), opt("nelm"), opt("home")};
        a.finish();
    }
    std::size_t circles = 0;
    for (YamlMap& c : m.maps("commands")) {
        p.cmds.push_back(read_command(c));
        p.cmds.back().fb.index = p.cmds.size() - 1;
        circles += p.cmds.back().fb.fb == "MC_CircleCenterMove";
    }
    std::stable_sort(p.cmds.begin(), p.cmds.end(), [](auto& x, auto& y) { return x.at_s < y.at_s; });
    p.checks = read_checks(m.map("checks"), circles);
    p.trajectory = read_trajectory_options(m.map("trajectory"));
    m.finish();
    return p;
}

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
        for (Check& c : circle_checks(*p.circle, d.arc, mc.recorder().samples(),
                                      "the scenario has no MC_CircleCenterMove command"))
            checks.push_back(std::move(c));
    return checks;
}

/// The figures of the finished run into `rep`.
void report_run(MotionController& mc, const MotionPlan& p, const MotionDriver& driver,
                const std::vector<Check>& checks, nlohmann::json& rep) {
    std::vector<std::int64_t> cmd(4), act(4);
    double max_follow = 0;
    for (const auto& s : mc.recorder().samples())
        for (unsigned a = 0; a < 4; ++a) max_follow = std::max(max_follow, static_cast<double>(std::llabs(s.cmd[a] - s.act[a])));
    for (unsigned a = 0; a < 4; ++a) {
        cmd[a] = mc.chip().command_position(a);
        act[a] = mc.chip().encoder_position(a);
    }
    rep["control_cycle_ms"] = p.cycle_ms;
    rep["duration_s"] = p.duration_s;
    rep["final_cmd_pulses"] = cmd;
    rep["final_act_pulses"] = act;
    rep["state"] = mc.state();
    rep["max_following_error_pulses"] = max_follow;
    rep["samples"] = mc.recorder().samples().size();
    rep["commands"] = driver.log;
    if (driver.program) rep["program"] = driver.program->report();
    rep["checks"] = nlohmann::json::array();
    for (const Check& c : checks) rep["checks"].push_back(to_json(c));
}

} // namespace

int run_motion_scenario(const YAML::Node& root, const std::string& file, const std::filesystem::path& out_dir,
                        std::uint64_t seed, nlohmann::json& report, const MotionObserver& on_cycle) {
    nlohmann::json& rep = report["motion"];
    rep["seed"] = seed; // the motion layer draws no random numbers; recorded for the report
    MotionPlan plan;
    try {
        plan = read_plan(root, file);
    } catch (const ConfigError& e) {
        rep["error"] = e.what();
        return 2;
    } catch (const YAML::Exception& e) {
        rep["error"] = file + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg;
        return 2;
    }

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
    sc_core::sc_start();

    const std::vector<Check> checks = judge(plan.checks, mc, driver);
    const bool ok = std::all_of(checks.begin(), checks.end(), [](const Check& c) { return c.passed(); });
    report_run(mc, plan, driver, checks, rep);
    try {
        std::filesystem::create_directories(out_dir);
        // The pictures' title: the scenario's name (as rcsim run reports it), not its path.
        const std::string name = root["name"] && root["name"].IsScalar() ? root["name"].Scalar()
                                                                         : std::filesystem::path(file).stem().string();
        std::optional<CircleOverlay> circle;
        if (plan.checks.circle && driver.arc)
            circle = CircleOverlay{plan.checks.circle->center_x, plan.checks.circle->center_y,
                                   plan.checks.circle->radius, driver.arc->t0_s, driver.arc->t1_s};
        write_trajectory_files(mc.recorder(), out_dir, name, circle, plan.trajectory,
                               plan.trajectory.pulse_trace ? &mc.chip().pulse_trace() : nullptr);
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
