// rcsim — the parts report.html is made of, shared by the page (report_html.cpp) and its charts
// (html_charts.cpp): tolerant readers of report.json values, number formats, the SVG charts.
// Internal to scenarios/report/.
#pragma once

#include "scenarios/report/interrupt_log.h"
#include "scenarios/report/report_html.h"
#include "scenarios/report/svg.h"
#include "models/plumbing/hex.h"
#include "models/stats.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace rcsim::report::html {

using json = nlohmann::json;

/// The colour of an IR level in every chart.
inline const char* colour_of(unsigned level) {
    static const char* const kLevelColour[] = {"#1f77b4", "#2ca02c", "#9467bd", "#e07b00",
                                               "#8c564b", "#7f7f7f", "#bcbd22", "#17becf"};
    return kLevelColour[level % 8];
}

// report.json values, with a default where the key is missing or of another type (a page is
// drawn for any report, however partial).
inline double jd(const json& j, const char* key, double def = 0) {
    if (j.is_object() && j.contains(key) && j[key].is_number()) return j[key].get<double>();
    return def;
}
inline std::uint64_t ju(const json& j, const char* key) {
    if (j.is_object() && j.contains(key) && j[key].is_number()) return j[key].get<std::uint64_t>();
    return 0;
}
inline std::string js(const json& j, const char* key, const std::string& def = "") {
    if (j.is_object() && j.contains(key) && j[key].is_string()) return j[key].get<std::string>();
    return def;
}
inline const json& jo(const json& j, const char* key) {
    static const json empty = json::object();
    if (j.is_object() && j.contains(key)) return j[key];
    return empty;
}

/// Whole numbers without decimals, others with `dec`.
inline std::string smart(double v, int dec = 3) {
    return (std::floor(v) == v && std::fabs(v) < 1e15) ? svg::num(v, 0) : svg::num(v, dec);
}

/// A histogram of `v` with min, mean, p99 and max marked.
std::string histogram_svg(const std::string& title, const Samples& v, const std::string& xlabel,
                          const std::string& colour);
/// Table 3: simulated vs paper, bars with the budget line and the margin.
std::string table3_svg(const json& t);
/// Per-port character latency (stop bit to RXD read): min..max bar, mean and p99 ticks, limit.
std::string char_latency_svg(const json& ports, double limit);
/// The logic-analyser picture of [t0, t1]: one row per IR level, a thin bar from IR rise to the
/// first ISR instruction (waiting), a thick bar from there to IRET done (in service), ticks at
/// the INTA cycles and at the EOI. The x axis is (t - origin_us) / unit_us. `rows` are those that
/// reach into [t0, t1], in entry order; `levels` IR rows are drawn.
std::string timeline_svg(const std::vector<TimelineRow>& rows, unsigned levels, double t0, double t1,
                         double origin_us, double unit_us, const std::string& xlabel, const InterruptRow* mark,
                         const std::string& aria);

} // namespace rcsim::report::html
