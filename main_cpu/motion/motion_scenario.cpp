// rcsim — the motion scenario runner. See motion_scenario.h and docs/motion.md.
#include "main_cpu/motion/motion_scenario.h"

#include "main_cpu/motion/motion_controller.h"
#include "models/clock.h"
#include "models/config_error.h"

#include <cmath>
#include <functional>
#include <iostream>
#include <map>
#include <set>

namespace rcsim::motion {
namespace {

/// A YAML mapping whose every read names file and line on error, and whose unread keys are errors.
class Fields {
public:
    Fields(YAML::Node n, const std::string& file, std::string what) : n_(n), file_(file), what_(std::move(what)) {
        if (n && !n.IsMap()) fail(n, what_ + " must be a mapping");
    }
    [[noreturn]] void fail(const YAML::Node& at, const std::string& msg) const {
        throw ConfigError(file_, at.Mark().is_null() ? 0 : at.Mark().line + 1, msg);
    }
    bool has(const std::string& k) const { return n_ && n_[k]; }
    YAML::Node raw(const std::string& k) {
        used_.insert(k);
        return n_[k];
    }
    double num(const std::string& k, std::optional<double> def, double lo, double hi) {
        if (!has(k)) {
            if (!def) fail(n_, what_ + ": missing key '" + k + "'");
            return *def;
        }
        YAML::Node v = raw(k);
        double d = 0;
        try {
            d = v.as<double>();
        } catch (const YAML::Exception&) {
            fail(v, what_ + ": '" + k + "' must be a number, got '" + YAML::Dump(v) + "'");
        }
        if (!(d >= lo && d <= hi))
            fail(v, what_ + ": '" + k + "' = " + YAML::Dump(v) + " is outside [" + std::to_string(lo) + ", " +
                        std::to_string(hi) + "]");
        return d;
    }
    std::string str(const std::string& k, std::optional<std::string> def) {
        if (!has(k)) {
            if (!def) fail(n_, what_ + ": missing key '" + k + "'");
            return *def;
        }
        YAML::Node v = raw(k);
        if (!v.IsScalar()) fail(v, what_ + ": '" + k + "' must be a scalar");
        return v.Scalar();
    }
    void finish() const {
        if (!n_) return;
        for (auto it = n_.begin(); it != n_.end(); ++it) {
            if (!it->first.IsScalar()) fail(it->first, what_ + ": a key must be a plain name, not '" + YAML::Dump(it->first) + "'");
            const std::string k = it->first.Scalar();
            if (!used_.count(k)) fail(it->first, what_ + ": unknown key '" + k + "'");
        }
    }
    const YAML::Node& node() const { return n_; }

private:
    YAML::Node n_;
    std::string file_, what_;
    std::set<std::string> used_;
};

struct TimedCommand {
    double at_s = 0;
    std::function<void(MotionController&, nlohmann::json&)> run;
};

constexpr double big = 1e9;

BufferMode buffer_of(Fields& f) {
    const std::string b = f.str("buffer", std::string("aborting"));
    if (b == "aborting") return BufferMode::aborting;
    if (b == "buffered") return BufferMode::buffered;
    f.fail(f.raw("buffer"), "buffer must be 'aborting' or 'buffered', got '" + b + "'");
}

/// Sets a block's inputs and raises Execute (a new edge if it was already high).
template <typename Fb> void trigger(MotionController& mc, Fb& fb) {
    fb.Execute = false; // a falling edge first, so that Execute rises again
    fb.call();
    fb.Execute = true;
    mc.auto_release(fb);
}

TimedCommand parse_command(const YAML::Node& n, const std::string& file) {
    Fields f(n, file, "motion.commands[]");
    TimedCommand c;
    c.at_s = f.num("at_ms", std::nullopt, 0, big) / 1000.0;
    if (f.has("token")) {
        const std::string tok = f.str("token", std::nullopt), data = f.str("data", std::string());
        c.run = [tok, data](MotionController& mc, nlohmann::json& log) {
            const MotionReply r = mc.command(tok, data);
            log.push_back({{"token", tok}, {"data", data}, {"bch", r.bch}, {"reply", r.data}});
        };
    } else if (f.has("inject_fault")) {
        const unsigned axis = static_cast<unsigned>(f.num("inject_fault", std::nullopt, 0, 3));
        const auto code = static_cast<std::uint16_t>(f.num("code", 0x7500, 0, 0xFFFF));
        const std::string clear_after = f.str("clear_after", std::string("no"));
        if (clear_after != "yes" && clear_after != "no")
            f.fail(f.raw("clear_after"), "clear_after must be 'yes' or 'no', got '" + clear_after + "'");
        const bool clear = clear_after == "yes";
        c.run = [axis, code, clear](MotionController& mc, nlohmann::json& log) {
            mc.drive(axis).inject_fault(code);
            if (clear) mc.drive(axis).clear_fault_cause();
            log.push_back({{"inject_fault", axis}, {"code", code}});
        };
    } else {
        const std::string fb = f.str("fb", std::nullopt);
        auto axis_of = [&]() { return static_cast<unsigned>(f.num("axis", std::nullopt, 0, 3)); };
        auto v = [&](const char* k) { return f.num(k, std::nullopt, -big, big); };
        std::function<void(MotionController&)> set;
        if (fb == "MC_Power") {
            const unsigned a = axis_of();
            const bool en = f.num("enable", 1, 0, 1) != 0;
            set = [a, en](MotionController& mc) { mc.power(a).Enable = en; };
        } else if (fb == "MC_Reset") {
            const unsigned a = axis_of();
            set = [a](MotionController& mc) { trigger(mc, mc.blocks(a).reset); };
        } else if (fb == "MC_Home") {
            const unsigned a = axis_of();
            const double pos = f.num("position", 0, -big, big), dir = f.num("direction", -1, -1, 1);
            const double vel = f.num("velocity", 10000, -big, big);
            set = [a, pos, dir, vel](MotionController& mc) {
                auto& b = mc.blocks(a).home;
                b.Position = pos, b.Direction = dir < 0 ? -1 : 1, b.Velocity = vel;
                trigger(mc, b);
            };
        } else if (fb == "MC_MoveAbsolute" || fb == "MC_MoveRelative") {
            const unsigned a = axis_of();
            const double p = v(fb == "MC_MoveAbsolute" ? "position" : "distance");
            const double vel = v("velocity"), acc = v("acceleration"), dec = v("deceleration");
            const BufferMode m = buffer_of(f);
            const bool absolute = fb == "MC_MoveAbsolute";
            set = [=](MotionController& mc) {
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
        } else if (fb == "MC_Halt" || fb == "MC_Stop") {
            const unsigned a = axis_of();
            const double dec = f.num("deceleration", 0, 0, big);
            const bool halt = fb == "MC_Halt", exec = f.num("execute", 1, 0, 1) != 0;
            set = [=](MotionController& mc) {
                if (halt) {
                    mc.blocks(a).halt.Deceleration = dec;
                    trigger(mc, mc.blocks(a).halt);
                } else {
                    mc.blocks(a).stop.Deceleration = dec;
                    // MC_Stop keeps the axis in Stopping until the scenario drops Execute.
                    if (exec) mc.blocks(a).stop.Execute = true;
                    else mc.blocks(a).stop.Execute = false;
                }
            };
        } else if (fb == "MC_LineMove2") {
            const double x = v("x"), y = v("y"), vel = v("velocity"), acc = v("acceleration"), dec = v("deceleration");
            const BufferMode m = buffer_of(f);
            set = [=](MotionController& mc) {
                auto& b = mc.line_move();
                b.X = x, b.Y = y, b.Velocity = vel, b.Acceleration = acc, b.Deceleration = dec, b.Mode = m;
                trigger(mc, b);
            };
        } else if (fb == "MC_CircleCenterMove") {
            const double cx = v("center_x"), cy = v("center_y"), ex = v("end_x"), ey = v("end_y");
            const std::string dir = f.str("direction", std::string("ccw"));
            if (dir != "cw" && dir != "ccw") f.fail(f.raw("direction"), "direction must be cw or ccw, got '" + dir + "'");
            const double vel = v("velocity"), acc = v("acceleration"), dec = v("deceleration");
            const BufferMode m = buffer_of(f);
            set = [=](MotionController& mc) {
                auto& b = mc.circle_move();
                b.CenterX = cx, b.CenterY = cy, b.EndX = ex, b.EndY = ey, b.Direction = dir == "cw" ? dir_cw : dir_ccw;
                b.Velocity = vel, b.Acceleration = acc, b.Deceleration = dec, b.Mode = m;
                trigger(mc, b);
            };
        } else {
            f.fail(f.raw("fb"), "unknown function block '" + fb + "'");
        }
        c.run = [fb, set](MotionController& mc, nlohmann::json& log) {
            set(mc);
            log.push_back({{"fb", fb}});
        };
    }
    f.finish();
    return c;
}

/// Drives the control cycle and the timed commands.
struct Runner : sc_core::sc_module {
    MotionController& mc;
    std::vector<TimedCommand> cmds;
    sc_core::sc_time cycle;
    std::uint64_t cycles;
    nlohmann::json log = nlohmann::json::array();
    SC_HAS_PROCESS(Runner);
    Runner(sc_core::sc_module_name n, MotionController& m, sc_core::sc_time c, std::uint64_t count)
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

} // namespace
} // namespace rcsim::motion

int run_motion_scenario(const YAML::Node& root, const std::string& file, const std::filesystem::path& out_dir,
                        std::uint64_t seed, nlohmann::json& report) {
    using namespace rcsim;
    using namespace rcsim::motion;
    nlohmann::json& rep = report["motion"];
    rep["seed"] = seed; // the motion layer draws no random numbers; recorded for the report
    MotionConfig cfg;
    double cycle_ms = 1, duration_s = 0;
    std::vector<TimedCommand> cmds;
    std::vector<std::function<void(MotionController&, nlohmann::json&, bool&)>> checks;
    try {
        Fields m(root["motion"], file, "motion");
        if (!root["motion"]) throw ConfigError(file, 0, "no 'motion:' section");
        cycle_ms = m.num("control_cycle_ms", 1, 0.01, 1000);
        duration_s = m.num("duration_s", std::nullopt, 0, 3600);
        cfg.drive.following_lag_s = m.num("following_lag_ms", 2, 0, 1000) / 1000.0;
        cfg.start_speed = m.num("start_speed", 100, 1, 1e6);
        if (m.has("axes")) {
            YAML::Node axes = m.raw("axes");
            if (!axes.IsSequence() || axes.size() > 4) m.fail(axes, "motion.axes must be a list of at most 4 maps");
            for (std::size_t i = 0; i < axes.size(); ++i) {
                Fields a(axes[i], file, "motion.axes[" + std::to_string(i) + "]");
                auto opt = [&](const char* k) -> std::optional<std::int64_t> {
                    if (!a.has(k)) return std::nullopt;
                    return std::llround(a.num(k, std::nullopt, -1e9, 1e9));
                };
                cfg.switches[i] = {opt("pelm"), opt("nelm"), opt("home")};
                a.finish();
            }
        }
        if (m.has("commands")) {
            YAML::Node list = m.raw("commands");
            if (!list.IsSequence()) m.fail(list, "motion.commands must be a list");
            for (const auto& c : list) cmds.push_back(parse_command(c, file));
            std::stable_sort(cmds.begin(), cmds.end(), [](auto& x, auto& y) { return x.at_s < y.at_s; });
        }
        if (m.has("checks")) {
            Fields c(m.raw("checks"), file, "motion.checks");
            if (c.has("final_state")) {
                const std::string want = c.str("final_state", std::nullopt);
                checks.push_back([want](MotionController& mc, nlohmann::json& out, bool& ok) {
                    const bool pass = mc.state() == want;
                    ok &= pass;
                    out.push_back({{"check", "final_state"}, {"want", want}, {"got", mc.state()}, {"pass", pass}});
                });
            }
            if (c.has("final_positions")) {
                YAML::Node fp = c.raw("final_positions");
                if (!fp.IsSequence() || fp.size() > 4) c.fail(fp, "final_positions must be a list of up to 4 numbers");
                std::vector<std::int64_t> want;
                for (const auto& x : fp) {
                    try { want.push_back(x.as<std::int64_t>()); } catch (const YAML::Exception&) {
                        c.fail(x, "final_positions: '" + YAML::Dump(x) + "' is not an integer");
                    }
                }
                const double tol = c.num("position_tolerance", 0, 0, 1e9);
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
            if (c.has("circle")) {
                Fields cc(c.raw("circle"), file, "motion.checks.circle");
                const double cx = cc.num("center_x", std::nullopt, -big, big), cy = cc.num("center_y", std::nullopt, -big, big);
                const double r = cc.num("radius", std::nullopt, 0, big), lim = cc.num("max_radial_error", 1, 0, big);
                cc.finish();
                checks.push_back([=](MotionController& mc, nlohmann::json& out, bool& ok) {
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
                    out.push_back({{"check", "circle"}, {"max_radial_error_cmd", worst_cmd},
                                   {"max_radial_error_act", worst_act}, {"closes", closes},
                                   {"angle_span_rad", max_a - min_a}, {"pass", pass}});
                });
            }
            c.finish();
        }
        m.finish();
    } catch (const ConfigError& e) {
        rep["error"] = e.what();
        return 2;
    } catch (const YAML::Exception& e) {
        rep["error"] = file + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg;
        return 2;
    }

    const auto cycle = rcsim::ps(static_cast<std::uint64_t>(std::llround(cycle_ms * 1e9)));
    const auto count = static_cast<std::uint64_t>(std::llround(duration_s * 1000 / cycle_ms));
    MotionController mc("motion", cfg);
    Runner runner("motion_runner", mc, cycle, count);
    runner.cmds = std::move(cmds);
    sc_core::sc_start();

    bool ok = true;
    nlohmann::json results = nlohmann::json::array();
    for (auto& c : checks) c(mc, results, ok);
    std::vector<std::int64_t> cmd(4), act(4);
    double max_follow = 0;
    for (const auto& s : mc.recorder().samples())
        for (unsigned a = 0; a < 4; ++a) max_follow = std::max(max_follow, static_cast<double>(std::llabs(s.cmd[a] - s.act[a])));
    for (unsigned a = 0; a < 4; ++a) {
        cmd[a] = mc.chip().command_position(a);
        act[a] = mc.chip().encoder_position(a);
    }
    rep["control_cycle_ms"] = cycle_ms;
    rep["duration_s"] = duration_s;
    rep["final_cmd_pulses"] = cmd;
    rep["final_act_pulses"] = act;
    rep["state"] = mc.state();
    rep["max_following_error_pulses"] = max_follow;
    rep["samples"] = mc.recorder().samples().size();
    rep["commands"] = runner.log;
    rep["checks"] = results;
    rep["pass"] = ok;
    try {
        std::filesystem::create_directories(out_dir);
        mc.recorder().write_csv(out_dir / "trajectory.csv");
        mc.recorder().write_svg(out_dir / "trajectory.svg", 0, 1, "rcsim motion: " + file);
        rep["trajectory_csv"] = (out_dir / "trajectory.csv").string();
        rep["trajectory_svg"] = (out_dir / "trajectory.svg").string();
    } catch (const std::exception& e) {
        rep["error"] = e.what();
        return 2;
    }
    return ok ? 0 : 1;
}
