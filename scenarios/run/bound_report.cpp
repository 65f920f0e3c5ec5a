// rcsim — the static bound in a run's reports. See bound_report.h.
#include "scenarios/run/bound_report.h"

#include "models/plumbing/config_error.h"
#include "scenarios/world/world.h"

#include <fstream>
#include <iomanip>
#include <ostream>
#include <sstream>

namespace rcsim {

namespace {

/// The board's sources by 8259A level (docs/system.md §3.3), as report.json names them.
const char* const kSources[] = {"rs232_0", "rs232_1", "rs232_2", "dpram"};

/// interrupts.SOURCE.FIGURE.max, or null when the source has no such figure (not serviced).
nlohmann::json observed_max(const nlohmann::json& interrupts, const std::string& source, const char* figure) {
    if (!interrupts.contains(source) || !interrupts[source].contains(figure)) return nullptr;
    const nlohmann::json& f = interrupts[source][figure];
    return f.is_object() && f.contains("max") ? f["max"] : nlohmann::json(nullptr);
}

/// The witness's best value when its figure is `source`'s (interrupts.SOURCE....), else null.
nlohmann::json searched(const nlohmann::json& witness, const std::string& source) {
    if (witness.is_null()) return nullptr;
    const std::string prefix = "interrupts." + source + ".";
    const std::string figure = witness.value("figure", std::string());
    if (figure.compare(0, prefix.size(), prefix) != 0 || !witness["best"].is_object()) return nullptr;
    return witness["best"].value("value", nlohmann::json(nullptr));
}

/// SEG:OFF as the vector table holds it, four upper-case hex digits each.
std::string hex4(unsigned v) {
    std::ostringstream os;
    os << std::uppercase << std::hex << std::setw(4) << std::setfill('0') << v;
    return os.str();
}

std::string us(double v) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(1) << v << " us";
    return os.str();
}

/// The path's first instructions, "WHERE INSTRUCTION; ..." (at most `n`).
std::string path_head(const std::vector<bound::Step>& path, std::size_t n) {
    std::string s;
    for (std::size_t i = 0; i < path.size() && i < n; ++i)
        s += (i ? "; " : "") + path[i].where + " " + path[i].instruction;
    if (path.size() > n) s += "; ...";
    return s;
}

} // namespace

nlohmann::json read_witness(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw ConfigError("--witness '" + path + "': cannot read it (SEARCH_DIR/search.json of rcsim search)");
    nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("figure") || !j.contains("best"))
        throw ConfigError("--witness '" + path + "': not a search.json (no \"figure\" and \"best\"; docs/search.md)");
    return j;
}

nlohmann::json bound_report(const bound::Result& result, const World& world, const nlohmann::json& interrupts,
                            const nlohmann::json& witness) {
    const nlohmann::json analysed = bound::to_json(result);
    nlohmann::json sources = nlohmann::json::object();
    for (unsigned level = 0; level < 4; ++level) {
        const std::string name = kSources[level];
        const auto it = result.sources.find(name);
        if (it == result.sources.end()) continue;
        const bound::SourceBound& b = it->second;
        const InterruptRecord* blocking = world.probe.longest_blocking(level);
        const nlohmann::json& a = analysed["sources"][name];
        sources[name] = {{"observed_service_us", observed_max(interrupts, name, "service_us")},
                         {"observed_blocking_us", blocking ? nlohmann::json(blocking->blocking_us()) : nlohmann::json(nullptr)},
                         {"observed_latency_us", observed_max(interrupts, name, "latency_us")},
                         {"bound_service_us", b.service_us},
                         {"bound_blocking_us", b.blocking_us},
                         {"bound_latency_us", b.latency_us},
                         {"searched_us", searched(witness, name)},
                         {"handler", b.entry},
                         {"vector", b.source.vector},
                         {"handler_address", hex4(b.source.cs) + ":" + hex4(b.source.ip)},
                         {"path", a.value("path", nlohmann::json::array())},
                         {"loops", a.value("loops", nlohmann::json::array())}};
    }
    return {{"budget_us", result.budget_us}, {"fits", result.fits()}, {"sources", sources}};
}

std::vector<BoundFigure> bound_figures(const bound::Result& result) {
    std::vector<BoundFigure> figures;
    for (const char* name : kSources) {
        const auto it = result.sources.find(name);
        if (it == result.sources.end()) continue;
        const bound::SourceBound& b = it->second;
        figures.push_back({name, b.blocking_us, b.entry, path_head(b.blocking_path.empty() ? b.path : b.blocking_path, 4)});
    }
    return figures;
}

void write_bound_text(const bound::Result& result, std::ostream& os) {
    os << "bound: budget " << us(result.budget_us) << " (the rule: blocking time <= budget)\n";
    for (const char* name : kSources) {
        const auto it = result.sources.find(name);
        if (it == result.sources.end()) continue;
        const bound::SourceBound& b = it->second;
        const bool over = b.blocking_us > result.budget_us;
        os << "  " << std::left << std::setw(8) << name << std::right << " " << b.entry << ": service " << us(b.service_us)
           << ", blocking " << us(b.blocking_us) << ", latency " << us(b.latency_us) << (over ? "  OVER BUDGET" : "  fits")
           << "\n";
        if (over)
            os << "           path: " << path_head(b.blocking_path.empty() ? b.path : b.blocking_path, 6) << "\n";
    }
    os << "  main code: longest IF = 0 stretch " << us(result.main_if0.us) << "\n";
    if (!result.fits()) os << "over budget: " << bound::describe_over_budget(result) << "\n";
}

} // namespace rcsim
