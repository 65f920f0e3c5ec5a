// The motion controller's token interface and the X-Y plotter circle scenario end to end.
#include "main_cpu/motion/motion_scenario.h"
#include "tests/motion/motion_bench.h"

#include <fstream>
#include <sstream>

using namespace rcsim::motion;
using namespace rcsim::motion::test;

namespace {

TEST(MotionController, TokensMoveAndReportWithBchCodes) {
    run_bench([](Bench& b) {
        EXPECT_EQ(b.mc.command("XX", "").bch, 0x01);
        EXPECT_EQ(b.mc.command("SV", "2").bch, 0x02);
        EXPECT_EQ(b.mc.command("MA", "0,100,1000,1000,1000").bch, 0x04); // not powered
        EXPECT_EQ(b.mc.command("MA", "0,100,abc,1000,1000").bch, 0x02);
        EXPECT_EQ(b.mc.state(), "DISABLED");
        b.power_on();
        EXPECT_EQ(b.mc.state(), "STANDSTILL");
        EXPECT_EQ(b.mc.command("MA", "2,-3000,20000,200000,200000").bch, 0x00);
        EXPECT_EQ(b.mc.command("ML", "1000,2000,20000,200000,200000").bch, 0x00);
        b.until([&] { return b.mc.state() == "STANDSTILL"; });
        b.cycles(20); // let the drives settle
        const auto p = b.mc.positions();
        EXPECT_EQ(p[0], 1000);
        EXPECT_EQ(p[1], 2000);
        EXPECT_EQ(p[2], -3000);
        // Half circle CCW about (0,2000) from (1000,2000) to (-1000,2000).
        EXPECT_EQ(b.mc.command("MC", "0,2000,-1000,2000,0,10000").bch, 0x00);
        b.cycles(1);
        b.until([&] { return b.mc.state() == "STANDSTILL"; });
        EXPECT_EQ(b.mc.chip().command_position(0), -1000);
        EXPECT_EQ(b.mc.chip().command_position(1), 2000);
        EXPECT_EQ(b.mc.command("SV", "0").bch, 0x00);
        b.cycles(1);
        EXPECT_EQ(b.mc.state(), "DISABLED");
    });
}

TEST(MotionController, ConsecutiveTokensOnOneBlockEachMove) {
    run_bench([](Bench& b) {
        b.power_on();
        for (int target : {4000, -2000, 1000}) {
            ASSERT_EQ(b.mc.command("MA", "0," + std::to_string(target) + ",30000,200000,200000").bch, 0x00);
            b.cycles(1);
            EXPECT_EQ(b.mc.axis(0).state(), AxisState::discrete_motion) << target;
            b.until([&] { return b.mc.axis(0).state() == AxisState::standstill; });
            EXPECT_EQ(b.mc.chip().command_position(0), target);
        }
    });
}

TEST(MotionScenario, XyPlotterCircleWritesCsvAndSvgAndCloses) {
    const std::string file = std::string(RCSIM_SOURCE_DIR) + "/scenarios/xy_plotter_circle.yaml";
    const YAML::Node root = YAML::LoadFile(file);
    const auto out = std::filesystem::temp_directory_path() / "rcsim_motion_circle_test";
    std::filesystem::remove_all(out);
    nlohmann::json report;
    ASSERT_EQ(run_motion_scenario(root, file, out, 1, report), 0) << report.dump(2);
    const auto& m = report["motion"];
    EXPECT_EQ(m["state"], "STANDSTILL");
    EXPECT_EQ(m["final_cmd_pulses"][0], 0);
    EXPECT_EQ(m["final_cmd_pulses"][1], 0);
    EXPECT_LE(m["checks"][2]["max_radial_error_cmd"].get<double>(), 1.0);
    EXPECT_TRUE(m["checks"][2]["closes"].get<bool>());
    EXPECT_GT(m["checks"][2]["angle_span_rad"].get<double>(), 6.0); // went all the way round
    std::ifstream csv(out / "trajectory.csv");
    std::string header;
    std::getline(csv, header);
    EXPECT_EQ(header, "t_s,axis,cmd_pulses,act_pulses");
    std::size_t rows = 0;
    for (std::string line; std::getline(csv, line);) ++rows;
    EXPECT_EQ(rows, 4 * m["samples"].get<std::size_t>());
    std::ifstream svg(out / "trajectory.svg");
    std::stringstream ss;
    ss << svg.rdbuf();
    EXPECT_NE(ss.str().find("<polyline"), std::string::npos);
    EXPECT_NE(ss.str().find("axis 0 position"), std::string::npos);
    EXPECT_NE(ss.str().find("commanded"), std::string::npos);
}

TEST(MotionScenario, BadInputNamesFileAndLine) {
    const YAML::Node root = YAML::Load("motion:\n  duration_s: 1\n  commands:\n    - {at_ms: 5, fb: MC_Fly}\n");
    nlohmann::json report;
    EXPECT_EQ(run_motion_scenario(root, "bad.yaml", std::filesystem::temp_directory_path(), 0, report), 2);
    const std::string e = report["motion"]["error"];
    EXPECT_NE(e.find("bad.yaml:4"), std::string::npos) << e;
    EXPECT_NE(e.find("MC_Fly"), std::string::npos) << e;
    nlohmann::json r2;
    EXPECT_EQ(run_motion_scenario(YAML::Load("motion:\n  duration_s: 1\n  control_cycle_ms: -3\n"), "b2.yaml",
                                  std::filesystem::temp_directory_path(), 0, r2),
              2);
    EXPECT_NE(r2["motion"]["error"].get<std::string>().find("-3"), std::string::npos);
}

TEST(MotionScenario, FailingCheckReturnsOne) {
    const YAML::Node root = YAML::Load(
        "motion:\n  duration_s: 0.3\n  commands:\n    - {at_ms: 0, token: SV, data: '1'}\n"
        "    - {at_ms: 10, token: MA, data: '0,1000,20000,200000,200000'}\n"
        "  checks:\n    final_positions: [999]\n");
    nlohmann::json report;
    EXPECT_EQ(run_motion_scenario(root, "c.yaml", std::filesystem::temp_directory_path() / "rcsim_fail", 0, report), 1);
    EXPECT_EQ(report["motion"]["final_cmd_pulses"][0], 1000);
}

} // namespace
