// trajectory.csv and trajectory.svg from a hand-made recording (scenarios/trajectory_report.h).
#include "models/config_error.h"
#include "scenarios/trajectory_report.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace rcsim;

namespace {

std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

/// An L-shaped path on axes 0 and 1: (0,0) -> (1000,0) -> (1000,1000); the actual position lags
/// one sample behind. Axis 2 stays at 7.
motion::TrajectoryRecorder l_path() {
    motion::TrajectoryRecorder r;
    r.add(0.0, {0, 0, 7}, {0, 0, 7});
    r.add(0.001, {1000, 0, 7}, {0, 0, 7});
    r.add(0.0025, {1000, 1000, 7}, {1000, 0, 7});
    return r;
}

TEST(TrajectoryReport, CsvHasOneRowPerAxisPerSample) {
    const auto file = std::filesystem::temp_directory_path() / "rcsim_trajectory_test.csv";
    write_trajectory_csv(l_path(), file);
    EXPECT_EQ(slurp(file), "t_s,axis,cmd_pulses,act_pulses\n"
                           "0.000000,0,0,0\n0.000000,1,0,0\n0.000000,2,7,7\n"
                           "0.001000,0,1000,0\n0.001000,1,0,0\n0.001000,2,7,7\n"
                           "0.002500,0,1000,1000\n0.002500,1,1000,0\n0.002500,2,7,7\n");
}

TEST(TrajectoryReport, SvgDrawsBothPathsOnEqualScales) {
    const std::string s = trajectory_svg(l_path(), 0, 1, "run <1>");
    // Both axes span 0..1000; plus 10 % the plotted range is -50..1050 on both, mapped onto the
    // 500-pixel square at (70, 70): x = 70 + (v + 50) / 1100 * 500, y = 570 - (v + 50) / 1100 * 500,
    // so 0 -> 92.7 (x) / 547.3 (y) and 1000 -> 547.3 (x) / 92.7 (y).
    EXPECT_NE(s.find("stroke=\"#1f77b4\" stroke-width=\"1.5\" points=\"92.7,547.3 547.3,547.3 547.3,92.7\""),
              std::string::npos)
        << s;
    EXPECT_NE(s.find("stroke=\"#d62728\" stroke-width=\"1.5\" stroke-dasharray=\"4 3\" "
                     "points=\"92.7,547.3 92.7,547.3 547.3,547.3\""),
              std::string::npos)
        << s;
    EXPECT_NE(s.find(">run &lt;1&gt;</text>"), std::string::npos) << "the title is escaped";
    EXPECT_NE(s.find("axis 0 position [pulses]"), std::string::npos);
    EXPECT_NE(s.find("axis 1 position [pulses]"), std::string::npos);
    EXPECT_NE(s.find(">commanded (CAMC-QI CNT1)</text>"), std::string::npos);
    EXPECT_NE(s.find(">actual (drive 0x6064)</text>"), std::string::npos);
    // Ticks every 200 pulses (nice step for 1100 over 8 divisions): 0 at x 92.7, 1000 at x 547.3.
    EXPECT_NE(s.find("<text x=\"92.7\" y=\"586.0\" text-anchor=\"middle\" font-size=\"11.0\">0</text>"),
              std::string::npos);
    EXPECT_NE(s.find("<text x=\"547.3\" y=\"586.0\" text-anchor=\"middle\" font-size=\"11.0\">1000</text>"),
              std::string::npos);
}

TEST(TrajectoryReport, SvgOfOtherAxesUsesThem) {
    // Axis 2 never moves (extent 0): its value 7 is centred in the square, the span is axis 0's.
    const std::string s = trajectory_svg(l_path(), 0, 2, "t");
    EXPECT_NE(s.find("axis 2 position [pulses]"), std::string::npos);
    // y of 7 is the middle of the square: 570 - 0.5 * 500 = 320.
    EXPECT_NE(s.find("points=\"92.7,320.0 547.3,320.0 547.3,320.0\""), std::string::npos) << s;
}

TEST(TrajectoryReport, UnwritableFileIsNamed) {
    const auto dir = std::filesystem::temp_directory_path() / "rcsim_no_such_dir" / "x";
    try {
        write_trajectory_svg(l_path(), dir / "trajectory.svg", 0, 1, "t");
        FAIL() << "no error";
    } catch (const ConfigError& e) { // bad input (exit 2), naming the file
        EXPECT_EQ(std::string(e.what()), (dir / "trajectory.svg").string() + ": cannot write the file");
    }
    EXPECT_THROW(write_trajectory_csv(l_path(), dir / "trajectory.csv"), ConfigError);
    // A full disk: the open succeeds, the write fails.
    EXPECT_THROW(write_trajectory_csv(l_path(), "/dev/full"), ConfigError);
}

} // namespace
