// rcsim — the trajectory recorder: commanded and actual positions of every axis at each control
// cycle, in memory bounded whatever the length of the run (issue #48 item 3: a run kept every
// sample, about 0.14 MB per simulated second). It keeps
// - the pictures' samples: every sample until kPlotCap are kept; beyond, per time bucket (a
//   power of two of control cycles, doubled whenever the cap is reached) the first, the last and
//   those where each plotted figure (position, following error, velocity, path speed) is lowest and
//   highest, so every peak the pictures show survives;
// - the latest kRecent samples (the live monitor's path, Modbus's registers);
// - every sample of an open window (the circle the checks judge, from its command to its outcome);
// - the largest following error;
// and hands every sample to its sinks as it comes (trajectory.csv is streamed to disk by one).
// The files drawn from it are written by the top floor (scenarios/report/trajectory_report.h).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <vector>

namespace rcsim::motion {

struct TrajectorySample {
    double t_s = 0;
    std::vector<std::int64_t> cmd, act; // CAMC-QI CNT1 (command) and CNT2 (drive 0x6064), pulses
    // Velocity since the previous control cycle's sample in pulses/s, per axis (the first four):
    // kept with the sample, since the pictures' neighbour of a sample is not always its cycle's.
    bool has_velocity = false;
    std::array<double, 4> vel_cmd{}, vel_act{};
};

class TrajectoryRecorder {
public:
    static constexpr std::size_t kPlotCap = std::size_t{1} << 13;  // pictures' samples, at most
    static constexpr std::size_t kRecent = std::size_t{1} << 12;   // latest samples kept

    using Sink = std::function<void(const TrajectorySample&)>;

    explicit TrajectoryRecorder(std::size_t plot_cap = kPlotCap, std::size_t recent = kRecent);

    void add(double t_s, std::vector<std::int64_t> cmd, std::vector<std::int64_t> act);
    /// Called with every sample from now on, in order (a file streamed as the run goes).
    void on_sample(Sink sink) { sinks_.push_back(std::move(sink)); }

    /// Samples recorded so far.
    std::uint64_t count() const { return count_; }
    /// The pictures' samples in time order: every sample until the cap was first reached (then
    /// reduced() is true), the bucket picks described above after.
    std::vector<TrajectorySample> plot_samples() const;
    bool reduced() const { return width_ > 1; }
    /// The latest samples, oldest first; recent()[i] is sample number recent_first() + i.
    const std::deque<TrajectorySample>& recent() const { return recent_; }
    std::uint64_t recent_first() const { return count_ - recent_.size(); }
    /// The latest sample but `back`, or nullptr.
    const TrajectorySample* last(std::size_t back = 0) const;

    /// Keeps every sample from now until end_window() (a new window drops the last one's).
    void start_window();
    void end_window() { window_open_ = false; }
    const std::vector<TrajectorySample>& window() const { return window_; }

    /// The largest |command - actual| of any axis in any sample, pulses.
    double max_following_error() const { return max_follow_; }

private:
    struct Kept {
        std::uint64_t index = 0; // the sample's number
        TrajectorySample s;
    };
    /// One bucket's picks, gathered as its samples come: the first, the last, and the lowest and
    /// highest sample of every plotted figure.
    struct Bucket {
        static constexpr std::size_t kFigures = 22; // 4 axes x (cmd, act, error, cmd and act velocity), 2 path speeds
        std::uint64_t id = 0;
        bool any = false;
        Kept first, last;
        std::array<Kept, kFigures> lo, hi;
        std::array<double, kFigures> lo_v{}, hi_v{};
        void add(const Kept& k);
        std::vector<Kept> picks() const; // in time order, each sample once
    };
    std::size_t cap_, recent_cap_;
    std::uint64_t count_ = 0;
    std::uint64_t width_ = 1;  // control cycles per bucket
    std::vector<Kept> kept_;   // closed buckets' picks, in time order
    Bucket open_;              // the bucket being filled (once width_ > 1)
    std::deque<TrajectorySample> recent_;
    bool window_open_ = false;
    std::vector<TrajectorySample> window_;
    double max_follow_ = 0;
    std::vector<Sink> sinks_;

    void close_bucket();
    void coarsen();
};

} // namespace rcsim::motion
