// rcsim — trajectory recording and pictures: trajectory.csv (t_s,axis,cmd_pulses,act_pulses,
// one row per axis per sample) and trajectory.svg (X-Y plot of commanded and actual paths).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace rcsim::motion {

struct TrajectorySample {
    double t_s = 0;
    std::vector<std::int64_t> cmd, act;
};

class TrajectoryRecorder {
public:
    void add(double t_s, std::vector<std::int64_t> cmd, std::vector<std::int64_t> act);
    const std::vector<TrajectorySample>& samples() const { return samples_; }
    bool moved() const;

    /// Throws std::runtime_error naming the file when it cannot be written.
    void write_csv(const std::filesystem::path& file) const;
    /// X-Y plot of axis `ax` against axis `ay`.
    void write_svg(const std::filesystem::path& file, unsigned ax = 0, unsigned ay = 1,
                   const std::string& title = "X-Y trajectory") const;

private:
    std::vector<TrajectorySample> samples_;
};

} // namespace rcsim::motion
