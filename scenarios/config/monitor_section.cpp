// rcsim — the `monitor:` section. See monitor_section.h.
#include "scenarios/config/monitor_section.h"

#include "models/clock.h"
#include "models/plumbing/config_error.h"
#include "scenarios/config/yaml_map.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>

namespace rcsim::monitor {

namespace {
sc_core::sc_time ms_time(double ms) { return ps(static_cast<std::uint64_t>(std::llround(ms * 1e9))); }
} // namespace

void parse_listen(const std::string& text, MonitorOptions& o) {
    const auto colon = text.rfind(':');
    std::string host = colon == std::string::npos ? std::string("127.0.0.1") : text.substr(0, colon);
    const std::string port = colon == std::string::npos ? text : text.substr(colon + 1);
    if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
    if (host.empty()) host = "127.0.0.1";
    const bool digits = !port.empty() && port.size() <= 5 && std::all_of(port.begin(), port.end(), ::isdigit);
    if (!digits || std::stoul(port) > 65535)
        throw ConfigError("--monitor '" + text + "': the port must be a number 0..65535 ([HOST:]PORT)");
    o.host = host;
    o.port = static_cast<unsigned>(std::stoul(port));
}

std::optional<MonitorOptions> read_monitor_section(const YAML::Node& root, const std::string& file) {
    if (!root.IsMap() || !root["monitor"]) return std::nullopt;
    MonitorOptions o;
    YamlMap m(root["monitor"], file, "monitor.");
    if (m.has("listen")) {
        const std::string listen = m.require<std::string>("listen");
        try {
            parse_listen(listen, o);
        } catch (const ConfigError&) {
            m.fail(m.child("listen"), "'monitor.listen' = '" + listen + "' is not [HOST:]PORT (port 0..65535)");
        }
    }
    for (YamlMap c : m.maps("commands", 1000)) {
        ScriptedCommand sc;
        sc.at = ms_time(c.number("at_ms", 0, 0, 3.6e6));
        sc.token = c.require<std::string>("token");
        if (sc.token.size() != 2) c.fail(c.child("token"), "'" + c.context() + "token' must be two characters");
        sc.data = c.get<std::string>("data", "");
        c.finish();
        o.commands.push_back(sc);
    }
    std::stable_sort(o.commands.begin(), o.commands.end(),
                     [](const ScriptedCommand& a, const ScriptedCommand& b) { return a.at < b.at; });
    m.finish();
    return o;
}

} // namespace rcsim::monitor
