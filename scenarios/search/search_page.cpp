#include "scenarios/search/search_page.h"

#include "models/plumbing/output_file.h"
#include "scenarios/report/svg.h"
#include "scenarios/sweep/merge.h"
#include "scenarios/sweep/sweep.h"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <fstream>
#include <sstream>

namespace rcsim::search {

namespace fs = std::filesystem;
using nlohmann::json;
using svg::esc;
using svg::num;

namespace {

const char* direction_name(Direction d) { return d == Direction::maximize ? "maximize" : "minimize"; }

json value_or_null(const std::optional<double>& v) { return v ? json(*v) : json(); }

/// The witness's report.json, or null when it has none.
json witness_report(const PageInput& in) {
    if (!in.result.best) return json();
    const fs::path p = in.dir / "runs" / in.result.history[*in.result.best].id / "report.json";
    std::error_code ec;
    return fs::exists(p, ec) ? sweep::read_json_file(p) : json();
}

std::vector<std::size_t> by_influence(const std::vector<double>& share) {
    std::vector<std::size_t> order(share.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return share[a] > share[b]; });
    return order;
}

/// [lo, hi] of the measured figures.
std::pair<double, double> figure_span(const SearchResult& r) {
    double lo = INFINITY, hi = -INFINITY;
    for (const Point& p : r.history)
        if (p.figure) lo = std::min(lo, *p.figure), hi = std::max(hi, *p.figure);
    if (!(lo <= hi)) return {0, 1};
    if (lo == hi) return {lo - 1, hi + 1};
    return {lo, hi};
}

/// Best so far against runs (a step line) over every run's figure (dots).
std::string progress_chart(const PageInput& in) {
    const SearchResult& r = in.result;
    const double W = 560, H = 300, L = 70, R = 16, T = 34, B = 48;
    svg::Doc d(W, H, "best so far against runs");
    d.text(L, 18, "Best so far against runs", "start", 13, "font-weight=\"bold\"");
    const auto [lo, hi] = figure_span(r);
    const svg::NiceRange ny = svg::nice_range(lo, hi, 5);
    const svg::Scale sx{0, std::max<double>(1, static_cast<double>(r.history.size())), L, W - R, false};
    const svg::Scale sy{ny.lo, ny.hi, H - B, T, false};
    d.y_axis(sy, L, W - R, in.options.figure, 5);
    d.x_axis(sx, H - B, "run", 8, true);
    std::vector<svg::Point> line;
    std::optional<double> best;
    const bool up = in.options.direction == Direction::maximize;
    for (std::size_t i = 0; i < r.history.size(); ++i) {
        const Point& p = r.history[i];
        if (!p.figure) continue;
        d.with_title("<circle cx=\"" + num(sx(static_cast<double>(i + 1))) + "\" cy=\"" + num(sy(*p.figure)) +
                         "\" r=\"2.5\" fill=\"#8aa4c8\"",
                     p.id + ": " + num(*p.figure, 3));
        if (!best || (up ? *p.figure > *best : *p.figure < *best)) {
            if (best) line.push_back({sx(static_cast<double>(i + 1)), sy(*best)});
            best = p.figure;
            line.push_back({sx(static_cast<double>(i + 1)), sy(*best)});
        }
    }
    if (best) line.push_back({sx(static_cast<double>(r.history.size())), sy(*best)});
    if (line.size() > 1) d.polyline(line, "#c0392b", 2);
    return d.str();
}

/// A colour from pale (lowest figure) to dark red (highest).
std::string heat(double f, double lo, double hi) {
    const double t = hi > lo ? (f - lo) / (hi - lo) : 1;
    const unsigned g = static_cast<unsigned>(std::lround(220 - 190 * t)) & 0xFFu;
    const unsigned b = static_cast<unsigned>(std::lround(200 - 180 * t)) & 0xFFu;
    char buf[32];
    std::snprintf(buf, sizeof buf, "#e6%02x%02x", g, b);
    return buf;
}

/// The figure over the two most influential axes (over the one, against the figure, when there is one).
std::string axes_chart(const PageInput& in, const std::vector<double>& share) {
    const SearchResult& r = in.result;
    const auto order = by_influence(share);
    const bool two = r.axes.size() >= 2;
    const Axis& ax = r.axes[order[0]];
    const double W = 560, H = 340, L = 70, R = 16, T = 34, B = 48;
    svg::Doc d(W, H, "the figure over the most influential axes");
    d.text(L, 18, two ? "The figure over the two most influential axes" : "The figure over the axis", "start", 13,
           "font-weight=\"bold\"");
    const auto [flo, fhi] = figure_span(r);
    const svg::Scale sx{ax.lo, ax.hi > ax.lo ? ax.hi : ax.lo + 1, L, W - R, false};
    svg::Scale sy{flo, fhi, H - B, T, false};
    std::string ytitle = in.options.figure;
    if (two) {
        const Axis& ay = r.axes[order[1]];
        sy = {ay.lo, ay.hi > ay.lo ? ay.hi : ay.lo + 1, H - B, T, false};
        ytitle = ay.path;
    } else {
        const svg::NiceRange ny = svg::nice_range(flo, fhi, 5);
        sy = {ny.lo, ny.hi, H - B, T, false};
    }
    d.y_axis(sy, L, W - R, ytitle, 5);
    d.x_axis(sx, H - B, ax.path, 6, ax.whole);
    for (std::size_t i = 0; i < r.history.size(); ++i) {
        const Point& p = r.history[i];
        if (!p.figure || p.values.size() != r.axes.size()) continue;
        const double x = sx(p.values[order[0]]), y = sy(two ? p.values[order[1]] : *p.figure);
        d.with_title("<circle cx=\"" + num(x) + "\" cy=\"" + num(y) + "\" r=\"4\" fill=\"" + heat(*p.figure, flo, fhi) +
                         "\" stroke=\"#555\" stroke-width=\"0.5\"",
                     p.id + ": " + num(*p.figure, 3));
        if (r.best && *r.best == i) d.marker(x, y, svg::Marker::cross, "#000", 14);
    }
    return d.str();
}

std::string axes_table(const PageInput& in, const std::vector<double>& share) {
    std::ostringstream h;
    h << "<table><tr><th>axis</th><th>range</th><th>from</th><th>influence</th><th>witness</th></tr>\n";
    const Point* w = in.result.best ? &in.result.history[*in.result.best] : nullptr;
    for (std::size_t i : by_influence(share)) {
        const Axis& a = in.result.axes[i];
        h << "<tr><td><code>" << esc(a.path) << "</code></td><td>" << esc(a.text(a.lo)) << " .. " << esc(a.text(a.hi))
          << "</td><td>" << esc(a.origin) << "</td><td>" << num(100 * share[i], 1) << " %</td><td>"
          << (w && w->values.size() > i ? esc(a.text(w->values[i])) : std::string("(as written)")) << "</td></tr>\n";
    }
    return h.str() + "</table>\n";
}

std::string runs_table(const SearchResult& r) {
    std::ostringstream h;
    h << "<table><tr><th>#</th><th>run</th><th>stage</th><th>figure</th><th>verdict</th></tr>\n";
    for (std::size_t i = 0; i < r.history.size(); ++i) {
        const Point& p = r.history[i];
        h << "<tr" << (r.best && *r.best == i ? " class=\"best\"" : "") << "><td>" << i + 1
          << "</td><td><a href=\"runs/" << esc(p.id) << "/report.html\">" << esc(p.id) << "</a></td><td>" << esc(p.stage)
          << "</td><td>" << (p.figure ? num(*p.figure, 3) : std::string("not measured")) << "</td><td>" << esc(p.verdict)
          << "</td></tr>\n";
    }
    return h.str() + "</table>\n";
}

} // namespace

