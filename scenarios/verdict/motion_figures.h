// rcsim — the motion layer in the main board's slot of a communication run (main_cpu.motion,
// docs/scenarios.md "Motion over the serial protocol"): its configuration from the scenario (the
// main-CPU cost model), report.json "motion" and the checks on it, and what the scripted hosts
// did (ports[].script and port<n>_script_completed).
#pragma once

#include "main_cpu/motion/motion_controller.h"
#include "scenarios/host/protocol_host.h"
#include "scenarios/config/trajectory_options.h"

#include <optional>

#include <nlohmann/json.hpp>

#include <vector>

namespace rcsim {

class World;
struct Scenario;
struct Check;

/// report.json ports[p].script: steps, completed, the failure if any, when it finished.
nlohmann::json script_json(const ScriptResult& r);

/// report.json "motion" of a run with main_cpu.motion: the snapshot (state, positions), the
/// control cycle's duration and start jitter, the command latency (host ETX to first pulse),
/// the cost model's totals.
nlohmann::json motion_system_json(const World& w);

/// port<n>_script_completed for every scripted port, st_program_error_free with main_cpu.program,
/// and with main_cpu.motion the motion checks the scenario asks for (circle, final_state,
/// max_cycle_jitter_us), in report order.
std::vector<Check> system_motion_checks(const World& w, const Scenario& s);

/// The radial-error plot's circle: the scenario's `checks.circle` over the window of the last
/// accepted MC (none without both).
std::optional<CircleOverlay> circle_overlay(const World& w, const Scenario& s);
/// The instants the time pictures mark: the first missed CSP SYNC, labelled with the count.
std::vector<TimeMark> trajectory_marks(const World& w);

/// Command latency in microseconds: the scripted moves of one host (its commands answered BCH 00
/// with a move token) paired in order with the moves the motion layer accepted.
std::vector<double> command_latencies_us(const ScriptResult& host, const std::vector<motion::MoveRecord>& moves);

} // namespace rcsim
