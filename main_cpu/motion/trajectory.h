// rcsim — the trajectory recorder: commanded and actual positions of every axis at each control
// cycle. The files drawn from it (trajectory.csv, trajectory.svg) are written by the top floor
// (scenarios/report/trajectory_report.h).
#pragma once

#include <cstdint>
#include <vector>

namespace rcsim::motion {

struct TrajectorySample {
    double t_s = 0;
    std::vector<std::int64_t> cmd, act; // CAMC-QI CNT1 (command) and CNT2 (drive 0x6064), pulses
};

class TrajectoryRecorder {
public:
    void add(double t_s, std::vector<std::int64_t> cmd, std::vector<std::int64_t> act);
    const std::vector<TrajectorySample>& samples() const { return samples_; }

private:
    std::vector<TrajectorySample> samples_;
};

} // namespace rcsim::motion