std::string reproduce_command(const PageInput& in) {
    std::string cmd = "rcsim run " + sweep::shell_quote((fs::path(in.options.out) / "worst.yaml").string());
    if (!in.options.symbols.empty()) cmd += " --symbols " + sweep::shell_quote(in.options.symbols);
    return cmd;
}

std::string witness_cause(const json& report, const std::string& figure) {
    if (!report.is_object()) return "";
    const std::string prefix = "interrupts.";
    if (figure.rfind(prefix, 0) == 0) {
        const std::string source = figure.substr(prefix.size(), figure.find('.', prefix.size()) - prefix.size());
        const json& worst = report["interrupts"][source]["worst"];
        if (figure.find(".latency_us.") != std::string::npos && worst.is_array() && !worst.empty() &&
            worst[0].contains("text"))
            return source + "'s worst latency: " + worst[0]["text"].get<std::string>();
    }
    if (figure.rfind("table3.", 0) == 0 && report.contains("table3") && report["table3"].is_object()) {
        const json& t = report["table3"];
        auto us = [&t](const char* key) { return t[key].is_number() ? num(t[key].get<double>(), 3) + " us" : std::string("not measured"); };
        return "Table 3 of the witness: budget " + us("budget_us") + "; RS-232 receive service mean " + us("rs232_isr_us") +
               ", longest " + us("rs232_isr_max_us") + "; DP-RAM byte " + us("dpram_byte_us") + "; margin " + us("margin_us") +
               ", worst margin " + us("worst_margin_us");
    }
    if (report.contains("checks") && report["checks"].is_array())
        for (const json& c : report["checks"])
            if (c.value("passed", true) == false && c.contains("why") && c["why"].is_string())
                return c.value("name", std::string("a check")) + ": " + c["why"].get<std::string>();
    return report.value("verdict_reason", std::string());
}

