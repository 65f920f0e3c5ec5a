// rcsim — what the trajectory files of a motion run hold (`trajectory:` in a motion section or
// under main_cpu, docs/motion.md "Trajectory pictures"), and the circle a radial-error plot
// measures against.
#pragma once

#include <cstddef>
#include <string>

namespace rcsim {

class YamlMap;

/// What the trajectory files hold (`trajectory:` in a motion section or under main_cpu).
struct TrajectoryOptions {
    std::size_t csv_every = 1; // trajectory.csv: every n-th control-cycle sample (and the last)
    bool pulse_trace = false;  // trajectory_pulses.csv: every pulse with its exact time
};
/// Reads {csv_every: 1..1e9, pulse_trace: bool}; finish()es the map.
TrajectoryOptions read_trajectory_options(YamlMap m);

/// The circle a radial-error plot measures against, and the window it applies to.
struct CircleOverlay {
    double center_x = 0, center_y = 0, radius = 0;
    double t0_s = 0, t1_s = 0;
    double max_radial_error = -1; // the circle check's limit, pulses, drawn on the plot (< 0: none)
};

/// An instant the time pictures mark across every panel and label once (a missed CSP SYNC).
struct TimeMark {
    double t_s = 0;
    std::string label;
};

} // namespace rcsim
