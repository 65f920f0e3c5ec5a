// rcsim — the motion scenario runner. See motion_scenario.h and docs/motion.md.
#include "scenarios/motion_scenario.h"

#include "main_cpu/motion/motion_controller.h"
#include "models/clock.h"
#include "models/config_error.h"
#include "scenarios/trajectory_report.h"
#include "scenarios/yaml_map.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>

namespace rcsim {
namespace {

using motion::BufferMode;
using motion::MotionController;

struct TimedCommand {
    double at_s = 0;
    std::function<void(MotionController&, nlohmann::json&)> run;
};

/// A check on the finished run: appends its result to the list and clears `ok` when it fails.
using Check = std::function<void(MotionController&, nlohmann::json&, bool&)>;

/// Everything the `motion:` section asks for.
struct MotionPlan {
    motion::MotionConfig cfg;
    double cycle_ms = 1, duration_s = 0;
    std::vector<TimedCommand> cmds;
    std::vector<Check> checks;
};

constexpr double big = 1e9;

BufferMode buffer_of(YamlMap& f) {
    return f.choice("buffer", "aborting", {"aborting", "buffered"}) == "buffered" ? BufferMode::buffered
                                                                                  : BufferMode::aborting;
}

/// Sets a block's inputs and raises Execute (a new edge if it was already high).
template <typename Fb> void trigger(MotionController& mc, Fb& fb) {
    fb.Execute = false; // a falling edge first, so that Execute rises again
    fb.call();
    fb.Execute = true;
    mc.auto_release(fb);
}

/// The inputs of the PLCopen block `fb`, read from its command, applied when the command runs.
std::function<void(MotionController&)> read_block(YamlMap& f, const std::string& fb) {
    auto axis_of = [&]() { return static_cast<unsigned>(f.require_number("axis", 0, 3)); };
    auto v = [&](const char* k) { return f.require_number(k, -big, big); };
    if (fb == "MC_Power") {
        const unsigned a = axis_of();
        const bool en = f.number("enable", 1, 0, 1) != 0;
        return [a, en](MotionController& mc) { mc.power(a).Enable = en; };
    }
    if (fb == "MC_Reset") {
        const unsigned a = axis_of();
        return [a](MotionController& mc) { trigger(mc, mc.blocks(a).reset); };
    }
    if (fb == "MC_Home") {
        const unsigned a = axis_of();
        const double pos = f.number("position", 0, -big, big), dir = f.number("direction", -1, -1, 1);
        const double vel = f.number("velocity", 10000, -big, big);
        return [a, pos, dir, vel](MotionController& mc) {
            auto& b = mc.blocks(a).home;
            b.Position = pos, b.Direction = dir < 0 ? -1 : 1, b.Velocity = vel;
            trigger(mc, b);
        };
    }
    if (fb == "MC_MoveAbsolute" || fb == "MC_MoveRelative") {
        const unsigned a = axis_of();
        const bool absolute = fb == "MC_MoveAbsolute";
        const double p = v(absolute ? "position" : "distance");
        const double vel = v("velocity"), acc = v("acceleration"), dec = v("deceleration");
        const BufferMode m = buffer_of(f);
        return [=](MotionController& mc) {
            if (absolute) {
                auto& b = mc.blocks(a).move_abs;
                b.Position = p, b.Velocity = vel, b.Acceleration = acc, b.Deceleration = dec, b.Mode = m;
                trigger(mc, b);
            } else {
                auto& b = mc.blocks(a).move_rel;
                b.Distance = p, b.Velocity = vel, b.Acceleration = acc, b.Deceleration = dec, b.Mode = m;
                trigger(mc, b);
            }
        };
    }
    if (fb == "MC_Halt" || fb == "MC_Stop") {
        const unsigned a = axis_of();
        const double dec = f.number("deceleration", 0, 0, big);
        const bool halt = fb == "MC_Halt", exec = f.number("execute", 1, 0, 1) != 0;
        return [=](MotionController& mc) {
            if (halt) {
                mc.blocks(a).halt.Deceleration = dec;
                trigger(mc, mc.blocks(a).halt);
            } else {
                mc.blocks(a).stop.Deceleration = dec;
                // MC_Stop keeps the axis in Stopping until the scenario drops Execute.
                mc.blocks(a).stop.Execute = exec;
            }
        };
    }
    if (fb == "MC_LineMove2") {
        const double x = v("x"), y = v("y"), vel = v("velocity"), acc = v("acceleration"), dec = v("deceleration");
        const BufferMode m = buffer_of(f);
        return [=](MotionController& mc) {
            auto& b = mc.line_move();
            b.X = x, b.Y = y, b.Velocity = vel, b.Acceleration = acc, b.Deceleration = dec, b.Mode = m;
            trigger(mc, b);
        };
    }
    if (fb == "MC_CircleCenterMove") {
        const double cx = v("center_x"), cy = v("center_y"), ex = v("end_x"), ey = v("end_y");
        const bool cw = f.choice("direction", "ccw", {"cw", "ccw"}) == "cw";
        const double vel = v("velocity"), acc = v("acceleration"), dec = v("deceleration");
        const BufferMode m = buffer_of(f);
        return [=](MotionController& mc) {
            auto& b = mc.circle_move();
            b.CenterX = cx, b.CenterY = cy, b.EndX = ex, b.EndY = ey, b.Direction = cw ? motion::dir_cw : motion::dir_ccw;
            b.Velocity = vel, b.Acceleration = acc, b.Deceleration = dec, b.Mode = m;
            trigger(mc, b);
        };
    }
    f.fail(f.child("fb"), "unknown function block '" + fb + "'");
}

/// One entry of `motion.commands`: a motion token, a drive fault, or a PLCopen block.
TimedCommand read_command(YamlMap f) {
    TimedCommand c;
    c.at_s = f.require_number("at_ms", 0, big) / 1000.0;
    if (f.has("token")) {
        const std::string tok = f.require<std::string>("token"), data = f.get<std::string>("data", "");
        c.run = [tok, data](MotionController& mc, nlohmann::json& log) {
            const MotionReply r = mc.command(tok, data);
            log.push_back({{"token", tok}, {"data", data}, {"bch", r.bch}, {"reply", r.data}});
        };
    } else if (f.has("inject_fault")) {
        const unsigned axis = static_cast<unsigned>(f.require_number("inject_fault", 0, 3));
        const auto code = static_cast<std::uint16_t>(f.number("code", 0x7500, 0, 0xFFFF));
        const bool clear = f.choice("clear_after", "no", {"yes", "no"}) == "yes";
        c.run = [axis, code, clear](MotionController& mc, nlohmann::json& log) {
            mc.drive(axis).inject_fault(code);
            if (clear) mc.drive(axis).clear_fault_cause();
            log.push_back({{"inject_fault", axis}, {"code", code}});
        };
    } else {
        const std::string fb = f.require<std::string>("fb");
        const std::function<void(MotionController&)> set = read_block(f, fb);
        c.run = [fb, set](MotionController& mc, nlohmann::json& log) {
            set(mc);
            log.push_back({{"fb", fb}});
        };
    }
    f.finish();
    return c;
}

Check circle_check(YamlMap cc) {
    const double cx = cc.require_number("center_x", -big, big), cy = cc.require_number("center_y", -big, big);
    const double r = cc.require_number("radius", 0, big), lim = cc.number("max_radial_error", 1, 0, big);
    cc.finish();
    return [=](MotionController& mc, nlohmann::json& out, bool& ok) {
        double worst_cmd = 0, worst_act = 0, min_a = 1e300, max_a = -1e300;
        const auto& s = mc.recorder().samples();
        for (const auto& p : s) {
            worst_cmd = std::max(worst_cmd, std::abs(std::hypot(p.cmd[0] - cx, p.cmd[1] - cy) - r));
            worst_act = std::max(worst_act, std::abs(std::hypot(p.act[0] - cx, p.act[1] - cy) - r));
            const double ang = std::atan2(p.cmd[1] - cy, p.cmd[0] - cx);
            min_a = std::min(min_a, ang);
            max_a = std::max(max_a, ang);
        }
        const bool closes = !s.empty() && s.back().cmd[0] == s.front().cmd[0] && s.back().cmd[1] == s.front().cmd[1];
        const bool pass = worst_cmd <= lim && !s.empty();
        ok &= pass;
        out.push_back({{"check", "circle"}, {"max_radial_error_cmd", worst_cmd}, {"max_radial_error_act", worst_act},
                       {"closes", closes}, {"angle_span_rad", max_a - min_a}, {"pass", pass}});
    };
}

/// `motion.checks`, in report order: final_state, final_positions, circle.
std::vector<Check> read_checks(YamlMap c) {
    std::vector<Check> checks;
    const std::string want_state = c.get<std::string>("final_state", "");
    if (!want_state.empty())
        checks.push_back([want_state](MotionController& mc, nlohmann::json& out, bool& ok) {
            const bool pass = mc.state() == want_state;
            ok &= pass;
            out.push_back({{"check", "final_state"}, {"want", want_state}, {"got", mc.state()}, {"pass", pass}});
        });
    if (c.has("final_positions")) {
        const std::vector<std::int64_t> want = c.list<std::int64_t>("final_positions", motion::MotionController::axes);
        const double tol = c.number("position_tolerance", 0, 0, 1e9);
        checks.push_back([want, tol](MotionController& mc, nlohmann::json& out, bool& ok) {
            bool pass = true;
            nlohmann::json got = nlohmann::json::array();
            for (std::size_t a = 0; a < want.size(); ++a) {
                const std::int64_t p = mc.chip().command_position(static_cast<unsigned>(a));
                got.push_back(p);
                pass &= std::llabs(p - want[a]) <= tol;
            }
            ok &= pass;
            out.push_back({{"check", "final_positions"}, {"want", want}, {"got", got}, {"pass", pass}});
        });
    }
    const bool circle = c.has("circle");
    YamlMap cc = c.map("circle");
    if (circle) checks.push_back(circle_check(cc));
    c.finish();
    return checks;
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
    std::size_t i = 0;
    for (YamlMap& a : m.maps("axes", motion::MotionController::axes)) {
        auto opt = [&](const char* k) -> std::optional<std::int64_t> {
            if (!a.has(k)) return std::nullopt;
            return std::llround(a.number(k, 0, -big, big));
        };
        p.cfg.switches[i++] = {opt("pelm"), opt("nelm"), opt("home")};
        a.finish();
    }
    for (YamlMap& c : m.maps("commands")) p.cmds.push_back(read_command(c));
    std::stable_sort(p.cmds.begin(), p.cmds.end(), [](auto& x, auto& y) { return x.at_s < y.at_s; });
    p.checks = read_checks(m.map("checks"));
    m.finish();
    return p;
}

/// Drives the control cycle and the timed commands.
struct MotionDriver : sc_core::sc_module {
    MotionController& mc;
    std::vector<TimedCommand> cmds;
    sc_core::sc_time cycle;
    std::uint64_t cycles;
    nlohmann::json log = nlohmann::json::array();
    SC_HAS_PROCESS(MotionDriver);
    MotionDriver(sc_core::sc_module_name n, MotionController& m, sc_core::sc_time c, std::uint64_t count)
        : sc_module(n), mc(m), cycle(c), cycles(count) {
        SC_THREAD(run);
    }
    void run() {
        std::size_t next = 0;
        for (std::uint64_t k = 0; k <= cycles; ++k) {
            const sc_core::sc_time now = sc_core::sc_time_stamp();
            while (next < cmds.size() && cmds[next].at_s <= now.to_seconds() + 1e-12) cmds[next++].run(mc, log);
            mc.control_cycle(now);
            if (k < cycles) wait(cycle);
        }
        sc_core::sc_stop();
    }
};

/// The figures of the finished run into `rep`.
void report_run(MotionController& mc, const MotionPlan& p, const MotionDriver& driver, nlohmann::json results,
                bool ok, nlohmann::json& rep) {
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
    rep["checks"] = std::move(results);
    rep["pass"] = ok;
}

} // namespace

int run_motion_scenario(const YAML::Node& root, const std::string& file, const std::filesystem::path& out_dir,
                        std::uint64_t seed, nlohmann::json& report) {
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
    MotionDriver driver("motion_runner", mc, cycle, count);
    driver.cmds = std::move(plan.cmds);
    sc_core::sc_start();

    bool ok = true;
    nlohmann::json results = nlohmann::json::array();
    for (auto& c : plan.checks) c(mc, results, ok);
    report_run(mc, plan, driver, std::move(results), ok, rep);
    try {
        std::filesystem::create_directories(out_dir);
        write_trajectory_csv(mc.recorder(), out_dir / "trajectory.csv");
        write_trajectory_svg(mc.recorder(), out_dir / "trajectory.svg", 0, 1, "rcsim motion: " + file);
        rep["trajectory_csv"] = (out_dir / "trajectory.csv").string();
        rep["trajectory_svg"] = (out_dir / "trajectory.svg").string();
    } catch (const std::exception& e) {
        rep["error"] = e.what();
        return 2;
    }
    return ok ? 0 : 1;
}

} // namespace rcsim
