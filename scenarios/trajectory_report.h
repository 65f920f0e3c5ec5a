// rcsim — the files drawn from a motion run's trajectory recorder (main_cpu/motion/trajectory.h):
// trajectory.csv and trajectory.svg (docs/motion.md "Trajectory pictures").
#pragma once

#include "main_cpu/motion/trajectory.h"

#include <filesystem>
#include <string>

namespace rcsim {

/// trajectory.csv: header `t_s,axis,cmd_pulses,act_pulses`, one row per axis per sample.
/// Throws std::runtime_error naming the file when it cannot be written.
void write_trajectory_csv(const motion::TrajectoryRecorder& rec, const std::filesystem::path& file);

/// The X-Y picture of axis `ax` against axis `ay`: commanded path solid blue, actual path dashed
/// red, equal scales on both axes (a circle must look round), ticks in pulses, a legend.
std::string trajectory_svg(const motion::TrajectoryRecorder& rec, unsigned ax, unsigned ay, const std::string& title);
/// Writes trajectory_svg() to `file`; throws std::runtime_error naming the file on failure.
void write_trajectory_svg(const motion::TrajectoryRecorder& rec, const std::filesystem::path& file, unsigned ax,
                          unsigned ay, const std::string& title);

} // namespace rcsim
