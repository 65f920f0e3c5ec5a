// rcsim — the `motion:` section read into a plan. See motion_plan.h.
#include "scenarios/config/motion_plan.h"

#include "models/plumbing/config_error.h"
#include "scenarios/config/yaml_map.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

namespace rcsim {

namespace {

/// Seconds to milliseconds at the kernel's picosecond resolution (no 151.00000000000003).
double ms(double s) { return std::round(s * 1e12) / 1e9; }

constexpr double kTwoPi = 6.283185307179586;

} // namespace

const char* to_string(FbOutcome o) {
    switch (o) {
    case FbOutcome::done: return "done";
    case FbOutcome::error: return "error";
    case FbOutcome::aborted: return "aborted";
    case FbOutcome::busy: return "busy";
    case FbOutcome::superseded: return "superseded";
    }
    return "?";
}

bool FbCommand::as_expected() const {
    if (outcome != expect) return false;
    return outcome != FbOutcome::error || !expect_error_id || *expect_error_id == error_id;
}

nlohmann::json FbCommand::to_json() const {
    nlohmann::json j = {{"command", index}, {"at_ms", ms(at_s)}, {"fb", fb}, {"expect", rcsim::to_string(expect)}};
    if (expect_error_id) j["expect_error_id"] = *expect_error_id;
    j["outcome"] = rcsim::to_string(outcome);
    if (outcome == FbOutcome::error) j["error_id"] = error_id;
    j["outcome_ms"] = outcome_s < 0 ? nlohmann::json(nullptr) : nlohmann::json(ms(outcome_s));
    return j;
}

double CommandedArc::radius() const { return std::hypot(start_x - center_x, start_y - center_y); }

double CommandedArc::sweep_rad() const {
    if (std::llround(end_x) == std::llround(start_x) && std::llround(end_y) == std::llround(start_y)) return kTwoPi;
    const double a0 = std::atan2(start_y - center_y, start_x - center_x);
    const double a1 = std::atan2(end_y - center_y, end_x - center_x);
    double d = ccw ? a1 - a0 : a0 - a1;
    while (d <= 0) d += kTwoPi;
    while (d > kTwoPi) d -= kTwoPi;
    return d;
}

namespace {

using motion::BufferMode;
using motion::MotionController;

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
    if (fb == "MC_MoveVelocity") {
        // Never Done (Part 1 §3.9): the command's outcome is InVelocity ("done"), Error or
        // CommandAborted. The sign of velocity gives the direction, as for the MV token.
        const unsigned a = axis_of();
        const double vel = v("velocity"), acc = v("acceleration"), dec = v("deceleration");
        const BufferMode m = buffer_of(f);
        return [=](MotionController& mc) {
            auto& b = mc.blocks(a).move_vel;
            b.Velocity = vel, b.Acceleration = acc, b.Deceleration = dec, b.Mode = m;
            b.Direction = motion::McDirection::positive;
            Issued is = trigger(mc, b);
            is.watch.poll = [&b]() -> std::optional<std::pair<FbOutcome, std::uint16_t>> {
                if (b.InVelocity) return std::make_pair(FbOutcome::done, std::uint16_t{0});
                if (b.Error) return std::make_pair(FbOutcome::error, b.ErrorID);
                if (b.CommandAborted) return std::make_pair(FbOutcome::aborted, std::uint16_t{0});
                return std::nullopt;
            };
            return is;
        };
    }
    if (fb == "MC_SetPosition") {
        const unsigned a = axis_of();
        const std::int32_t pos = pulses("position");
        const bool rel = f.get<bool>("relative", false);
        return [=](MotionController& mc) {
            auto& b = mc.blocks(a).set_pos;
            b.Position = pos, b.Relative = rel;
            return trigger(mc, b);
        };
    }
    if (fb == "MC_ReadStatus" || fb == "MC_ReadActualPosition" || fb == "MC_ReadAxisError" ||
        fb == "MC_ReadParameter") {
        // Enable-type reads: one call with Enable when the command runs; "done" when Valid,
        // "error" with the ErrorID (e.g. 0x7006 for a parameter number the axis does not have).
        const unsigned a = axis_of();
        const std::int32_t number = fb == "MC_ReadParameter" ? static_cast<std::int32_t>(f.require_number("parameter", 0, 1000)) : 0;
        return [=](MotionController& mc) {
            std::shared_ptr<motion::McEnableFb> b;
            if (fb == "MC_ReadStatus") b = std::make_shared<motion::MC_ReadStatus>();
            else if (fb == "MC_ReadActualPosition") b = std::make_shared<motion::MC_ReadActualPosition>();
            else if (fb == "MC_ReadAxisError") b = std::make_shared<motion::MC_ReadAxisError>();
            else {
                auto p = std::make_shared<motion::MC_ReadParameter>();
                p->ParameterNumber = number;
                b = p;
            }
            b->Axis = &mc.axis(a);
            b->Enable = true;
            b->call();
            return Issued{{nullptr, [b]() -> std::optional<std::pair<FbOutcome, std::uint16_t>> {
                               if (b->Error) return std::make_pair(FbOutcome::error, b->ErrorID);
                               return std::make_pair(FbOutcome::done, std::uint16_t{0});
                           }},
                          std::nullopt};
        };
    }
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

} // namespace

MotionPlan read_motion_plan(const YAML::Node& root, const std::string& file) {
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


} // namespace rcsim
