// rcsim — the verdicts of a motion run. See motion_checks.h.
#include "scenarios/verdict/motion_checks.h"

#include "main_cpu/st/program.h"

#include <algorithm>
#include <cmath>

namespace rcsim {

namespace {

constexpr double kTwoPi = 6.283185307179586;

/// `a` folded into (-pi, pi]: the turn between two neighbouring samples.
double wrap(double a) {
    while (a > kTwoPi / 2) a -= kTwoPi;
    while (a <= -kTwoPi / 2) a += kTwoPi;
    return a;
}

/// Seconds to milliseconds at the kernel's picosecond resolution (no 151.00000000000003).
double ms(double s) { return std::round(s * 1e12) / 1e9; }

bool in_window(const motion::TrajectorySample& s, double t0, double t1) {
    // The samples carry the control cycle's time; 1 ps slack absorbs the seconds conversion.
    return s.t_s >= t0 - 1e-12 && s.t_s <= t1 + 1e-12 && s.cmd.size() >= 2;
}

} // namespace

Check fb_outcome_check(const std::vector<FbCommand>& cmds) {
    nlohmann::json bad = nlohmann::json::array();
    for (const FbCommand& c : cmds)
        if (!c.as_expected()) bad.push_back(c.to_json());
    Check c = Check::at_most("fb_outcomes_as_expected", Figure::of(double(bad.size())), 0);
    c.detail = {{"commands", cmds.size()}, {"unexpected", bad}};
    return c;
}

Check final_state_check(const std::string& want, const std::string& got) {
    Check c = Check::at_most("final_state", Figure::of(want == got ? 0.0 : 1.0), 0);
    c.detail = {{"want", want}, {"got", got}};
    return c;
}

Check program_check(const st::StProgram& p) {
    Check c = Check::at_most("st_program_error_free", Figure::of(p.error().empty() && p.cycles() > 0 ? 0.0 : 1.0), 0);
    c.detail = {{"program", p.current()}, {"cycles", p.cycles()},
                {"error", p.cycles() == 0 ? "the program never ran (no RN token?)" : p.error()}};
    return c;
}

Check final_positions_check(const std::vector<std::int64_t>& want, const std::vector<std::int64_t>& got,
                            double tolerance) {
    double worst = 0;
    for (std::size_t a = 0; a < want.size() && a < got.size(); ++a)
        worst = std::max(worst, std::abs(double(got[a]) - double(want[a])));
    Check c = Check::at_most("final_positions", Figure::of(worst), tolerance);
    c.detail = {{"want", want}, {"got", std::vector<std::int64_t>(got.begin(), got.begin() + long(want.size()))}};
    return c;
}

double swept_angle_rad(const std::vector<motion::TrajectorySample>& samples, double t0, double t1, double cx,
                       double cy, bool ccw) {
    double sum = 0, prev = 0;
    bool first = true;
    for (const auto& s : samples) {
        if (!in_window(s, t0, t1)) continue;
        const double x = double(s.cmd[0]) - cx, y = double(s.cmd[1]) - cy;
        if (x == 0 && y == 0) continue; // the centre has no angle
        const double a = std::atan2(y, x);
        // Neighbouring samples are one control cycle apart: far less than half a turn.
        if (!first) sum += wrap(a - prev);
        prev = a, first = false;
    }
    return ccw ? sum : -sum;
}

std::vector<Check> circle_checks(const CircleLimits& lim, const std::optional<ArcRun>& run,
                                 const std::vector<motion::TrajectorySample>& samples, const std::string& why_none) {
    const CommandedArc& arc = run ? run->arc : CommandedArc{};
    // One pulse of arc less than commanded; without a command, what a full circle would need.
    const double sweep_limit = run ? arc.sweep_rad() - 1 / arc.radius()
                                   : lim.radius > 0 ? kTwoPi - 1 / lim.radius : kTwoPi;
    if (!run)
        return {Check::at_most("circle_radial_error_pulses", Figure::none(why_none), lim.max_radial_error),
                Check::at_least("circle_swept_angle_rad", Figure::none(why_none), sweep_limit),
                Check::at_most("circle_end_error_pulses", Figure::none(why_none), lim.max_end_error)};

    double worst_cmd = 0, worst_act = 0;
    const motion::TrajectorySample* last = nullptr;
    std::size_t n = 0;
    for (const auto& s : samples) {
        if (!in_window(s, run->t0_s, run->t1_s)) continue;
        const auto radial = [&](const std::vector<std::int64_t>& p) {
            return std::abs(std::hypot(double(p[0]) - lim.center_x, double(p[1]) - lim.center_y) - lim.radius);
        };
        worst_cmd = std::max(worst_cmd, radial(s.cmd));
        if (s.act.size() >= 2) worst_act = std::max(worst_act, radial(s.act));
        last = &s, ++n;
    }
    const std::string none = "no trajectory sample between the circle command and its outcome";
    Check radial = Check::at_most("circle_radial_error_pulses", n ? Figure::of(worst_cmd) : Figure::none(none),
                                  lim.max_radial_error);
    radial.detail = {{"samples", n}, {"actual_path_max_radial_error_pulses", worst_act}};

    const double swept = swept_angle_rad(samples, run->t0_s, run->t1_s, arc.center_x, arc.center_y, arc.ccw);
    Check sweep = Check::at_least("circle_swept_angle_rad", n ? Figure::of(swept) : Figure::none(none), sweep_limit);
    sweep.detail = {{"commanded_rad", arc.sweep_rad()}, {"radius_pulses", arc.radius()},
                    {"direction", arc.ccw ? "ccw" : "cw"}};

    Figure end = Figure::none(none);
    nlohmann::json end_detail = {{"commanded", {arc.end_x, arc.end_y}}};
    if (last) {
        end = Figure::of(std::max(std::abs(double(last->cmd[0]) - arc.end_x), std::abs(double(last->cmd[1]) - arc.end_y)));
        end_detail["ended"] = {last->cmd[0], last->cmd[1]};
        end_detail["at_ms"] = ms(last->t_s);
    }
    Check closure = Check::at_most("circle_end_error_pulses", end, lim.max_end_error);
    closure.detail = end_detail;
    return {radial, sweep, closure};
}

} // namespace rcsim
