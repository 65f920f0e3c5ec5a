// rcsim — summary.html (merge.h) and the charts of summary.html and compare.html.
#include "scenarios/sweep/summary_html.h"

#include "scenarios/sweep/merge.h"
#include "scenarios/report/svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

namespace rcsim::sweep {

using json = nlohmann::json;
using svg::esc;
using svg::num;

namespace html {

const char* const kCss =
    "body{font-family:-apple-system,\"Segoe UI\",Helvetica,Arial,sans-serif;font-size:14px;color:#222;"
    "margin:0 auto;max-width:1300px;padding:0 16px 40px}"
    "h1{font-size:22px}h2{font-size:18px;margin-top:32px;border-bottom:1px solid #ccc}"
    "table{border-collapse:collapse;font-size:12px;margin:8px 0}"
    "th,td{border:1px solid #ddd;padding:2px 6px;text-align:right;white-space:nowrap}"
    "th{background:#f2f2f2;white-space:normal;overflow-wrap:anywhere}td.k,th.k{text-align:left}"
    "td.w{white-space:normal;overflow-wrap:anywhere;min-width:14em}pre{font-size:12px;overflow-x:auto}"
    "tr.fail td{background:#fbe3e4}tr.stopped td{background:#eee;color:#555}tr.reg td{background:#fbe3e4}tr.imp td{background:#e3f6e6}"
    "tr.within td{background:#fff8e0}tr.ign td{color:#999}td.better{color:#0a7a28}td.worse{color:#b3141d}"
    ".banner{padding:10px 14px;border-radius:4px;font-weight:bold}.pass{background:#e3f6e6}"
    ".fail{background:#fbe3e4}.charts{display:flex;flex-wrap:wrap;gap:8px}"
    "details{margin:4px 0}summary{cursor:pointer}";

std::string cell(double v) {
    if (!std::isfinite(v)) return "-";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

namespace {

const char* const kPalette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b",
                                "#e377c2", "#7f7f7f", "#bcbd22", "#17becf", "#393b79"};

/// [lo, hi] widened so that a constant or a single value still gets an axis.
std::pair<double, double> padded(double lo, double hi, bool log) {
    if (log) return {lo / 1.3, hi * 1.3};
    if (hi == lo) {
        const double d = lo == 0 ? 1 : std::fabs(lo) * 0.1;
        return {lo - d, hi + d};
    }
    const double d = (hi - lo) * 0.08;
    return {lo - d, hi + d};
}

} // namespace

std::string xy_chart(const std::string& title, const std::string& xlabel, const std::string& ylabel,
                     const std::vector<XySeries>& series) {
    // The legend goes under the plot, a row per series, so that it never hides a point.
    const bool legend = series.size() > 1 && series.size() <= 6;
    const double kLegendRow = 15;
    const double W = 420, plot_h = 280, L = 64, R = 14, T = 34, B = 50;
    const double H = plot_h + (legend ? kLegendRow * static_cast<double>(series.size()) + 4 : 0);
    svg::Doc d(W, H, title);
    d.text(L, 18, title, "start", 13, "font-weight=\"bold\"");
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    bool whole_x = true; // wait states, sizes: ticks at whole values only
    for (const auto& s : series)
        for (const auto& p : s.points) {
            x0 = std::min(x0, p.x), x1 = std::max(x1, p.x);
            y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
            whole_x = whole_x && p.x == std::floor(p.x);
        }
    if (!(x0 <= x1)) {
        d.text(W / 2, H / 2, "no values", "middle", 12, "fill=\"#888\"");
        return d.str();
    }
    const bool log = x0 > 0 && x1 / x0 >= 20;
    const auto [xa, xb] = padded(x0, x1, log);
    const auto [ya, yb] = padded(y0, y1, false);
    const svg::Scale sx{xa, xb, L, W - R, log};
    const svg::Scale sy{ya, yb, plot_h - B, T, false};
    d.y_axis(sy, L, W - R, ylabel, 5);
    d.x_axis(sx, plot_h - B, xlabel, 6, whole_x && !log);
    for (std::size_t i = 0; i < series.size(); ++i) {
        const std::string colour = kPalette[i % (sizeof kPalette / sizeof kPalette[0])];
        std::vector<svg::Point> line;
        for (const auto& p : series[i].points) line.push_back({sx(p.x), sy(p.y)});
        if (line.size() > 1) d.polyline(line, colour, 1.5);
        for (const auto& p : series[i].points) {
            d.with_title("<circle cx=\"" + num(sx(p.x)) + "\" cy=\"" + num(sy(p.y)) + "\" r=\"3.5\" fill=\"" + colour +
                             "\"",
                         p.tip);
            if (p.stopped)
                d.with_title("<circle class=\"stopped\" cx=\"" + num(sx(p.x)) + "\" cy=\"" + num(sy(p.y)) +
                                 "\" r=\"7\" fill=\"none\" stroke=\"#777\" stroke-dasharray=\"2 2\"",
                             p.tip);
            else if (p.failed)
                d.marker(sx(p.x), sy(p.y), svg::Marker::cross, "#c82333", 11);
        }
    }
    if (legend) {
        std::vector<svg::LegendEntry> entries;
        for (std::size_t i = 0; i < series.size(); ++i) entries.push_back({series[i].label, kPalette[i]});
        d.legend(L - 40, plot_h + 8, entries, kLegendRow);
    }
    return d.str();
}

std::string overlaid_histogram(const std::string& title, const std::vector<double>& baseline,
                               const std::vector<double>& current) {
    const double W = 420, H = 250, L = 56, R = 14, T = 40, B = 50;
    svg::Doc d(W, H, title);
    d.text(L, 18, title, "start", 13, "font-weight=\"bold\"");
    double lo = INFINITY, hi = -INFINITY;
    for (const auto* v : {&baseline, &current})
        for (double x : *v) lo = std::min(lo, x), hi = std::max(hi, x);
    if (!(lo <= hi)) {
        d.text(W / 2, H / 2, "no values", "middle", 12, "fill=\"#888\"");
        return d.str();
    }
    const auto [a, b] = padded(lo, hi, false);
    const int bins = 12;
    const double width = (b - a) / bins;
    auto count = [&](const std::vector<double>& v) {
        std::vector<int> c(bins, 0);
        for (double x : v) ++c[std::min(bins - 1, static_cast<int>((x - a) / width))];
        return c;
    };
    const auto cb = count(baseline), cc = count(current);
    const int top = std::max(*std::max_element(cb.begin(), cb.end()), *std::max_element(cc.begin(), cc.end()));
    const svg::Scale sx{a, b, L, W - R, false};
    const svg::Scale sy{0, std::max(1.0, top * 1.15), H - B, T, false};
    d.y_axis(sy, L, W - R, "runs", 4);
    struct Layer { const std::vector<int>* c; const char* colour; const char* name; };
    for (const Layer& layer : {Layer{&cb, "#1f77b4", "baseline"}, Layer{&cc, "#ff7f0e", "current"}})
        for (int i = 0; i < bins; ++i) {
            if (!(*layer.c)[i]) continue;
            const double x0 = sx(a + width * i), x1 = sx(a + width * (i + 1)), y = sy((*layer.c)[i]);
            d.with_title("<rect x=\"" + num(x0 + 0.5) + "\" y=\"" + num(y) + "\" width=\"" + num(x1 - x0 - 1) +
                             "\" height=\"" + num(sy.p0 - y) + "\" fill=\"" + layer.colour + "\" fill-opacity=\"0.55\"",
                         std::string(layer.name) + ": " + std::to_string((*layer.c)[i]) + " runs in " +
                             cell(a + width * i) + " .. " + cell(a + width * (i + 1)));
        }
    d.x_axis(sx, H - B, "value", 6);
    d.legend(W - R - 110, T - 14, {{"baseline", "#1f77b4", "", true}, {"current", "#ff7f0e", "", true}}, 16);
    return d.str();
}

} // namespace html

namespace {

/// The figures summary.html plots against each numeric axis. `ports[*]` sums over the ports.
struct Headline {
    const char* key;
    const char* title;
};
const Headline kHeadlines[] = {
    {"table3.rs232_isr_us", "Table 3 RS-232 ISR mean [us]"},
    {"table3.rs232_isr_max_us", "Table 3 RS-232 ISR max [us]"},
    {"table3.dpram_byte_us", "Table 3 DP-RAM per byte [us]"},
    {"table3.margin_us", "Table 3 margin [us]"},
    {"table3.worst_margin_us", "Table 3 worst-case margin [us]"},
    {"interrupts.rs232_rx.latency_us.p99", "RS-232 RX latency p99 [us]"},
    {"interrupts.rs232_rx.latency_us.max", "RS-232 RX latency max [us]"},
    {"interrupts.dpram.latency_us.max", "DP-RAM interrupt latency max [us]"},
    {"ports[*].frames_delivered", "frames delivered (all ports)"},
    {"ports[*].overruns", "82510 overruns (all ports)"},
    {"motion.max_following_error_pulses", "max following error [pulses]"},
    {"rtf", "real-time factor"},
};

/// A headline figure of one summary run, or NaN when it has none.
double headline(const json& run, const std::string& key) {
    const json& f = run["figures"];
    const auto star = key.find("[*]");
    if (star == std::string::npos) return f.contains(key) && f[key].is_number() ? f[key].get<double>() : NAN;
    double sum = 0;
    bool any = false;
    for (int p = 0; p < 16; ++p) {
        const std::string k = key.substr(0, star) + "[" + std::to_string(p) + "]" + key.substr(star + 3);
        if (!f.contains(k)) break;
        if (f[k].is_number()) sum += f[k].get<double>(), any = true;
    }
    return any ? sum : NAN;
}

/// A run the sweep stopped: interrupted (its report holds the figures so far) or never run.
bool stopped_run(const json& run) {
    const std::string status = run.value("status", std::string());
    return status == "interrupted" || status == "not run";
}

/// The checks a summary run failed, comma-separated ("" when none).
std::string failed_checks(const json& run) {
    std::string failed;
    for (const auto& [name, c] : run["checks"].items())
        if (!c.value("passed", false)) failed += (failed.empty() ? "" : ", ") + name;
    return failed;
}

/// Parameters whose values are numbers in every run that has them, with two distinct values at least.
std::vector<std::string> numeric_axes(const json& runs) {
    std::map<std::string, std::set<double>> values;
    std::set<std::string> not_numeric;
    for (const auto& r : runs)
        for (const auto& [k, v] : r["parameters"].items()) {
            if (v.is_number()) values[k].insert(v.get<double>());
            else not_numeric.insert(k);
        }
    std::vector<std::string> out;
    for (const auto& [k, vs] : values)
        if (!not_numeric.count(k) && vs.size() >= 2) out.push_back(k);
    return out;
}

/// The runs that have `axis`, one series per combination of their other parameters.
std::vector<html::XySeries> series_of(const json& runs, const std::string& axis, const std::string& key) {
    std::map<std::string, html::XySeries> by;
    for (const auto& r : runs) {
        const json& p = r["parameters"];
        if (!p.contains(axis) || !p[axis].is_number()) continue;
        const double y = headline(r, key);
        if (std::isnan(y)) continue;
        std::string label = r["entry"].get<std::string>();
        for (const auto& [k, v] : p.items())
            if (k != axis) label += " " + k.substr(k.rfind('.') == std::string::npos ? 0 : k.rfind('.') + 1) + "=" + number_text(v);
        auto& s = by[label];
        s.label = label;
        // A failed run's point says which checks failed.
        const std::string failed = failed_checks(r);
        const bool stopped = stopped_run(r);
        s.points.push_back({p[axis].get<double>(), y, r["status"] != "passed",
                            r["id"].get<std::string>() + ": " + html::cell(y) +
                                (stopped ? "; interrupted (figures so far)" : failed.empty() ? "" : "; failed: " + failed),
                            stopped});
    }
    std::vector<html::XySeries> out;
    for (auto& [k, s] : by) {
        std::sort(s.points.begin(), s.points.end(), [](const auto& a, const auto& b) { return a.x < b.x; });
        out.push_back(std::move(s));
    }
    return out;
}

void runs_table(const json& runs, std::ostringstream& o) {
    std::vector<std::string> params;
    std::set<std::string> seen;
    for (const auto& r : runs)
        for (const auto& [k, v] : r["parameters"].items())
            if (seen.insert(k).second) params.push_back(k);
    // A headline no run has (the motion figure of a serial sweep) would be a column of dashes: left
    // out, and named under the table, so that the table fits 1280 px.
    std::vector<const Headline*> shown;
    std::string absent;
    for (const Headline& h : kHeadlines) {
        const bool any = std::any_of(runs.begin(), runs.end(), [&](const json& r) { return !std::isnan(headline(r, h.key)); });
        if (any) shown.push_back(&h);
        else absent += (absent.empty() ? "" : ", ") + std::string(h.key);
    }
    o << "<table id=\"runs\">\n<tr><th class=\"k\">run</th><th class=\"k\">status</th>";
    for (const auto& p : params) o << "<th>" << esc(p) << "</th>";
    for (const Headline* h : shown) o << "<th>" << esc(h->title) << "</th>";
    // The checks and the sweep's judgement in one wrapping column (three were wider than 1280 px).
    o << "<th class=\"k\">outcome: failed checks, expected to fail, why</th></tr>\n";
    for (const auto& r : runs) {
        // Red is what fails the sweep: a run not as expected, not a by-design failure.
        const std::string judged = r.value("outcome", std::string("?"));
        const bool ok = judged == "passed" || judged == "inconclusive";
        o << "<tr" << (stopped_run(r) ? " class=\"stopped\"" : ok ? "" : " class=\"fail\"") << "><td class=\"k\">" << esc(r["id"].get<std::string>())
          << "</td><td class=\"k\">" << esc(r["status"].get<std::string>()) << "</td>";
        for (const auto& p : params)
            o << "<td>" << (r["parameters"].contains(p) ? esc(number_text(r["parameters"][p])) : "") << "</td>";
        for (const Headline* h : shown) o << "<td>" << html::cell(headline(r, h->key)) << "</td>";
        const std::string failed = failed_checks(r);
        std::string expected;
        for (const auto& name : r.value("expected_failures", json::array())) expected += (expected.empty() ? "" : ", ") + name.get<std::string>();
        o << "<td class=\"k w\">" << esc(judged);
        if (!failed.empty()) o << "<br>failed: " << esc(failed);
        if (!expected.empty()) o << "<br>expected to fail: " << esc(expected);
        for (const auto& why : r.value("outcome_why", json::array())) o << "<br>" << esc(why.get<std::string>());
        o << "</td></tr>\n";
    }
    o << "</table>\n";
    if (!absent.empty()) o << "<p>In no run: " << esc(absent) << ".</p>\n";
}

} // namespace

std::string summary_html(const nlohmann::json& summary) {
    const json& runs = summary["results"];
    // The sweep's judgement, run by run: as expected, not, or stopped (interrupted, not run), which
    // is neither (issue #51: stopped runs were counted as "not" as expected).
    std::size_t expected = 0, not_expected = 0, stopped_runs = 0;
    for (const auto& r : runs) {
        const std::string outcome = r.value("outcome", std::string("?"));
        if (stopped_run(r)) ++stopped_runs;
        else if (outcome == "passed" || outcome == "inconclusive") ++expected;
        else ++not_expected;
    }
    // Only an interrupted sweep has these: a complete one's page stays as it was.
    const std::size_t interrupted = summary.value("interrupted", 0u), not_run = summary.value("not run", 0u);
    std::string stopped;
    if (interrupted) stopped += ", " + std::to_string(interrupted) + " interrupted";
    if (not_run) stopped += ", " + std::to_string(not_run) + " not run (the sweep was interrupted)";
    std::ostringstream o;
    o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>rcsim sweep: "
      << runs.size() << " runs, " << not_expected << " not as expected</title>\n<style>" << html::kCss
      << "</style>\n</head>\n<body>\n<h1>rcsim sweep summary</h1>\n<div class=\"banner "
      << (not_expected || stopped_runs ? "fail" : "pass") << "\" id=\"banner\">" << runs.size() << " runs: "
      << summary.value("passed", 0u) << " passed, " << summary.value("failed", 0u) << " failed a check, "
      << summary.value("no report", 0u) << " without a report" << stopped << "; " << expected << " as expected, "
      << not_expected << " not" << (stopped_runs ? ", " + std::to_string(stopped_runs) + " interrupted/not run" : "")
      << "</div>\n<h2>Runs</h2>\n";
    runs_table(runs, o);
    for (const std::string& axis : numeric_axes(runs)) {
        o << "<h2>Against " << esc(axis) << "</h2>\n<p>One line per combination of the other parameters; "
             "a red cross marks a run that failed, a dashed grey ring one interrupted (its figures so far).</p>\n<div class=\"charts\">\n";
        std::string constant;
        for (const Headline& h : kHeadlines) {
            const auto series = series_of(runs, axis, h.key);
            bool nonzero = false;
            for (const auto& s : series)
                for (const auto& p : s.points) nonzero = nonzero || p.y != 0;
            if (series.empty()) continue;
            if (!nonzero) { // rtf with --reproducible, overruns when there are none
                constant += (constant.empty() ? "" : ", ") + std::string(h.key);
                continue;
            }
            o << html::xy_chart(h.title, axis, h.title, series) << "\n";
        }
        o << "</div>\n";
        if (!constant.empty()) o << "<p>0 in every run: " << esc(constant) << ".</p>\n";
    }
    o << "</body>\n</html>\n";
    return o.str();
}

} // namespace rcsim::sweep
