// rcsim — the verdicts of a motion run (docs/motion.md "Checks"): what became of every
// function-block command, where the axes ended, and the circle the X-Y plotter was told to draw.
// Every verdict is a Check (scenarios/verdict/checks.h), the one schema of report.json "checks"; what
// one figure cannot say (wanted and seen states, the commands with an unexpected outcome) is in
// the check's "detail".
#pragma once

#include "main_cpu/motion/trajectory.h"
#include "scenarios/config/motion_plan.h"
#include "scenarios/verdict/checks.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace rcsim {

namespace st {
class StProgram;
}

/// `fb_outcomes_as_expected`: the number of commands whose outcome the scenario did not expect,
/// limit 0; detail: those commands.
Check fb_outcome_check(const std::vector<FbCommand>& cmds);

/// `final_state`: mismatches (0 or 1) between the wanted and the final overall axis state.
Check final_state_check(const std::string& want, const std::string& got);

/// st_program_error_free: the loaded Structured Text program ran (an RN reached it) and no
/// runtime error stopped it (docs/st.md).
Check program_check(const st::StProgram& p);
/// `final_positions`: the largest |command position - wanted| over the listed axes, limit
/// `tolerance` pulses.
Check final_positions_check(const std::vector<std::int64_t>& want, const std::vector<std::int64_t>& got,
                            double tolerance);

/// The arc as the run drew it: commanded at t0_s, its outcome (or the end of the run) at t1_s.
struct ArcRun {
    CommandedArc arc;
    double t0_s = 0, t1_s = 0;
};

/// The angle axes 0/1's commanded path turns through around (cx, cy) over the samples with
/// t0_s <= t <= t1_s, positive in the commanded direction (counter-clockwise when `ccw`).
double swept_angle_rad(const std::vector<motion::TrajectorySample>& samples, double t0_s, double t1_s, double cx,
                       double cy, bool ccw);

/// The circle checks over the arc's window, in report order:
/// - `circle_radial_error_pulses`: the largest distance of the commanded path from the circle
///   (limit max_radial_error);
/// - `circle_swept_angle_rad`: the angle swept around the commanded centre, at least the
///   commanded arc less one pulse of arc (1 / radius): 2 pi - 1/R for a full circle;
/// - `circle_end_error_pulses`: where the path ended, per axis, from the commanded end point
///   (limit max_end_error).
/// Without an arc (no MC_CircleCenterMove) all three are "not measured" with `why_none`.
std::vector<Check> circle_checks(const CircleLimits& lim, const std::optional<ArcRun>& run,
                                 const std::vector<motion::TrajectorySample>& samples, const std::string& why_none);

} // namespace rcsim