json search_json(const PageInput& in) {
    const SearchResult& r = in.result;
    const std::vector<double> share = influence(r);
    json axes = json::array();
    for (std::size_t i = 0; i < r.axes.size(); ++i) {
        const Axis& a = r.axes[i];
        axes.push_back({{"path", a.path}, {"lo", a.lo}, {"hi", a.hi}, {"whole", a.whole}, {"origin", a.origin},
                        {"influence", share[i]}});
    }
    json history = json::array();
    std::optional<double> best;
    const bool up = in.options.direction == Direction::maximize;
    for (const Point& p : r.history) {
        if (p.figure && (!best || (up ? *p.figure > *best : *p.figure < *best))) best = p.figure;
        json params = json::object();
        for (std::size_t i = 0; i < p.values.size(); ++i) params[r.axes[i].path] = sweep::scalar_json(YAML::Node(r.axes[i].text(p.values[i])));
        history.push_back({{"run", p.id}, {"stage", p.stage}, {"parameters", params}, {"value", value_or_null(p.figure)},
                           {"verdict", p.verdict}, {"best_so_far", value_or_null(best)}});
    }
    json j = {{"figure", in.options.figure}, {"direction", direction_name(in.options.direction)},
              {"scenario", in.scenario_name}, {"seed", in.options.seed}, {"algorithm", in.algorithm},
              {"starts", in.starts}, {"budget", in.options.runs}, {"runs", r.history.size()}, {"wall_s", r.wall_s},
              {"axes", axes}, {"history", history}, {"best", nullptr},
              {"base", r.history.empty() ? json() : value_or_null(r.history[0].figure)},
              {"interrupted", r.stopped_by ? json(r.stopped_by == SIGINT ? "SIGINT" : "SIGTERM") : json()}};
    if (r.best) {
        const Point& w = r.history[*r.best];
        j["best"] = {{"value", *w.figure}, {"run", w.id}, {"verdict", w.verdict}, {"parameters", history[*r.best]["parameters"]},
                     {"witness", "worst.yaml"}, {"report", "runs/" + w.id + "/report.html"},
                     {"cause", witness_cause(witness_report(in), in.options.figure)},
                     {"reproduce", reproduce_command(in)}};
    }
    return j;
}

