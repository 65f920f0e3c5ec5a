#include "tests/scenarios/trace/trace_check.h"

#include <sstream>

namespace rcsim::test {

const nlohmann::json& trace_events(const nlohmann::json& doc) {
    static const nlohmann::json none = nlohmann::json::array();
    if (doc.is_array()) return doc;
    if (doc.is_object() && doc.contains("traceEvents") && doc["traceEvents"].is_array()) return doc["traceEvents"];
    return none;
}

std::map<std::pair<long, long>, std::string> thread_names(const nlohmann::json& doc) {
    std::map<std::pair<long, long>, std::string> names;
    for (const auto& e : trace_events(doc))
        if (e.value("ph", "") == "M" && e.value("name", "") == "thread_name")
            names[{e.value("pid", -1L), e.value("tid", -1L)}] = e["args"].value("name", "");
    return names;
}

namespace {

struct Track {
    double last_ts = -1e300;
    std::vector<std::string> open_b;   // names of open B slices, innermost last
    std::vector<double> open_x_end;    // ends of the X slices enclosing the current time
};

} // namespace

std::vector<std::string> check_trace(const nlohmann::json& doc, std::size_t limit) {
    std::vector<std::string> problems;
    auto bad = [&](std::size_t i, const std::string& what) {
        if (problems.size() < limit) problems.push_back("event " + std::to_string(i) + ": " + what);
    };
    if (!doc.is_array() && !(doc.is_object() && doc.contains("traceEvents") && doc["traceEvents"].is_array())) {
        problems.push_back("not a trace: neither {\"traceEvents\":[...]} nor an array");
        return problems;
    }
    std::map<std::string, Track> tracks;
    const auto& events = trace_events(doc);
    for (std::size_t i = 0; i < events.size(); ++i) {
        const auto& e = events[i];
        if (!e.is_object() || !e.contains("ph") || !e["ph"].is_string() || !e.contains("pid")) {
            bad(i, "not an event object with ph and pid");
            continue;
        }
        const std::string ph = e["ph"];
        if (ph == "M") continue;
        if (!e.contains("ts") || !e["ts"].is_number()) {
            bad(i, "no numeric ts");
            continue;
        }
        const double ts = e["ts"];
        const std::string name = e.value("name", "");
        std::ostringstream key;
        if (ph == "C") key << "C/" << e["pid"] << "/" << name;
        else key << "T/" << e["pid"] << "/" << e.value("tid", nlohmann::json(0));
        Track& t = tracks[key.str()];
        if (ts < t.last_ts) bad(i, "ts " + std::to_string(ts) + " before the track's previous " + std::to_string(t.last_ts));
        t.last_ts = ts;
        while (!t.open_x_end.empty() && t.open_x_end.back() <= ts) t.open_x_end.pop_back();
        if (ph == "B") {
            t.open_b.push_back(name);
        } else if (ph == "E") {
            if (t.open_b.empty()) bad(i, "E without an open B");
            else if (!name.empty() && name != t.open_b.back()) bad(i, "E '" + name + "' closes B '" + t.open_b.back() + "'");
            if (!t.open_b.empty()) t.open_b.pop_back();
        } else if (ph == "X") {
            if (!e.contains("dur") || !e["dur"].is_number() || e["dur"].get<double>() < 0) {
                bad(i, "X without a duration >= 0");
                continue;
            }
            const double end = ts + e["dur"].get<double>();
            if (!t.open_x_end.empty() && end > t.open_x_end.back())
                bad(i, "X '" + name + "' starts inside a slice but ends after it");
            t.open_x_end.push_back(end);
        } else if (ph == "C") {
            if (!e.contains("args") || !e["args"].is_object() || e["args"].empty()) bad(i, "counter without args");
            else
                for (const auto& [k, v] : e["args"].items())
                    if (!v.is_number()) bad(i, "counter arg '" + k + "' is not a number");
        } else if (ph != "i" && ph != "I") {
            bad(i, "phase '" + ph + "' is not one this validator knows");
        }
    }
    for (const auto& [k, t] : tracks)
        if (!t.open_b.empty()) problems.push_back("track " + k + ": " + std::to_string(t.open_b.size()) + " B never closed");
    return problems;
}

} // namespace rcsim::test
