// rcsim — the verdicts of a motion run (docs/motion.md "Checks"): what became of every
// function-block command, where the axes ended, and the circle the X-Y plotter was told to draw.
// Every verdict is a Check (scenarios/checks.h), the one schema of report.json "checks"; what
// one figure cannot say (wanted and seen states, the commands with an unexpected outcome) is in
// the check's "detail".
#pragma once

#include "main_cpu/motion/trajectory.h"
#include "scenarios/checks.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace rcsim {

namespace st {
class StProgram;
}

/// What a function-block command ended with: the block's Done, Error (with ErrorID) or
/// CommandAborted output (PLCopen Part 1 Table 2); `busy` when none came by the end of the run,
/// `superseded` when a later command on the same block instance took it over first (the block
/// then reports on the new command only).
enum class FbOutcome : std::uint8_t { done, error, aborted, busy, superseded };
const char* to_string(FbOutcome o);

/// One function-block entry of `motion.commands` and what became of it.
struct FbCommand {
    std::size_t index = 0; // position in motion.commands
    std::string fb;
    double at_s = 0;
    FbOutcome expect = FbOutcome::done;           // done, error or aborted
    std::optional<std::uint16_t> expect_error_id; // expect error only; unset: any ErrorID
    FbOutcome outcome = FbOutcome::busy;
    std::uint16_t error_id = 0; // outcome error only
    double outcome_s = -1;      // when the outcome appeared; < 0: none (busy)

    bool as_expected() const;
    /// The command as report.json "motion.commands" lists it: at_ms, fb, expect, outcome, ...
    nlohmann::json to_json() const;
};

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

/// An MC_CircleCenterMove in absolute pulses of axes 0 (x) and 1 (y): start, centre, end.
struct CommandedArc {
    double start_x = 0, start_y = 0, center_x = 0, center_y = 0, end_x = 0, end_y = 0;
    bool ccw = true;

    double radius() const; // |start - centre|
    /// The angle from start to end in the commanded direction, in (0, 2 pi]; 2 pi when the end
    /// is the start (the CAMC-QI's full circle).
    double sweep_rad() const;
};

/// The arc as the run drew it: commanded at t0_s, its outcome (or the end of the run) at t1_s.
struct ArcRun {
    CommandedArc arc;
    double t0_s = 0, t1_s = 0;
};

/// `motion.checks.circle`: the circle the path must lie on, and how close it must end.
struct CircleLimits {
    double center_x = 0, center_y = 0, radius = 0;
    double max_radial_error = 1; // pulses
    double max_end_error = 0;    // pulses, per axis
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
