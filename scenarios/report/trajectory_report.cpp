// rcsim — the trajectory files. See trajectory_report.h.
#include "scenarios/report/trajectory_report.h"

#include "models/plumbing/config_error.h"
#include "models/plumbing/output_file.h"
#include "scenarios/report/svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>

namespace rcsim {

namespace {

using motion::TrajectorySample;

const char* const kAxisColour[4] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd"};
constexpr unsigned kAxes = 4;

bool has_axis(const TrajectorySample& s, unsigned a) { return s.cmd.size() > a && s.act.size() > a; }

/// The axes whose command or actual position ever left its first value.
std::vector<unsigned> moving_axes(const std::vector<TrajectorySample>& v) {
    std::vector<unsigned> out;
    for (unsigned a = 0; a < kAxes; ++a) {
        bool moved = false;
        for (const auto& s : v) {
            if (!has_axis(s, a)) continue;
            if (s.cmd[a] != v.front().cmd[a] || s.act[a] != v.front().act[a]) moved = true;
            if (moved) break;
        }
        if (moved) out.push_back(a);
    }
    if (out.empty()) out.push_back(0);
    return out;
}

/// One series of a time panel: `value(sample, previous)` (nullopt: no point), its colour, dash.
struct Series {
    std::string label, colour, dash;
    std::function<std::optional<double>(const TrajectorySample&, const TrajectorySample*)> value;
};

/// A panel of series against time at (x, y), w x h pixels, decimated to its pixel columns.
void time_panel(svg::Doc& d, const std::vector<TrajectorySample>& v, double x, double y, double w, double h,
                const std::string& y_title, const std::vector<Series>& series, double t0, double t1) {
    std::vector<std::vector<std::pair<double, double>>> pts;
    double lo = 0, hi = 0;
    bool any = false;
    for (const Series& s : series) {
        svg::ColumnDecimator dec(t0, t1, static_cast<unsigned>(w));
        const TrajectorySample* prev = nullptr;
        for (const auto& smp : v) {
            if (const auto val = s.value(smp, prev)) dec.add(smp.t_s, *val);
            prev = &smp;
        }
        pts.push_back(dec.points());
        for (const auto& [t, val] : pts.back()) {
            if (!any) lo = hi = val, any = true;
            lo = std::min(lo, val), hi = std::max(hi, val);
        }
    }
    const svg::NiceRange ry = svg::nice_range(lo, hi, 4);
    const svg::Scale sx{t0, t1, x, x + w, false}, sy{ry.lo, ry.hi, y + h, y, false};
    d.y_axis(sy, x, x + w, y_title, 4);
    d.x_axis(sx, y + h, "time [s]", 8);
    d.frame(x, y, w, h);
    std::vector<svg::LegendEntry> legend;
    for (std::size_t i = 0; i < series.size(); ++i) {
        std::vector<svg::Point> p;
        p.reserve(pts[i].size());
        for (const auto& [t, val] : pts[i]) p.push_back({sx(t), sy(val)});
        const std::string extra = series[i].dash.empty() ? "" : "stroke-dasharray=\"" + series[i].dash + "\"";
        if (!p.empty()) d.polyline(p, series[i].colour, 1.2, extra);
        legend.push_back({series[i].label, series[i].colour, series[i].dash});
    }
    // The legend to the right of the panel, one row per series.
    d.legend(x + w + 12, y + 10, legend, 16);
}

/// The velocity the recorder kept with `s` (since its control cycle's previous sample).
std::optional<double> velocity(const TrajectorySample& s, unsigned a, bool actual) {
    if (!s.has_velocity || a >= s.vel_cmd.size() || !has_axis(s, a)) return std::nullopt;
    return actual ? s.vel_act[a] : s.vel_cmd[a];
}

} // namespace

TrajectoryCsv::TrajectoryCsv(const std::filesystem::path& file, std::size_t every)
    : file_(file), every_(std::max<std::size_t>(every, 1)) {
    file_.stream() << "t_s,axis,cmd_pulses,act_pulses\n";
}

void TrajectoryCsv::row(const TrajectorySample& s) {
    char t[32];
    std::snprintf(t, sizeof t, "%.6f", s.t_s);
    for (std::size_t a = 0; a < s.cmd.size() && a < s.act.size(); ++a)
        file_.stream() << t << ',' << a << ',' << s.cmd[a] << ',' << s.act[a] << '\n';
}

void TrajectoryCsv::add(const TrajectorySample& s) {
    if (closed_) return;
    if (n_++ % every_ == 0) {
        row(s);
        unwritten_.reset();
    } else {
        unwritten_ = s; // assigned, not rebuilt: the vectors keep their storage
    }
}

void TrajectoryCsv::close() {
    if (closed_) return;
    closed_ = true;
    if (unwritten_) row(*unwritten_); // every n-th, and the last
    file_.close();
}

void write_pulse_csv(const std::vector<camc::PulseEvent>& pulses, const std::filesystem::path& file) {
    OutputFile f(file);
    std::ostream& out = f.stream();
    out << "t_s,axis,dir\n";
    char t[40];
    for (const auto& p : pulses) {
        // Twelve decimals: the kernel's picosecond, exactly.
        std::snprintf(t, sizeof t, "%.12f", p.time.to_seconds());
        out << t << ',' << p.axis << ',' << p.dir << '\n';
    }
    f.close();
}

std::string trajectory_svg(const motion::TrajectoryRecorder& rec, unsigned ax, unsigned ay, const std::string& title) {
    const std::vector<TrajectorySample> v = rec.plot_samples();
    // The bounding box of both paths (a unit box when nothing was recorded).
    double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
    bool any = false;
    for (const auto& s : v) {
        if (!has_axis(s, std::max(ax, ay))) continue;
        for (const auto* p : {&s.cmd, &s.act}) {
            const double x = double((*p)[ax]), y = double((*p)[ay]);
            if (!any) x0 = x1 = x, y0 = y1 = y, any = true;
            x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        }
    }
    // A margin of 5 % of the larger extent on every side: a move along the path's edge (a square's
    // side) would otherwise lie on the frame and be hidden by it.
    const double pad = 0.05 * std::max({x1 - x0, y1 - y0, 1.0});
    x0 -= pad, x1 += pad, y0 -= pad, y1 += pad;
    // Equal scales on nice bounds: the larger extent sets the span and the step; the other axis
    // gets the same span on multiples of that step around its middle.
    const bool x_big = x1 - x0 >= y1 - y0;
    const svg::NiceRange big = x_big ? svg::nice_range(x0, x1, 8) : svg::nice_range(y0, y1, 8);
    double span = big.hi - big.lo;
    const double o_lo = x_big ? y0 : x0, o_hi = x_big ? y1 : x1;
    double other = std::floor(((o_lo + o_hi) / 2 - span / 2) / big.step + 0.5) * big.step;
    if (other > o_lo) other -= big.step;
    if (other + span < o_hi) span += big.step;
    const double bx = x_big ? big.lo : other, by = x_big ? other : big.lo;

    // The X-Y square P x P at (M, top); the right margin holds the error panel's legend.
    const double M = 70, P = 500, W = M + P + 150, top = 60;
    const double fe_top = top + P + 70, fe_h = 130, H = fe_top + fe_h + 60; // following-error panel
    const svg::Scale sx{bx, bx + span, M, M + P, false};
    const svg::Scale sy{by, by + span, top + P, top, false};

    svg::Doc d(W, H, title);
    d.rect(0, 0, W, H, "white");
    d.title(title);
    d.y_axis(sy, M, M + P, "axis " + std::to_string(ay) + " position [pulses]", 8);
    d.x_axis(sx, top + P, "axis " + std::to_string(ax) + " position [pulses]", 8);
    d.frame(M, top, P, P);
    svg::Point start{}, arrow_at{}, arrow_from{}, end{};
    bool have_arrow = false;
    double travelled = 0;
    for (const bool actual : {false, true}) {
        svg::PathDecimator path(W, H);
        for (const auto& s : v) {
            if (!has_axis(s, std::max(ax, ay))) continue;
            const auto& p = actual ? s.act : s.cmd;
            path.add({sx(double(p[ax])), sy(double(p[ay]))});
        }
        const std::string colour = actual ? "#d62728" : "#1f77b4";
        if (path.as_cells()) d.dots(path.cells(), colour);
        else if (actual) d.polyline(path.points(), colour, 1.5, "stroke-dasharray=\"4 3\"");
        else d.polyline(path.points(), colour, 1.5);
    }
    // Start, direction (an arrow 40 pixels along the commanded path) and end, from the samples
    // themselves (a long run's path may be drawn as cells).
    bool first = true;
    for (const auto& smp : v) {
        if (!has_axis(smp, std::max(ax, ay))) continue;
        const svg::Point p{sx(double(smp.cmd[ax])), sy(double(smp.cmd[ay]))};
        if (first) start = end = p, first = false;
        const double seg = std::hypot(p.x - end.x, p.y - end.y);
        if (!have_arrow && seg > 0 && travelled + seg >= 40) {
            const double f = (40 - travelled) / seg;
            arrow_at = {end.x + f * (p.x - end.x), end.y + f * (p.y - end.y)};
            arrow_from = end, have_arrow = true;
        }
        travelled += seg;
        end = p;
    }
    if (any) {
        d.marker(start.x, start.y, svg::Marker::circle, "#2ca02c", 9);
        d.text(start.x + 8, start.y - 8, "start", "start", 11);
        if (have_arrow) d.arrow(arrow_at, arrow_at.x - arrow_from.x, arrow_at.y - arrow_from.y, "#1f77b4", 12);
        d.marker(end.x, end.y, svg::Marker::square, "#333", 6);
    }
    d.legend(M + 10, top + 15, {{"commanded (CAMC-QI CNT1)", "#1f77b4"}, {"actual (drive 0x6064)", "#d62728", "4 3"}});

    // The following error: what separates the two paths.
    if (!v.empty()) {
        const double t0 = v.front().t_s, t1 = std::max(v.back().t_s, t0 + 1e-6);
        std::vector<Series> fe;
        for (const unsigned a : {ax, ay})
            fe.push_back({"axis " + std::to_string(a), kAxisColour[a % kAxes], "",
                          [a](const TrajectorySample& s, const TrajectorySample*) -> std::optional<double> {
                              if (!has_axis(s, a)) return std::nullopt;
                              return double(s.cmd[a] - s.act[a]);
                          }});
        d.text(M, fe_top - 12, "following error (command - actual)", "start", 12);
        time_panel(d, v, M, fe_top, P, fe_h, "[pulses]", fe, t0, t1);
    }
    return d.str();
}

void write_trajectory_svg(const motion::TrajectoryRecorder& rec, const std::filesystem::path& file, unsigned ax,
                          unsigned ay, const std::string& title) {
    write_file(file, trajectory_svg(rec, ax, ay, title));
}

std::string trajectory_time_svg(const motion::TrajectoryRecorder& rec, const std::string& title,
                                const std::optional<CircleOverlay>& circle) {
    const std::vector<TrajectorySample> v = rec.plot_samples();
    const double W = 900, M = 80, PW = 640, PH = 170, gap = 80, top = 60;
    const unsigned panels = circle ? 5 : 4;
    const double H = top + panels * (PH + gap) + 10;
    svg::Doc d(W, H, title);
    d.rect(0, 0, W, H, "white");
    d.title(title);
    if (v.empty()) {
        d.text(W / 2, top + 40, "no trajectory sample", "middle");
        return d.str();
    }
    const double t0 = v.front().t_s, t1 = std::max(v.back().t_s, t0 + 1e-6);
    const std::vector<unsigned> axes = moving_axes(v);
    std::vector<Series> pos, vel, fe;
    for (const unsigned a : axes) {
        const std::string n = "axis " + std::to_string(a);
        const char* c = kAxisColour[a % kAxes];
        for (const bool act : {false, true}) {
            pos.push_back({n + (act ? " actual" : " command"), c, act ? "4 3" : "",
                           [a, act](const TrajectorySample& s, const TrajectorySample*) -> std::optional<double> {
                               if (!has_axis(s, a)) return std::nullopt;
                               return double(act ? s.act[a] : s.cmd[a]);
                           }});
            vel.push_back({n + (act ? " actual" : " command"), c, act ? "4 3" : "",
                           [a, act](const TrajectorySample& s, const TrajectorySample*) { return velocity(s, a, act); }});
        }
        fe.push_back({n, c, "", [a](const TrajectorySample& s, const TrajectorySample*) -> std::optional<double> {
                          if (!has_axis(s, a)) return std::nullopt;
                          return double(s.cmd[a] - s.act[a]);
                      }});
    }
    double y = top;
    auto heading = [&](const std::string& s) { d.text(M, y - 10, s, "start", 13); };
    heading("position");
    time_panel(d, v, M, y, PW, PH, "[pulses]", pos, t0, t1);
    y += PH + gap;
    heading("velocity (from one control cycle to the next)");
    time_panel(d, v, M, y, PW, PH, "[pulses/s]", vel, t0, t1);
    y += PH + gap;
    // The speed along the X-Y path (axes 0 and 1): what PLCopen's Velocity of an interpolated
    // move commands, which neither axis' velocity shows alone.
    heading("path speed of axes 0/1: sqrt(vx^2 + vy^2), from one control cycle to the next");
    std::vector<Series> path;
    for (const bool act : {false, true})
        path.push_back({act ? "actual" : "command", act ? "#d62728" : "#1f77b4", act ? "4 3" : "",
                        [act](const TrajectorySample& s, const TrajectorySample*) -> std::optional<double> {
                            const auto vx = velocity(s, 0, act), vy = velocity(s, 1, act);
                            if (!vx || !vy) return std::nullopt;
                            return std::hypot(*vx, *vy);
                        }});
    time_panel(d, v, M, y, PW, PH, "[pulses/s]", path, t0, t1);
    y += PH + gap;
    heading("following error (command - actual)");
    time_panel(d, v, M, y, PW, PH, "[pulses]", fe, t0, t1);
    if (circle) {
        y += PH + gap;
        const CircleOverlay c = *circle;
        heading("radial error: distance from the centre - radius, over the circle command");
        std::vector<Series> rad;
        for (const bool act : {false, true})
            rad.push_back({act ? "actual" : "command", act ? "#d62728" : "#1f77b4", act ? "4 3" : "",
                           [c, act](const TrajectorySample& s, const TrajectorySample*) -> std::optional<double> {
                               if (!has_axis(s, 1) || s.t_s < c.t0_s - 1e-12 || s.t_s > c.t1_s + 1e-12)
                                   return std::nullopt;
                               const auto& p = act ? s.act : s.cmd;
                               return std::hypot(double(p[0]) - c.center_x, double(p[1]) - c.center_y) - c.radius;
                           }});
        time_panel(d, v, M, y, PW, PH, "[pulses]", rad, t0, t1);
    }
    return d.str();
}

TrajectoryFiles::TrajectoryFiles(motion::TrajectoryRecorder& rec, const std::filesystem::path& dir,
                                 const TrajectoryOptions& opt)
    : rec_(rec), dir_(dir), csv_(std::make_shared<TrajectoryCsv>(dir / "trajectory.csv", opt.csv_every)) {
    rec_.on_sample([csv = csv_](const TrajectorySample& s) { csv->add(s); });
}

void TrajectoryFiles::finish(const std::string& title, const std::optional<CircleOverlay>& circle,
                             const std::vector<camc::PulseEvent>* pulses) {
    csv_->close();
    write_trajectory_svg(rec_, dir_ / "trajectory.svg", 0, 1, title);
    write_file(dir_ / "trajectory_time.svg", trajectory_time_svg(rec_, title, circle));
    if (pulses) write_pulse_csv(*pulses, dir_ / "trajectory_pulses.csv");
}

} // namespace rcsim
