// rcsim — the `motion:` section of a scenario file (schema in docs/motion.md), read into a plan:
// the motion layer's configuration, the timed commands (motion tokens, drive faults, PLCopen
// blocks with the outcome each is expected to have), the checks and the trajectory options.
// The reader is strict: every error names the file and line (ConfigError). A PLCopen command is
// read into a closure that sets its block's inputs and raises Execute when the command runs, and
// a watch that reports its outcome.
#pragma once

#include "scenarios/config/trajectory_options.h"
#include "main_cpu/motion/motion_controller.h"

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rcsim {

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

/// An MC_CircleCenterMove in absolute pulses of axes 0 (x) and 1 (y): start, centre, end.
struct CommandedArc {
    double start_x = 0, start_y = 0, center_x = 0, center_y = 0, end_x = 0, end_y = 0;
    bool ccw = true;

    double radius() const; // |start - centre|
    /// The angle from start to end in the commanded direction, in (0, 2 pi]; 2 pi when the end
    /// is the start (the CAMC-QI's full circle).
    double sweep_rad() const;
};

/// `motion.checks.circle`: the circle the path must lie on, and how close it must end.
struct CircleLimits {
    double center_x = 0, center_y = 0, radius = 0;
    double max_radial_error = 1; // pulses
    double max_end_error = 0;    // pulses, per axis
};

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
    std::function<void(motion::MotionController&, nlohmann::json&)> run; // tokens and faults: log entry
    std::function<Issued(motion::MotionController&)> issue;              // function blocks
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

/// The whole `motion:` section of `root`; throws ConfigError naming `file` and the line.
MotionPlan read_motion_plan(const YAML::Node& root, const std::string& file);

} // namespace rcsim
