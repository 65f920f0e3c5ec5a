// trajectory.csv and trajectory.svg from a hand-made recording (scenarios/report/trajectory_report.h).
#include "tests/support/files.h"
#include "models/plumbing/config_error.h"
#include "scenarios/report/trajectory_report.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <optional>
#include <set>

using namespace rcsim;

namespace {

using rcsim::test::slurp;

/// An L-shaped path on axes 0 and 1: (0,0) -> (1000,0) -> (1000,1000); the actual position lags
/// one sample behind. Axis 2 stays at 7.
void l_path_into(motion::TrajectoryRecorder& r);
motion::TrajectoryRecorder l_path() {
    motion::TrajectoryRecorder r;
    l_path_into(r);
    return r;
}

/// trajectory.csv streamed from `rec`'s samples as they are added by `record`.
void write_csv(const std::filesystem::path& file, std::size_t every,
               const std::function<void(motion::TrajectoryRecorder&)>& record) {
    motion::TrajectoryRecorder r;
    TrajectoryCsv csv(file, every);
    r.on_sample([&csv](const motion::TrajectorySample& s) { csv.add(s); });
    record(r);
    csv.close();
}

void l_path_into(motion::TrajectoryRecorder& r) {
    r.add(0.0, {0, 0, 7}, {0, 0, 7});
    r.add(0.001, {1000, 0, 7}, {0, 0, 7});
    r.add(0.0025, {1000, 1000, 7}, {1000, 0, 7});
}

TEST(TrajectoryReport, CsvHasOneRowPerAxisPerSample) {
    const auto file = rcsim::test::scratch_dir() / "trajectory.csv";
    write_csv(file, 1, l_path_into);
    EXPECT_EQ(slurp(file), "t_s,axis,cmd_pulses,act_pulses\n"
                           "0.000000,0,0,0\n0.000000,1,0,0\n0.000000,2,7,7\n"
                           "0.001000,0,1000,0\n0.001000,1,0,0\n0.001000,2,7,7\n"
                           "0.002500,0,1000,1000\n0.002500,1,1000,0\n0.002500,2,7,7\n");
}

TEST(TrajectoryReport, SvgDrawsBothPathsOnEqualScalesWithNiceBounds) {
    const std::string s = trajectory_svg(l_path(), 0, 1, "run <1>");
    // Both axes span 0..1000, widened by 5 % of it on every side so that no move lies on the
    // frame: nice_range(-50, 1050, 8) has step 200 and bounds [-200, 1200], mapped onto the
    // 500-pixel square at (70, 60): x = 70 + (v + 200) / 2.8, y = 560 - (v + 200) / 2.8, so 0 is
    // at 141.4 / 488.6 and 1000 at 498.6 / 131.4, inside the frame (70..570, 60..560).
    EXPECT_NE(s.find("stroke=\"#1f77b4\" stroke-width=\"1.5\" points=\"141.4,488.6 498.6,488.6 498.6,131.4\""),
              std::string::npos)
        << s;
    // The actual path repeats its first point: the decimator merges it.
    EXPECT_NE(s.find("stroke=\"#d62728\" stroke-width=\"1.5\" stroke-dasharray=\"4 3\" "
                     "points=\"141.4,488.6 498.6,488.6\""),
              std::string::npos)
        << s;
    EXPECT_NE(s.find(">run &lt;1&gt;</text>"), std::string::npos) << "the title is escaped";
    EXPECT_NE(s.find("axis 0 position [pulses]"), std::string::npos);
    EXPECT_NE(s.find("axis 1 position [pulses]"), std::string::npos);
    EXPECT_NE(s.find(">commanded (CAMC-QI CNT1)</text>"), std::string::npos);
    EXPECT_NE(s.find(">actual (drive 0x6064)</text>"), std::string::npos);
    // Ticks every 200 pulses, the axis starting and ending on one: -200 at x 70, 1200 at x 570.
    EXPECT_NE(s.find("<text x=\"70.0\" y=\"576.0\" text-anchor=\"middle\" font-size=\"11.0\">-200</text>"),
              std::string::npos);
    EXPECT_NE(s.find("<text x=\"570.0\" y=\"576.0\" text-anchor=\"middle\" font-size=\"11.0\">1200</text>"),
              std::string::npos);
    // Start mark on the first point, an arrow 40 pixels along the path pointing +x (tip at
    // x 181.4, base 12 back, half-width 5.4), an end mark on (1000, 1000).
    EXPECT_NE(s.find("<circle cx=\"141.4\" cy=\"488.6\" r=\"4.5\" fill=\"#2ca02c\"/>"), std::string::npos) << s;
    EXPECT_NE(s.find("<polygon fill=\"#1f77b4\" points=\"181.4,488.6 169.4,494.0 169.4,483.2\"/>"), std::string::npos) << s;
    EXPECT_NE(s.find("<rect x=\"495.6\" y=\"128.4\" width=\"6.0\" height=\"6.0\" fill=\"#333\"/>"), std::string::npos) << s;
    EXPECT_NE(s.find("following error (command - actual)"), std::string::npos);
}

TEST(TrajectoryReport, SvgOfOtherAxesUsesThem) {
    // Axis 2 never moves: axis 0's span (1400, step 200, as above) around axis 2's value 7 on
    // multiples of the step: floor((7 - 700) / 200 + 0.5) = -3, so [-600, 800];
    // y(7) = 560 - 607 / 2.8 = 343.2.
    const std::string s = trajectory_svg(l_path(), 0, 2, "t");
    EXPECT_NE(s.find("axis 2 position [pulses]"), std::string::npos);
    EXPECT_NE(s.find("points=\"141.4,343.2 498.6,343.2\""), std::string::npos) << s;
}

TEST(TrajectoryReport, CsvEveryNthSampleAndTheLast) {
    const auto file = rcsim::test::scratch_dir() / "trajectory_every.csv";
    write_csv(file, 4, [](motion::TrajectoryRecorder& r) {
        for (int i = 0; i < 10; ++i) r.add(i * 0.001, {i}, {i});
    });
    EXPECT_EQ(slurp(file), "t_s,axis,cmd_pulses,act_pulses\n0.000000,0,0,0\n0.004000,0,4,4\n0.008000,0,8,8\n"
                           "0.009000,0,9,9\n");
}

TEST(TrajectoryReport, PulseCsvHasExactTimes) {
    const auto file = rcsim::test::scratch_dir() / "trajectory_pulses.csv";
    write_pulse_csv({{sc_core::sc_time(1234567, sc_core::SC_PS), 1, -1}, {sc_core::sc_time(2, sc_core::SC_MS), 0, 1}},
                    file);
    EXPECT_EQ(slurp(file), "t_s,axis,dir\n0.000001234567,1,-1\n0.002000000000,0,1\n");
}

TEST(TrajectoryReport, TimePlotHasItsPanels) {
    const std::string plain = trajectory_time_svg(l_path(), "name", std::nullopt);
    EXPECT_NE(plain.find(">name</text>"), std::string::npos);
    for (const char* panel : {">position</text>", ">velocity (from one control cycle to the next)</text>",
                              ">following error (command - actual)</text>", ">time [s]</text>",
                              ">path speed of axes 0/1: sqrt(vx^2 + vy^2), each the least-squares slope over 10 ms</text>"})
        EXPECT_NE(plain.find(panel), std::string::npos) << panel;
    EXPECT_EQ(plain.find("radial error"), std::string::npos) << "no circle, no radial panel";
    // Axes 0 and 1 moved, axis 2 did not: no series for it.
    EXPECT_NE(plain.find(">axis 1 command</text>"), std::string::npos);
    EXPECT_EQ(plain.find(">axis 2 command</text>"), std::string::npos);
    const std::string circ = trajectory_time_svg(l_path(), "name", CircleOverlay{0, 0, 1000, 0, 1});
    EXPECT_NE(circ.find("radial error"), std::string::npos);
}

TEST(TrajectoryReport, UnwritableFileIsNamed) {
    const auto dir = rcsim::test::scratch_dir() / "no_such_dir" / "x";
    try {
        write_trajectory_svg(l_path(), dir / "trajectory.svg", 0, 1, "t");
        FAIL() << "no error";
    } catch (const ConfigError& e) { // bad input (exit 2), naming the file
        // With the system's reason (models/plumbing/output_file.h): the folder does not exist.
        EXPECT_EQ(std::string(e.what()),
                  (dir / "trajectory.svg").string() + ": cannot write the file: " + std::strerror(ENOENT));
    }
    EXPECT_THROW(write_csv(dir / "trajectory.csv", 1, l_path_into), ConfigError);
    // A full disk: the open succeeds, the write fails.
    EXPECT_THROW(write_csv("/dev/full", 1, l_path_into), ConfigError);
}

} // namespace

