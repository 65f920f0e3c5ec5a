// rcsim — the `monitor:` section of a scenario file (docs/monitor.md): where the remote monitor
// listens and the motion commands it issues by itself at simulated times.
#pragma once

#include <systemc>
#include <yaml-cpp/yaml.h>

#include <optional>
#include <string>
#include <vector>

namespace rcsim::monitor {

/// A motion command the monitor issues by itself at a simulated time (the scenario's
/// `monitor.commands`), as a client's "motion" request would.
struct ScriptedCommand {
    sc_core::sc_time at;
    std::string token, data;
};

struct MonitorOptions {
    std::string host = "127.0.0.1";
    unsigned port = 0;
    std::vector<ScriptedCommand> commands;
};

/// "[HOST:]PORT" (HOST numeric, default 127.0.0.1; PORT 0..65535, 0 = ephemeral) into `o`.
/// Throws ConfigError naming the text.
void parse_listen(const std::string& text, MonitorOptions& o);

/// The `monitor:` section of a scenario document (docs/monitor.md), read strictly: errors name
/// `file` and the line. None when the document has no such section.
std::optional<MonitorOptions> read_monitor_section(const YAML::Node& root, const std::string& file);

} // namespace rcsim::monitor
