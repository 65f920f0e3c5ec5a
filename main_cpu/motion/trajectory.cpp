// rcsim — the trajectory recorder. See trajectory.h.
#include "main_cpu/motion/trajectory.h"

namespace rcsim::motion {

void TrajectoryRecorder::add(double t, std::vector<std::int64_t> cmd, std::vector<std::int64_t> act) {
    samples_.push_back({t, std::move(cmd), std::move(act)});
}

} // namespace rcsim::motion
