// rcsim — the files drawn from a motion run's trajectory recorder (main_cpu/motion/trajectory.h):
// trajectory.csv, trajectory.svg (the X-Y path with a following-error panel), trajectory_time.svg
// (position, velocity, following error and radial error against time) and, on request,
// trajectory_pulses.csv (docs/motion.md "Trajectory pictures").
//
// Every picture is decimated (svg::ColumnDecimator, svg::PathDecimator) from the recorder's bounded
// picture samples, so its size is bounded by its pixels, not by the length of the run: well under
// 2 MB for any run; trajectory.csv is streamed to disk. Memory stays flat (issue #48 item 3).
#pragma once

#include "scenarios/config/trajectory_options.h"
#include "camc_qi/camc_qi.h"
#include "main_cpu/motion/trajectory.h"
#include "models/plumbing/output_file.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rcsim {

/// trajectory.csv, streamed as the run goes (a long run keeps none of its rows): header
/// `t_s,axis,cmd_pulses,act_pulses`, one row per axis per kept sample (every `every`-th, and the
/// last). Throws ConfigError naming the file when it cannot be created, and from close() when
/// anything written was lost.
class TrajectoryCsv {
public:
    explicit TrajectoryCsv(const std::filesystem::path& file, std::size_t every = 1);
    void add(const motion::TrajectorySample& s);
    /// Writes the last sample if it was not, and closes; later add()s are ignored.
    void close();

private:
    OutputFile file_;
    std::size_t every_;
    std::uint64_t n_ = 0;
    bool closed_ = false;
    std::optional<motion::TrajectorySample> unwritten_; // the latest sample, when not written
    void row(const motion::TrajectorySample& s);
};

/// trajectory_pulses.csv: header `t_s,axis,dir`, one row per pulse (the CAMC-QI's pulse trace).
void write_pulse_csv(const std::vector<camc::PulseEvent>& pulses, const std::filesystem::path& file);

/// The X-Y picture of axis `ax` against axis `ay`, titled `title`: commanded path solid blue,
/// actual path dashed red, equal scales on nice tick bounds (a circle must look round), a start
/// mark, a direction arrow and an end mark; below it the following error (command - actual) of
/// both axes against time, which shows what the two paths, a pixel or two apart, cannot.
std::string trajectory_svg(const motion::TrajectoryRecorder& rec, unsigned ax, unsigned ay, const std::string& title);
/// Writes trajectory_svg() to `file`; throws ConfigError naming the file on failure.
void write_trajectory_svg(const motion::TrajectoryRecorder& rec, const std::filesystem::path& file, unsigned ax,
                          unsigned ay, const std::string& title);

/// The path speed panel's window: long enough that the window covers kPathSpeedWindowPulses
/// pulses at the run's top commanded path speed (so a pulse of quantisation is lost in it), in
/// steps of 10 ms from kPathSpeedWindowMin to kPathSpeedWindowMax seconds.
constexpr double kPathSpeedWindowPulses = 1000, kPathSpeedWindowMin = 0.010, kPathSpeedWindowMax = 0.200;
double path_speed_window_s(const std::vector<motion::TrajectorySample>& v);
/// The path speed of axes 0 and 1 (command, or actual) at each sample with a whole window around
/// it: sqrt(vx^2 + vy^2), each the least-squares slope of the axis' position over the samples
/// within window_s / 2 of it, corrected for the path's curvature; (time, pulses/s).
std::vector<std::pair<double, double>> path_speed(const std::vector<motion::TrajectorySample>& v, bool actual,
                                                  double window_s);

/// Panels against time: position (command solid, actual dashed) and velocity per axis that moved,
/// the path speed of axes 0/1 (path_speed() over path_speed_window_s(), stated in the heading),
/// the following error per axis, and with `circle` the radial error of both paths over its window
/// with the check's tolerance (circle->max_radial_error, when not negative) drawn across it; each
/// of `marks` as a vertical line across every panel, labelled over the first.
std::string trajectory_time_svg(const motion::TrajectoryRecorder& rec, const std::string& title,
                                const std::optional<CircleOverlay>& circle, const std::vector<TimeMark>& marks = {});

/// Every trajectory file of one run into `dir`: trajectory.csv streamed from the recorder's samples
/// from construction on, then at finish() trajectory.svg (axes 0/1), trajectory_time.svg and, when
/// `pulses` is given, trajectory_pulses.csv. Errors as the writers above.
class TrajectoryFiles {
public:
    TrajectoryFiles(motion::TrajectoryRecorder& rec, const std::filesystem::path& dir, const TrajectoryOptions& opt);
    void finish(const std::string& title, const std::optional<CircleOverlay>& circle,
                const std::vector<camc::PulseEvent>* pulses, const std::vector<TimeMark>& marks = {});

private:
    motion::TrajectoryRecorder& rec_;
    std::filesystem::path dir_;
    std::shared_ptr<TrajectoryCsv> csv_; // shared with the recorder's sink
};

} // namespace rcsim
