// The motion scenario runner (scenarios/motion_scenario.h): the X-Y plotter circle end to end,
// and bad `motion:` sections, each error naming file, line and the full key path (the same
// cases through the rcsim executable are in tests/cli/bad_input.sh).
#include "scenarios/motion_scenario.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

using rcsim::run_motion_scenario;

namespace {

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

/// The error run_motion_scenario() reports for the scenario text `yaml` (file "m.yaml"), or
/// "(exit N)" when it did not return 2.
std::string error_of(const std::string& yaml) {
    nlohmann::json report;
    const int rc = run_motion_scenario(YAML::Load(yaml), "m.yaml", std::filesystem::temp_directory_path(), 0, report);
    if (rc != 2) return "(exit " + std::to_string(rc) + ")";
    return report["motion"]["error"].get<std::string>();
}

TEST(MotionScenario, BadSectionErrorsNameFileLineAndKeyPath) {
    EXPECT_EQ(error_of("motion: 5\n"), "m.yaml:1: 'motion' must be a mapping");
    EXPECT_EQ(error_of("motion:\n  control_cycle_ms: 1\n"), "m.yaml:2: missing required key 'motion.duration_s'");
    EXPECT_EQ(error_of("motion:\n  duration_s: 0.01\n  bogus: 1\n"), "m.yaml:3: unknown key 'motion.bogus'");
    EXPECT_EQ(error_of("motion:\n  duration_s: 5000\n"), "m.yaml:2: 'motion.duration_s' = 5000 is out of range [0, 3600]");
    // The command's index is in the key path, the line is the command's.
    EXPECT_EQ(error_of("motion:\n  duration_s: 0.01\n  commands:\n    - {at_ms: 0, token: SV, data: '1'}\n"
                       "    - {at_ms: 0, fb: MC_Power, axis: 9}\n"),
              "m.yaml:5: 'motion.commands[1].axis' = 9 is out of range [0, 3]");
    EXPECT_EQ(error_of("motion:\n  duration_s: 0.01\n  commands:\n    - {at_ms: 0, fb: MC_MoveAbsolute, axis: 0,"
                       " position: 1, velocity: 1, acceleration: 1, deceleration: 1, buffer: later}\n"),
              "m.yaml:4: 'motion.commands[0].buffer' must be 'aborting' or 'buffered', got 'later'");
    EXPECT_EQ(error_of("motion:\n  duration_s: 0.01\n  commands:\n    - {at_ms: 0, inject_fault: 0, clear_after: maybe}\n"),
              "m.yaml:4: 'motion.commands[0].clear_after' must be 'yes' or 'no', got 'maybe'");
    EXPECT_EQ(error_of("motion:\n  duration_s: 0.01\n  commands:\n    - {at_ms: 0, token: SV, fb: MC_Power}\n"),
              "m.yaml:4: unknown key 'motion.commands[0].fb'");
    EXPECT_EQ(error_of("motion:\n  duration_s: 0.01\n  commands: {at_ms: 0}\n"),
              "m.yaml:3: 'motion.commands' must be a list of mappings");
    // Four axes (MotionController::axes): a fifth entry is refused.
    EXPECT_EQ(error_of("motion:\n  duration_s: 0.01\n  axes: [{}, {}, {}, {}, {}]\n"),
              "m.yaml:3: 'motion.axes' must be a list of at most 4 mappings");
    EXPECT_EQ(error_of("motion:\n  duration_s: 0.01\n  axes:\n    - {pelm: 100}\n    - {plem: 100}\n"),
              "m.yaml:5: unknown key 'motion.axes[1].plem'");
    EXPECT_EQ(error_of("motion:\n  duration_s: 0.01\n  checks:\n    final_positions: [0, a]\n"),
              "m.yaml:4: bad value for 'motion.checks.final_positions[1]': 'a'");
    EXPECT_EQ(error_of("motion:\n  duration_s: 0.01\n  checks:\n    circle: {center_x: 0, center_y: 0}\n"),
              "m.yaml:4: missing required key 'motion.checks.circle.radius'");
    EXPECT_EQ(error_of("motion:\n  duration_s: 0.01\n  checks:\n    position_tolerance: 3\n"),
              "m.yaml:4: unknown key 'motion.checks.position_tolerance'");
}

} // namespace
