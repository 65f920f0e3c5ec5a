// rcsim — trajectory CSV and SVG writers. See trajectory.h.
#include "main_cpu/motion/trajectory.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rcsim::motion {

void TrajectoryRecorder::add(double t, std::vector<std::int64_t> cmd, std::vector<std::int64_t> act) {
    samples_.push_back({t, std::move(cmd), std::move(act)});
}

bool TrajectoryRecorder::moved() const {
    if (samples_.size() < 2) return false;
    for (const auto& s : samples_)
        if (s.cmd != samples_.front().cmd || s.act != samples_.front().act) return true;
    return false;
}

namespace {
std::ofstream open_out(const std::filesystem::path& file) {
    std::ofstream out(file);
    if (!out) throw std::runtime_error("cannot write " + file.string());
    return out;
}
} // namespace

void TrajectoryRecorder::write_csv(const std::filesystem::path& file) const {
    std::ofstream out = open_out(file);
    out << "t_s,axis,cmd_pulses,act_pulses\n";
    char t[32];
    for (const auto& s : samples_) {
        std::snprintf(t, sizeof t, "%.6f", s.t_s);
        for (std::size_t a = 0; a < s.cmd.size(); ++a) out << t << ',' << a << ',' << s.cmd[a] << ',' << s.act[a] << '\n';
    }
    if (!out) throw std::runtime_error("error writing " + file.string());
}

void TrajectoryRecorder::write_svg(const std::filesystem::path& file, unsigned ax, unsigned ay,
                                   const std::string& title) const {
    double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
    bool any = false;
    for (const auto& s : samples_) {
        if (s.cmd.size() <= std::max(ax, ay)) continue;
        for (const auto* v : {&s.cmd, &s.act}) {
            const double x = static_cast<double>((*v)[ax]), y = static_cast<double>((*v)[ay]);
            if (!any) { x0 = x1 = x; y0 = y1 = y; any = true; }
            x0 = std::min(x0, x); x1 = std::max(x1, x); y0 = std::min(y0, y); y1 = std::max(y1, y);
        }
    }
    // Equal scales on both axes (a circle must look round), with a margin.
    double span = std::max({x1 - x0, y1 - y0, 1.0}) * 1.1;
    const double cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
    x0 = cx - span / 2; y0 = cy - span / 2;
    const double W = 640, M = 70, P = W - 2 * M; // plot area P x P at (M, M)
    auto px = [&](double x) { return M + (x - x0) / span * P; };
    auto py = [&](double y) { return M + P - (y - y0) / span * P; };
    std::ofstream out = open_out(file);
    out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << W + 40
        << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
        << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
        << "<text x=\"" << W / 2 << "\" y=\"30\" text-anchor=\"middle\" font-size=\"16\">" << title << "</text>\n"
        << "<rect x=\"" << M << "\" y=\"" << M << "\" width=\"" << P << "\" height=\"" << P
        << "\" fill=\"none\" stroke=\"black\"/>\n";
    // Ticks: 5 divisions per axis with values.
    for (int i = 0; i <= 5; ++i) {
        const double v = span * i / 5;
        const double X = M + P * i / 5, Y = M + P - P * i / 5;
        out << "<line x1=\"" << X << "\" y1=\"" << M + P << "\" x2=\"" << X << "\" y2=\"" << M + P + 5
            << "\" stroke=\"black\"/><text x=\"" << X << "\" y=\"" << M + P + 18 << "\" text-anchor=\"middle\">"
            << std::llround(x0 + v) << "</text>\n"
            << "<line x1=\"" << M - 5 << "\" y1=\"" << Y << "\" x2=\"" << M << "\" y2=\"" << Y
            << "\" stroke=\"black\"/><text x=\"" << M - 8 << "\" y=\"" << Y + 4 << "\" text-anchor=\"end\">"
            << std::llround(y0 + v) << "</text>\n";
    }
    out << "<text x=\"" << W / 2 << "\" y=\"" << M + P + 40 << "\" text-anchor=\"middle\">axis " << ax
        << " position [pulses]</text>\n"
        << "<text transform=\"translate(16," << W / 2 << ") rotate(-90)\" text-anchor=\"middle\">axis " << ay
        << " position [pulses]</text>\n";
    auto path = [&](bool actual, const char* colour, const char* dash) {
        std::ostringstream pts;
        for (const auto& s : samples_) {
            if (s.cmd.size() <= std::max(ax, ay)) continue;
            const auto& v = actual ? s.act : s.cmd;
            pts << px(static_cast<double>(v[ax])) << ',' << py(static_cast<double>(v[ay])) << ' ';
        }
        out << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"1.5\" " << dash << "points=\""
            << pts.str() << "\"/>\n";
    };
    path(false, "#1f77b4", "");
    path(true, "#d62728", "stroke-dasharray=\"4 3\" ");
    // Legend.
    const double lx = M + 10, ly = M + 15;
    out << "<line x1=\"" << lx << "\" y1=\"" << ly << "\" x2=\"" << lx + 30 << "\" y2=\"" << ly
        << "\" stroke=\"#1f77b4\" stroke-width=\"2\"/><text x=\"" << lx + 36 << "\" y=\"" << ly + 4
        << "\">commanded (CAMC-QI CNT1)</text>\n"
        << "<line x1=\"" << lx << "\" y1=\"" << ly + 18 << "\" x2=\"" << lx + 30 << "\" y2=\"" << ly + 18
        << "\" stroke=\"#d62728\" stroke-width=\"2\" stroke-dasharray=\"4 3\"/><text x=\"" << lx + 36 << "\" y=\""
        << ly + 22 << "\">actual (drive 0x6064)</text>\n</svg>\n";
    if (!out) throw std::runtime_error("error writing " + file.string());
}

} // namespace rcsim::motion