std::string search_html(const PageInput& in, const json& s) {
    const SearchResult& r = in.result;
    std::vector<double> share;
    for (const json& a : s["axes"]) share.push_back(a["influence"].get<double>());
    std::ostringstream h;
    h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>rcsim search: " << esc(in.options.figure)
      << "</title>\n<style>body{font:14px sans-serif;margin:24px;max-width:1180px}table{border-collapse:collapse;margin:8px 0}"
         "td,th{border:1px solid #ccc;padding:3px 8px;text-align:left}tr.best{background:#fde2e2}"
         ".result{border:2px solid #c0392b;padding:10px 14px;margin:12px 0}.cause{white-space:pre-wrap;font-family:monospace}"
         ".charts{display:flex;flex-wrap:wrap;gap:12px}</style></head><body>\n";
    h << "<h1>rcsim search: " << esc(direction_name(in.options.direction)) << " <code>" << esc(in.options.figure)
      << "</code></h1>\n<p>Scenario <b>" << esc(in.scenario_name) << "</b>, " << r.history.size() << " runs of a budget of "
      << in.options.runs << ", " << esc(in.algorithm) << " from " << in.starts << " starts after a Latin-hypercube sample, seed "
      << in.options.seed << (r.stopped_by ? ", <b>stopped by a signal</b>" : "") << ".</p>\n";
    h << "<div class=\"result\">";
    if (r.best) {
        const Point& w = r.history[*r.best];
        h << "<p><b>Worst case found: " << num(*w.figure, 3) << "</b> in run <a href=\"runs/" << esc(w.id) << "/report.html\">"
          << esc(w.id) << "</a> (" << esc(w.verdict) << "); the scenario as written gave "
          << (r.history[0].figure ? num(*r.history[0].figure, 3) : std::string("not measured"))
          << ".</p>\n<p>Witness: <a href=\"worst.yaml\">worst.yaml</a> &mdash; <code>" << esc(reproduce_command(in))
          << "</code> gives the same figure.</p>\n";
        const std::string cause = s["best"].value("cause", std::string());
        if (!cause.empty()) h << "<p>What held it:</p><div class=\"cause\">" << esc(cause) << "</div>\n";
    } else {
        h << "<p><b>Not measured:</b> no run reported the figure.</p>\n";
    }
    const auto [flo, fhi] = figure_span(r);
    h << "</div>\n<div class=\"charts\">" << progress_chart(in) << (r.axes.empty() ? "" : axes_chart(in, share))
      << "</div>\n<p>Left: every run's figure (dots) and the best so far (line). Right: "
      << (r.axes.size() >= 2 ? "every run at its values of the two axes that explain most of the figure's variance"
                             : "every run's figure against the axis")
      << ", coloured from pale (" << num(flo, 3) << ") to dark red (" << num(fhi, 3) << "); &times; marks the witness.</p>\n"
      << "<h2>Axes</h2>\n<p>Influence: the share of the figure's variance over the runs that the axis explains alone "
         "(its correlation ratio over four equal cells).</p>\n"
      << axes_table(in, share) << "<h2>Runs</h2>\n<p>Every run's figures side by side: <a href=\"summary.html\">summary.html</a>.</p>\n"
      << runs_table(r) << "</body></html>\n";
    return h.str();
}

json write_witness(const PageInput& in) {
    const json s = search_json(in);
    if (in.result.best) {
        const Point& w = in.result.history[*in.result.best];
        std::ifstream f(in.dir / "runs" / w.id / "scenario.yaml");
        std::string line, body;
        std::getline(f, line); // the sweep's header comment
        for (std::string l; std::getline(f, l);) body += l + "\n";
        write_file(in.dir / "worst.yaml",
                   "# rcsim search witness: " + in.options.figure + " = " + num(*w.figure, 6) + " (run " + w.id + " of " +
                       std::to_string(in.result.history.size()) + ", search.json)\n# reproduce: " + reproduce_command(in) +
                       "\n" + body,
                   "the witness");
    }
    write_file(in.dir / "search.json", s.dump(2) + "\n", "the search's history");
    write_file(in.dir / "search.html", search_html(in, s), "the search's page");
    return s;
}

void print_outcome(const PageInput& in, std::ostream& out) {
    const SearchResult& r = in.result;
    if (r.best) {
        const Point& w = r.history[*r.best];
        out << "best: " << in.options.figure << " = " << num(*w.figure, 3) << " (run " << w.id << ", " << w.verdict
            << "; the scenario as written: "
            << (r.history[0].figure ? num(*r.history[0].figure, 3) : std::string("not measured")) << ")\n"
            << "witness: " << (fs::path(in.options.out) / "worst.yaml").string() << "\n";
    } else {
        out << "best: " << in.options.figure << " not measured in any run\n";
    }
    out << "search: " << (fs::path(in.options.out) / "search.html").string() << "\n";
}

} // namespace rcsim::search