// The path-speed panel on a straight line at 3000 pulses/s in X and 4000 in Y: a path speed of
// 5000 pulses/s (3-4-5) at every sample with a whole window around it, whatever the rounding of
// the positions; the panel draws it there, its value axis labelled in pulses/s.
TEST(TrajectoryReport, PathSpeedOfAStraightLineIsItsSpeed) {
    motion::TrajectoryRecorder r;
    for (int k = 0; k <= 1000; ++k) r.add(k * 0.001, {std::llround(3000.0 * k / 1000), std::llround(4000.0 * k / 1000)}, {0, 0});
    const auto v = r.plot_samples();
    const double w = path_speed_window_s(v); // 1000 / 5000 = 200 ms
    EXPECT_NEAR(w, 0.200, 1e-12);
    const auto speed = path_speed(v, false, w);
    EXPECT_EQ(speed.size(), 801u); // 0.1 s .. 0.9 s
    for (const auto& [t, s] : speed) EXPECT_NEAR(s, 5000, 1) << t;
    const std::string s = trajectory_time_svg(r, "name", std::nullopt);
    const std::size_t at = s.find(">path speed of axes 0/1");
    ASSERT_NE(at, std::string::npos);
    const std::string panel = s.substr(at, s.find(">following error (command - actual)</text>", at) - at);
    // The value axis' nice range is 0..6000 over the panel's 170 pixels (y 730 to 560): 5000 at
    // y = 730 - 170 * 5 / 6 = 588.3, where the command's line runs from t = 0.1 s (x = 80 + 640 * 0.1).
    EXPECT_NE(panel.find(">6000</text>"), std::string::npos);
    EXPECT_NE(panel.find("stroke=\"#1f77b4\" stroke-width=\"1.2\" points=\"144.0,588.3 "), std::string::npos);
    EXPECT_NE(panel.find("[pulses/s]"), std::string::npos);
}


