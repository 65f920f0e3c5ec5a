// rcsim — runs the `motion:` section of a scenario file (schema in docs/motion.md), read into a plan
// (config/motion_plan.h): builds the motion layer in SystemC, drives the control cycle, executes the
// timed commands, writes trajectory.csv / trajectory.svg into out_dir (report/trajectory_report.h)
// and fills report["motion"].
//
// Returns 0 on success, 1 when a check fails, 2 for bad input (the error, naming file and line,
// is in report["motion"]["error"]; the caller prints it, once). Elaborates modules and calls
// sc_start: call it once per process, before any other simulation has started.
#pragma once

#include "scenarios/config/motion_plan.h"
#include "main_cpu/motion/motion_controller.h"

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

namespace rcsim {

/// Called after every control cycle with the motion layer's state then (a live view's feed).
using MotionObserver = std::function<void(const motion::MotionSnapshot&)>;

/// Runs `plan`; `name` titles the pictures (the scenario's name).
int run_motion_plan(MotionPlan plan, const std::string& name, const std::filesystem::path& out_dir,
                    std::uint64_t seed, nlohmann::json& report, const MotionObserver& on_cycle = {});

/// Reads the `motion:` section of `root` (errors as above, naming `scenario_file`) and runs it.
int run_motion_scenario(const YAML::Node& root, const std::string& scenario_file,
                        const std::filesystem::path& out_dir, std::uint64_t seed, nlohmann::json& report,
                        const MotionObserver& on_cycle = {});

} // namespace rcsim
