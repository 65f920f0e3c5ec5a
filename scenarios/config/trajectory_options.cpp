// rcsim — the `trajectory:` options. See trajectory_options.h.
#include "scenarios/config/trajectory_options.h"

#include "scenarios/config/yaml_map.h"

namespace rcsim {

TrajectoryOptions read_trajectory_options(YamlMap m) {
    TrajectoryOptions o;
    o.csv_every = static_cast<std::size_t>(m.integer("csv_every", 1, 1, 1000000000));
    o.pulse_trace = m.get<bool>("pulse_trace", false);
    m.finish();
    return o;
}

} // namespace rcsim
