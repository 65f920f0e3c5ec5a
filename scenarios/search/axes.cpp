#include "scenarios/search/axes.h"

#include "models/clock.h"
#include "models/frame_codec.h"
#include "models/plumbing/config_error.h"
#include "scenarios/sweep/sweep.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <regex>
#include <stdexcept>

namespace rcsim::search {

namespace {

/// A per-port axis the scenario has no key for: its port and which one; port -1 when `path` is not one.
struct PortAxis {
    int port = -1;
    std::string what; // char_phase_us, frame_phase_chars, baud
};

PortAxis port_axis(const std::string& path) {
    static const std::regex re(R"(^ports\[([0-9])\]\.(char_phase_us|frame_phase_chars|baud)$)");
    std::smatch m;
    if (!std::regex_match(path, m, re)) return {};
    return {m[1].str()[0] - '0', m[2].str()};
}

bool generates_traffic(const PortScenario& p) {
    using P = HostTraffic::Pattern;
    const P k = p.protocol.traffic.pattern;
    return p.host == PortScenario::Host::protocol && k != P::none && k != P::script;
}

/// The longest frame port p's traffic sends, in characters.
double longest_frame_chars(const PortScenario& p) {
    return static_cast<double>(p.protocol.traffic.data_size + proto::overhead);
}

double char_time_us(const PortScenario& p) { return to_us(p.format().frame_time()); }

/// A key that holds a time or a rate: continuous even when its ends are written as integers.
bool continuous_key(const std::string& path) {
    for (const char* unit : {"_ms", "_us", "_s", "_hz"}) {
        const std::string u = unit;
        if (path.size() >= u.size() && path.compare(path.size() - u.size(), u.size(), u) == 0) return true;
    }
    return false;
}

std::string g10(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

} // namespace

double Axis::at(double u) const {
    u = std::min(1.0, std::max(0.0, u));
    if (!whole) return lo + u * (hi - lo);
    const double cells = hi - lo + 1;
    return std::min(hi, lo + std::floor(u * cells));
}

std::string Axis::text(double value) const {
    if (whole) return std::to_string(static_cast<long long>(std::llround(value)));
    return g10(value);
}

std::vector<Axis> default_axes(const Scenario& s) {
    std::vector<Axis> axes;
    bool any_traffic = false;
    for (std::size_t p = 0; p < s.ports.size(); ++p) {
        const PortScenario& port = s.ports[p];
        if (!generates_traffic(port)) continue;
        any_traffic = true;
        const std::string at = "ports[" + std::to_string(p) + "].";
        const HostTraffic& t = port.protocol.traffic;
        const double t_char = char_time_us(port), frame = longest_frame_chars(port);
        axes.push_back({at + "char_phase_us", 0, t_char, false,
                        "one character time at " + port.format().describe() + " (" + g10(t_char) + " us)"});
        axes.push_back({at + "frame_phase_chars", 0, frame - 1, true,
                        "one frame: the longest of its traffic, " + g10(frame) + " characters"});
        const double baud = port.format().bit.bps();
        axes.push_back({at + "baud", std::round(baud * (1 - kBaudTolerance)), std::round(baud * (1 + kBaudTolerance)), true,
                        g10(baud) + " +-2 % (RS-232 practice for 16x sampling; the 82510's own rate is exact)"});
        axes.push_back({at + "data_size", 0, static_cast<double>(t.data_size), true,
                        "frame lengths its traffic allows: 0 .. data_size " + std::to_string(t.data_size)});
        using P = HostTraffic::Pattern;
        if (t.pattern == P::fixed || t.pattern == P::poisson)
            axes.push_back({at + "rate_hz", t.rate * 0.5, t.rate * 1.5, false, "the gaps: rate_hz " + g10(t.rate) + " +-50 %"});
        if (t.pattern == P::burst) {
            const double period = to_us(t.burst_period) / 1000;
            axes.push_back({at + "burst_period_ms", period * 0.5, period * 1.5, false,
                            "the gaps: burst_period_ms " + g10(period) + " +-50 %"});
        }
    }
    if (any_traffic) {
        const double c = to_us(s.board.main.command_time);
        if (c > 0)
            axes.push_back({"main_cpu.command_time_us", c * (1 - kCommandTimeSpread), c * (1 + kCommandTimeSpread), false,
                            "the main CPU's response: command_time_us " + g10(c) + " +-50 %"});
    }
    axes.push_back({"seed", 1, kSeeds, true, "every random choice of the run"});
    return axes;
}

std::vector<Axis> written_axes(const std::vector<SearchAxisRange>& ranges, const Scenario& s, const std::string& origin) {
    std::vector<Axis> axes;
    for (const SearchAxisRange& r : ranges) {
        auto fail = [&](const std::string& why) {
            if (r.line > 0) throw ConfigError(s.file, r.line, "search axis '" + r.path + "': " + why);
            throw ConfigError("--axis '" + r.path + "': " + why);
        };
        for (const Axis& a : axes)
            if (a.path == r.path) fail("given twice");
        Axis a{r.path, r.lo, r.hi, r.whole && !continuous_key(r.path), origin};
        const PortAxis pa = port_axis(r.path);
        if (pa.port >= 0) {
            const YAML::Node ports = s.root["ports"];
            if (!ports || !ports.IsSequence() || static_cast<std::size_t>(pa.port) >= ports.size())
                fail("the scenario has no port " + std::to_string(pa.port));
            if (s.ports[pa.port].host != PortScenario::Host::protocol)
                fail("port " + std::to_string(pa.port) + "'s host is not a protocol host: it has no start_ms or " +
                     "baud of its own to vary (vary its keys by path, e.g. send[0].at_ms)");
            a.whole = pa.what != "char_phase_us";
            if (a.whole && (a.lo != std::floor(a.lo) || a.hi != std::floor(a.hi))) fail("its ends must be whole numbers");
            if (pa.what == "baud" && a.lo < 1) fail("a baud rate must be >= 1");
            if (pa.what != "baud" && a.lo < 0) fail("a phase must be >= 0");
        } else {
            try {
                sweep::set_path(YAML::Clone(s.root), r.path, YAML::Node(a.text(a.lo)));
            } catch (const std::invalid_argument& e) {
                fail(std::string("not a key of the scenario: ") + e.what());
            }
            if (r.path == "search" || r.path.rfind("search.", 0) == 0) fail("the search section is not a run's key");
        }
        axes.push_back(a);
    }
    return axes;
}

YAML::Node apply(const YAML::Node& base, const Scenario& s, const std::vector<Axis>& axes,
                 const std::vector<double>& values) {
    YAML::Node doc = YAML::Clone(base);
    doc.remove("search");
    struct Shift {
        bool any = false;
        double us = 0;
        long long baud = -1;
    };
    std::array<Shift, 3> shift{};
    for (std::size_t i = 0; i < axes.size(); ++i) {
        const Axis& a = axes[i];
        const PortAxis pa = port_axis(a.path);
        if (pa.port < 0) {
            try {
                sweep::set_path(doc, a.path, YAML::Node(a.text(values[i])));
            } catch (const std::invalid_argument& e) {
                throw std::invalid_argument("axis '" + a.path + "': " + e.what());
            }
            continue;
        }
        Shift& sh = shift[pa.port];
        const PortScenario& port = s.ports[pa.port];
        if (pa.what == "baud") {
            sh.baud = std::llround(values[i]);
            continue;
        }
        sh.any = true;
        sh.us += pa.what == "char_phase_us" ? values[i] : std::llround(values[i]) * char_time_us(port);
    }
    for (std::size_t p = 0; p < shift.size(); ++p) {
        YAML::Node port = doc["ports"].IsDefined() && doc["ports"].IsSequence() && p < doc["ports"].size()
                              ? doc["ports"][p] : YAML::Node();
        if (shift[p].any) {
            const double start_ms = to_us(s.ports[p].protocol.traffic.start) / 1000 + shift[p].us / 1000;
            port["start_ms"] = g10(start_ms);
        }
        if (shift[p].baud >= 0) {
            const std::string format = s.ports[p].format().describe();
            port["format"] = std::to_string(shift[p].baud) + format.substr(format.find(','));
        }
    }
    return doc;
}

} // namespace rcsim::search