namespace {

/// A circle of radius 5000 pulses about (-5000, 0), sampled every 1 ms for 1 s, whose path speed
/// is 20 000 pulses/s with a ripple of +-0.3 % (period 250 ms): positions rounded to whole pulses,
/// as the chip's counters are. The actual path is the command 2 ms late.
motion::TrajectoryRecorder rippled_circle() {
    motion::TrajectoryRecorder r;
    const double R = 5000, v = 20000, a = 0.003, T = 0.25, pi = std::acos(-1.0);
    auto angle = [&](double t) { return (v * t - a * v * T / (2 * pi) * (std::cos(2 * pi * t / T) - 1)) / R; };
    auto at = [&](double t) {
        const double th = angle(std::max(t, 0.0));
        return std::vector<std::int64_t>{std::llround(-R + R * std::cos(th)), std::llround(R * std::sin(th))};
    };
    for (int k = 0; k <= 1000; ++k) r.add(k * 0.001, at(k * 0.001), at(k * 0.001 - 0.002));
    return r;
}

// The path speed is measured over a window (issue #49 item 8): the window covers 1000 pulses at
// the top speed, 50 ms at 20 000 pulses/s. Over it the +-0.3 % ripple (+-60 pulses/s) shows as
// +-57.7: a least-squares slope over +-h of a sine of angular frequency W keeps
// 3 (sin x - x cos x) / x^3 of it, x = W h = 2 pi / 0.25 s * 25 ms, 0.961. The tolerance, 10
// pulses/s, is 3.5 sigma of the slope's quantisation noise (0.29 pulse / sqrt(sum t^2), 51
// samples: 2.8). Differences from one 1 ms sample to the next, 20 pulses each, swing by a
// pulse: +-5 %.
TEST(TrajectoryReport, PathSpeedOverItsWindowShowsTheRealRipple) {
    const auto v = rippled_circle().plot_samples();
    const double w = path_speed_window_s(v);
    EXPECT_DOUBLE_EQ(w, 0.050);
    const auto speed = path_speed(v, false, w);
    ASSERT_GT(speed.size(), 900u);
    double lo = 1e9, hi = 0;
    for (const auto& [t, s] : speed) lo = std::min(lo, s), hi = std::max(hi, s);
    EXPECT_NEAR(hi, 20057.7, 10);
    EXPECT_NEAR(lo, 19942.3, 10);
    // What one-cycle differences make of the same path.
    double dlo = 1e9, dhi = 0;
    for (std::size_t k = 1; k < v.size(); ++k) {
        const double d = std::hypot(double(v[k].cmd[0] - v[k - 1].cmd[0]), double(v[k].cmd[1] - v[k - 1].cmd[1])) /
                         (v[k].t_s - v[k - 1].t_s);
        dlo = std::min(dlo, d), dhi = std::max(dhi, d);
    }
    EXPECT_GT(dhi - dlo, 0.05 * 20000);
    const std::string svg = trajectory_time_svg(rippled_circle(), "c", std::nullopt);
    EXPECT_NE(svg.find(">path speed of axes 0/1: sqrt(vx^2 + vy^2), each the least-squares slope over 50 ms</text>"),
              std::string::npos);
}

// The window: 1000 pulses at the top speed, rounded up to 10 ms, from 10 ms to 200 ms.
TEST(TrajectoryReport, PathSpeedWindowFollowsTheTopSpeed) {
    auto line = [](double v) {
        motion::TrajectoryRecorder r;
        for (int k = 0; k <= 300; ++k) r.add(k * 0.001, {std::llround(v * k * 0.001), 0}, {0, 0});
        return path_speed_window_s(r.plot_samples());
    };
    EXPECT_NEAR(line(8000), 0.130, 1e-12);   // 1000 / 8000 = 125 ms
    EXPECT_NEAR(line(100000), 0.010, 1e-12); // 10 ms
    EXPECT_NEAR(line(50000), 0.020, 1e-12);  // 20 ms exactly
    EXPECT_NEAR(line(1000), 0.200, 1e-12);   // 1 s, cut to the most
}

// The radial-error panel draws the circle check's tolerance, +-max_radial_error, across it.
TEST(TrajectoryReport, RadialErrorPanelDrawsTheTolerance) {
    CircleOverlay c{-5000, 0, 5000, 0, 1};
    c.max_radial_error = 1.5;
    const std::string s = trajectory_time_svg(rippled_circle(), "c", c);
    const std::size_t at = s.find(">radial error: distance from the centre - radius");
    ASSERT_NE(at, std::string::npos);
    const std::string panel = s.substr(at);
    EXPECT_NE(panel.find(">max_radial_error ±1.5</text>"), std::string::npos);
    std::size_t lines = 0;
    const std::string across = "x1=\"80.0\"", dotted = "stroke=\"#555\" stroke-width=\"1.0\" stroke-dasharray=\"1 3\"";
    for (std::size_t p = panel.find(dotted); p != std::string::npos; p = panel.find(dotted, p + 1))
        if (panel.rfind("<line " + across, p) == panel.rfind("<line ", p)) ++lines; // from the panel's left edge
    EXPECT_EQ(lines, 2u); // +1.5 and -1.5 across the panel
    // The value axis reaches both lines: its nice range covers -1.5 .. 1.5.
    EXPECT_NE(panel.find(">-2</text>"), std::string::npos);
    EXPECT_NE(panel.find(">2</text>"), std::string::npos);
    c.max_radial_error = -1;
    EXPECT_EQ(trajectory_time_svg(rippled_circle(), "c", c).find("max_radial_error"), std::string::npos);
}

// A mark (the first missed CSP SYNC) is a vertical line across each of the five panels at its
// time, labelled once over the first; a mark outside the samples' time is not drawn.
TEST(TrajectoryReport, TimePlotMarksAnInstantAcrossEveryPanel) {
    const CircleOverlay c{-5000, 0, 5000, 0, 1};
    const std::string label = "CSP: SYNC missed (first of 2)";
    const std::string s = trajectory_time_svg(rippled_circle(), "c", c, {{0.25, label}});
    const std::string stroke = "stroke=\"#d62728\" stroke-width=\"1.0\" stroke-dasharray=\"4 2\"";
    std::size_t lines = 0;
    std::set<std::string> x;
    for (std::size_t p = s.find(stroke); p != std::string::npos; p = s.find(stroke, p + 1)) {
        const std::size_t open = s.rfind("<line ", p);
        const std::string tag = s.substr(open, p - open);
        const std::size_t x1 = tag.find("x1=\""), x2 = tag.find("x2=\"");
        ASSERT_NE(x1, std::string::npos);
        ASSERT_NE(x2, std::string::npos);
        const std::string a = tag.substr(x1 + 4, tag.find('"', x1 + 4) - x1 - 4);
        EXPECT_EQ(a, tag.substr(x2 + 4, tag.find('"', x2 + 4) - x2 - 4)); // vertical
        x.insert(a);
        ++lines;
    }
    EXPECT_EQ(lines, 5u); // position, velocity, path speed, following error, radial error
    EXPECT_EQ(x.size(), 1u); // at one time on every panel
    std::size_t labels = 0;
    for (std::size_t p = s.find(">" + label + "</text>"); p != std::string::npos; p = s.find(">" + label + "</text>", p + 1))
        ++labels;
    EXPECT_EQ(labels, 1u);
    EXPECT_EQ(trajectory_time_svg(rippled_circle(), "c", c, {{99.0, label}}).find(label), std::string::npos);
}

} // namespace
