// trajectory.csv and trajectory.svg from a hand-made recording (scenarios/report/trajectory_report.h).
#include "tests/support/files.h"
#include "models/plumbing/config_error.h"
#include "scenarios/report/trajectory_report.h"

#include <gtest/gtest.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <optional>

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
                              ">path speed of axes 0/1: sqrt(vx^2 + vy^2), from one control cycle to the next</text>"})
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

// The path-speed panel: the L path's second leg moves 1000 pulses of Y in 1.5 ms, a path speed of
// 666 667 pulses/s, the first leg 1000 pulses of X in 1 ms (1 000 000): the panel's nice range
// reaches the larger one, and its value axis is labelled in pulses/s.
TEST(TrajectoryReport, PathSpeedPanelSpansTheLegsSpeeds) {
    const std::string s = trajectory_time_svg(l_path(), "name", std::nullopt);
    const std::size_t at = s.find(">path speed of axes 0/1");
    ASSERT_NE(at, std::string::npos);
    const std::size_t next = s.find(">following error (command - actual)</text>", at);
    const std::string panel = s.substr(at, next - at);
    EXPECT_NE(panel.find(">1000000</text>"), std::string::npos) << panel;
    EXPECT_NE(panel.find("[pulses/s]"), std::string::npos);
}

