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
#include <memory>

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

const char* const kMarkColour = "#d62728";

/// One series of a time panel: `value(sample, previous)` (nullopt: no point), its colour, dash.
struct Series {
    std::string label, colour, dash;
    std::function<std::optional<double>(const TrajectorySample&, const TrajectorySample*)> value;
};

/// A horizontal line across a panel at `value` (a limit), in the legend as `label`.
struct Level {
    double value;
    std::string label, colour;
};

/// A panel of series against time at (x, y), w x h pixels, decimated to its pixel columns; the
/// levels drawn across it (dotted) and kept inside its value range.
void time_panel(svg::Doc& d, const std::vector<TrajectorySample>& v, double x, double y, double w, double h,
                const std::string& y_title, const std::vector<Series>& series, double t0, double t1,
                const std::vector<Level>& levels = {}, const std::vector<TimeMark>& marks = {},
                bool label_marks = false) {
    std::vector<std::vector<std::pair<double, double>>> pts;
    double lo = 0, hi = 0;
    bool any = false;
    for (const Level& l : levels) {
        if (!any) lo = hi = l.value, any = true;
        lo = std::min(lo, l.value), hi = std::max(hi, l.value);
    }
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
    for (std::size_t i = 0; i < levels.size(); ++i) {
        d.line(x, sy(levels[i].value), x + w, sy(levels[i].value), levels[i].colour, 1, "stroke-dasharray=\"1 3\"");
        if (i == 0 || levels[i].label != levels[i - 1].label) legend.push_back({levels[i].label, levels[i].colour, "1 3"});
    }
    for (const TimeMark& m : marks) {
        if (m.t_s < t0 || m.t_s > t1) continue;
        d.line(sx(m.t_s), y, sx(m.t_s), y + h, kMarkColour, 1, "stroke-dasharray=\"4 2\"");
        if (label_marks) d.text(sx(m.t_s), y - 24, m.label, "middle", 11, "fill=\"" + std::string(kMarkColour) + "\"");
    }
    // The legend to the right of the panel, one row per series.
    d.legend(x + w + 12, y + 10, legend, 16);
}

/// The velocity the recorder kept with `s` (since its control cycle's previous sample).
std::optional<double> velocity(const TrajectorySample& s, unsigned a, bool actual) {
    if (!s.has_velocity || a >= s.vel_cmd.size() || !has_axis(s, a)) return std::nullopt;
    return actual ? s.vel_act[a] : s.vel_cmd[a];
}

/// Solves the 3 x 3 normal equations m (a b c) = r by Cramer's rule for b and c; false when singular.
bool solve3(const double m[3][3], const double r[3], double& b, double& c) {
    auto det = [](double a0, double a1, double a2, double b0, double b1, double b2, double c0, double c1, double c2) {
        return a0 * (b1 * c2 - b2 * c1) - a1 * (b0 * c2 - b2 * c0) + a2 * (b0 * c1 - b1 * c0);
    };
    const double d = det(m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2]);
    if (!(std::abs(d) > 0)) return false;
    b = det(m[0][0], r[0], m[0][2], m[1][0], r[1], m[1][2], m[2][0], r[2], m[2][2]) / d;
    c = det(m[0][0], m[0][1], r[0], m[1][0], m[1][1], r[1], m[2][0], m[2][1], r[2]) / d;
    return true;
}

} // namespace

double path_speed_window_s(const std::vector<TrajectorySample>& v) {
    double peak = 0;
    for (const auto& s : v)
        if (const auto vx = velocity(s, 0, false), vy = velocity(s, 1, false); vx && vy)
            peak = std::max(peak, std::hypot(*vx, *vy));
    if (!(peak > 0)) return kPathSpeedWindowMin;
    // In steps of 10 ms, so that the speed's own few per cent of ripple between one-cycle
    // differences does not change the window of a run.
    const double w = std::ceil(kPathSpeedWindowPulses / peak / 0.010 - 1e-9) * 0.010;
    return std::clamp(w, kPathSpeedWindowMin, kPathSpeedWindowMax);
}

