// rcsim — trajectory.csv and trajectory.svg. See trajectory_report.h.
#include "scenarios/trajectory_report.h"

#include "models/config_error.h"
#include "scenarios/svg.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace rcsim {

namespace {

std::ofstream open_out(const std::filesystem::path& file) {
    std::ofstream out(file);
    if (!out) throw ConfigError(file.string(), 0, "cannot write the file");
    return out;
}

void close_out(std::ofstream& out, const std::filesystem::path& file) {
    out.close();
    if (!out) throw ConfigError(file.string(), 0, "cannot write the file (disk full?)");
}

bool has_axes(const motion::TrajectorySample& s, unsigned ax, unsigned ay) {
    return s.cmd.size() > std::max(ax, ay) && s.act.size() > std::max(ax, ay);
}

} // namespace

void write_trajectory_csv(const motion::TrajectoryRecorder& rec, const std::filesystem::path& file) {
    std::ofstream out = open_out(file);
    out << "t_s,axis,cmd_pulses,act_pulses\n";
    char t[32];
    for (const auto& s : rec.samples()) {
        std::snprintf(t, sizeof t, "%.6f", s.t_s);
        for (std::size_t a = 0; a < s.cmd.size() && a < s.act.size(); ++a)
            out << t << ',' << a << ',' << s.cmd[a] << ',' << s.act[a] << '\n';
    }
    close_out(out, file);
}

std::string trajectory_svg(const motion::TrajectoryRecorder& rec, unsigned ax, unsigned ay, const std::string& title) {
    // The bounding box of both paths (a unit box when nothing was recorded).
    double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
    bool any = false;
    for (const auto& s : rec.samples()) {
        if (!has_axes(s, ax, ay)) continue;
        for (const auto* v : {&s.cmd, &s.act}) {
            const double x = static_cast<double>((*v)[ax]), y = static_cast<double>((*v)[ay]);
            if (!any) x0 = x1 = x, y0 = y1 = y, any = true;
            x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        }
    }
    // Equal scales on both axes, the larger extent plus a 10 % margin, centred.
    const double span = std::max({x1 - x0, y1 - y0, 1.0}) * 1.1;
    const double cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
    const double W = 640, H = 680, M = 70, P = W - 2 * M; // plot area P x P at (M, M)
    const svg::Scale sx{cx - span / 2, cx + span / 2, M, M + P, false};
    const svg::Scale sy{cy - span / 2, cy + span / 2, M + P, M, false};

    svg::Doc d(W, H, title);
    d.rect(0, 0, W, H, "white");
    d.title(title);
    d.y_axis(sy, M, M + P, "axis " + std::to_string(ay) + " position [pulses]", 8);
    d.x_axis(sx, M + P, "axis " + std::to_string(ax) + " position [pulses]", 8);
    d.frame(M, M, P, P);
    for (const bool actual : {false, true}) {
        std::vector<svg::Point> pts;
        pts.reserve(rec.samples().size());
        for (const auto& s : rec.samples()) {
            if (!has_axes(s, ax, ay)) continue;
            const auto& v = actual ? s.act : s.cmd;
            pts.push_back({sx(static_cast<double>(v[ax])), sy(static_cast<double>(v[ay]))});
        }
        if (actual) d.polyline(pts, "#d62728", 1.5, "stroke-dasharray=\"4 3\"");
        else d.polyline(pts, "#1f77b4", 1.5);
    }
    d.legend(M + 10, M + 15, {{"commanded (CAMC-QI CNT1)", "#1f77b4"}, {"actual (drive 0x6064)", "#d62728", "4 3"}});
    return d.str();
}

void write_trajectory_svg(const motion::TrajectoryRecorder& rec, const std::filesystem::path& file, unsigned ax,
                          unsigned ay, const std::string& title) {
    std::ofstream out = open_out(file);
    out << trajectory_svg(rec, ax, ay, title);
    close_out(out, file);
}

} // namespace rcsim
