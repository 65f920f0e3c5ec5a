// rcsim — `rcsim run`'s progress on a terminal: one line on stderr, rewritten in place at most
// four times a wall-clock second, "run 12.3/60.0 s  RTF 1.85  ETA 0:25" (simulated time of the
// scenario's duration, simulated seconds per wall second, wall time left); without a duration
// (duration_s 0, a motion run) only the time and the RTF.
//
// It only reads the simulated time and the wall clock, from the stop poller's millisecond poll
// (models/plumbing/stop_signal.h), and is made only when stderr is a terminal (models/plumbing/progress_line.h):
// the simulation and every file a run writes are the same with it or without.
#pragma once

#include "models/plumbing/progress_line.h"

#include <chrono>
#include <optional>

namespace rcsim {

class RunProgress {
public:
    explicit RunProgress(double total_s) : line_(true), total_s_(total_s) {}
    ~RunProgress() { finish(); }
    RunProgress(const RunProgress&) = delete;
    RunProgress& operator=(const RunProgress&) = delete;

    /// Whether `rcsim run` draws the line: stderr is a terminal and CI is unset.
    static bool wanted() { return ProgressLine::interactive_default(); }
    /// At every simulated-millisecond poll; redraws when a quarter second has passed.
    void poll();
    /// Erases the line, before the run's summary.
    void finish();

private:
    using Clock = std::chrono::steady_clock;
    ProgressLine line_;
    double total_s_;
    std::optional<Clock::time_point> start_; // the first poll: the simulation's start
    Clock::time_point shown_;
    bool showing_ = false;
};

} // namespace rcsim