std::vector<std::pair<double, double>> path_speed(const std::vector<TrajectorySample>& v, bool actual,
                                                  double window_s) {
    // Each axis' least-squares slope over the samples within h = window_s / 2 of the sample's
    // time: the quantisation (+-0.5 pulse a sample) weighs 1/N^1.5 in a slope of N samples, where
    // a difference of two samples carries it whole. On a curve the slopes shrink by
    // 1 - (w h)^2 / 10 (w the velocity's turning rate, a_normal / v); the quadratic terms of the
    // same fit give a_normal, so that is divided out: a circle's speed is not drawn 0.1 % low.
    std::vector<std::pair<double, double>> out;
    const double eps = 1e-9, half = window_s / 2 + eps; // sample times are sums of the cycle
    std::size_t first = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
        const double t = v[i].t_s;
        if (!has_axis(v[i], 1) || t - half + 2 * eps < v.front().t_s || t + half - 2 * eps > v.back().t_s) continue;
        while (v[first].t_s < t - half) ++first;
        // Least squares of x = a + b t + c t^2 (t centred on the sample): the normal equations.
        double m[3][3] = {}, rx[3] = {}, ry[3] = {};
        std::size_t n = 0;
        const auto& p0 = actual ? v[i].act : v[i].cmd;
        for (std::size_t k = first; k < v.size() && v[k].t_s <= t + half; ++k) {
            if (!has_axis(v[k], 1)) continue;
            const double dt = v[k].t_s - t, pw[3] = {1, dt, dt * dt};
            const auto& p = actual ? v[k].act : v[k].cmd;
            const double px = double(p[0] - p0[0]), py = double(p[1] - p0[1]);
            for (int r = 0; r < 3; ++r) {
                for (int c = 0; c < 3; ++c) m[r][c] += pw[r] * pw[c];
                rx[r] += pw[r] * px, ry[r] += pw[r] * py;
            }
            ++n;
        }
        double bx = 0, cx = 0, by = 0, cy = 0;
        if (n < 4 || !solve3(m, rx, bx, cx) || !solve3(m, ry, by, cy)) continue;
        const double speed = std::hypot(bx, by);
        double shrink = 1;
        if (speed > 0) {
            const double a_normal = std::abs(bx * 2 * cy - by * 2 * cx) / speed, turn = a_normal / speed;
            shrink = 1 - turn * turn * (window_s / 2) * (window_s / 2) / 10;
        }
        out.emplace_back(t, speed / std::max(shrink, 0.5));
    }
    return out;
}

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
                                const std::optional<CircleOverlay>& circle, const std::vector<TimeMark>& marks) {
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
    time_panel(d, v, M, y, PW, PH, "[pulses]", pos, t0, t1, {}, marks, true);
    y += PH + gap;
    heading("velocity (from one control cycle to the next)");
    time_panel(d, v, M, y, PW, PH, "[pulses/s]", vel, t0, t1, {}, marks);
    y += PH + gap;
    // The speed along the X-Y path (axes 0 and 1): what PLCopen's Velocity of an interpolated
    // move commands, which neither axis' velocity shows alone.
    // Over a window, not from one cycle to the next: at 20 000 pulses/s a cycle moves 20 pulses,
    // and one pulse of quantisation would show as 5 % of ripple (docs/motion.md).
    const double window = path_speed_window_s(v);
    char wtext[32];
    std::snprintf(wtext, sizeof wtext, "%.0f ms", window * 1000);
    heading(std::string("path speed of axes 0/1: sqrt(vx^2 + vy^2), each the least-squares slope over ") + wtext);
    std::vector<Series> path;
    for (const bool act : {false, true}) {
        // Looked up by time: the panel hands the samples in order, the speeds follow them.
        auto speeds = std::make_shared<std::vector<std::pair<double, double>>>(path_speed(v, act, window));
        auto at = std::make_shared<std::size_t>(0);
        path.push_back({act ? "actual" : "command", act ? "#d62728" : "#1f77b4", act ? "4 3" : "",
                        [speeds, at](const TrajectorySample& s, const TrajectorySample* prev) -> std::optional<double> {
                            if (!prev) *at = 0;
                            while (*at < speeds->size() && (*speeds)[*at].first < s.t_s) ++*at;
                            if (*at < speeds->size() && (*speeds)[*at].first == s.t_s) return (*speeds)[*at].second;
                            return std::nullopt;
                        }});
    }
    time_panel(d, v, M, y, PW, PH, "[pulses/s]", path, t0, t1, {}, marks);
    y += PH + gap;
    heading("following error (command - actual)");
    time_panel(d, v, M, y, PW, PH, "[pulses]", fe, t0, t1, {}, marks);
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
        std::vector<Level> tol;
        if (c.max_radial_error >= 0) {
            char label[64];
            std::snprintf(label, sizeof label, "max_radial_error ±%g", c.max_radial_error); // fits the legend
            tol = {{c.max_radial_error, label, "#555"}, {-c.max_radial_error, label, "#555"}};
        }
        time_panel(d, v, M, y, PW, PH, "[pulses]", rad, t0, t1, tol, marks);
    }
    return d.str();
}

TrajectoryFiles::TrajectoryFiles(motion::TrajectoryRecorder& rec, const std::filesystem::path& dir,
                                 const TrajectoryOptions& opt)
    : rec_(rec), dir_(dir), csv_(std::make_shared<TrajectoryCsv>(dir / "trajectory.csv", opt.csv_every)) {
    rec_.on_sample([csv = csv_](const TrajectorySample& s) { csv->add(s); });
}

void TrajectoryFiles::finish(const std::string& title, const std::optional<CircleOverlay>& circle,
                             const std::vector<camc::PulseEvent>* pulses, const std::vector<TimeMark>& marks) {
    csv_->close();
    write_trajectory_svg(rec_, dir_ / "trajectory.svg", 0, 1, title);
    write_file(dir_ / "trajectory_time.svg", trajectory_time_svg(rec_, title, circle, marks));
    if (pulses) write_pulse_csv(*pulses, dir_ / "trajectory_pulses.csv");
}

} // namespace rcsim
