// The motion scenario runner (scenarios/run/motion_run.h): the X-Y plotter circle end to end,
// and bad `motion:` sections, each error naming file, line and the full key path (the same
// cases through the rcsim executable are in tests/scenarios/cli/bad_input.sh).
#include "scenarios/run/motion_run.h"
#include "tests/support/files.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

using rcsim::run_motion_scenario;
namespace test = rcsim::test;

namespace {

const double kPi = std::acos(-1.0);

/// The check `name` of a motion report (report["motion"]["checks"]), or an empty object.
nlohmann::json check_named(const nlohmann::json& report, const std::string& name) {
    for (const auto& c : report["motion"]["checks"])
        if (c["name"] == name) return c;
    ADD_FAILURE() << "no check " << name << " in " << report["motion"]["checks"].dump();
    return nlohmann::json::object();
}

TEST(MotionScenario, XyPlotterCircleWritesCsvAndSvgAndCloses) {
    const std::string file = std::string(RCSIM_SOURCE_DIR) + "/scenarios/xy_plotter_circle.yaml";
    const YAML::Node root = YAML::LoadFile(file);
    const auto out = test::scratch_dir() / "motion_circle_test";
    std::filesystem::remove_all(out);
    nlohmann::json report;
    ASSERT_EQ(run_motion_scenario(root, file, out, 1, report), 0) << report.dump(2);
    const auto& m = report["motion"];
    EXPECT_EQ(m["state"], "STANDSTILL");
    EXPECT_EQ(m["final_cmd_pulses"][0], 0);
    EXPECT_EQ(m["final_cmd_pulses"][1], 0);
    // Every check in the one schema (scenarios/verdict/checks.h), in report order.
    std::vector<std::string> names;
    for (const auto& c : m["checks"]) {
        names.push_back(c["name"]);
        EXPECT_TRUE(c["passed"].get<bool>()) << c.dump();
        EXPECT_EQ(c["status"], "passed");
        EXPECT_TRUE(c["value"].is_number() && c["limit"].is_number()) << c.dump();
    }
    EXPECT_EQ(names, (std::vector<std::string>{"fb_outcomes_as_expected", "final_state", "final_positions",
                                               "circle_radial_error_pulses", "circle_swept_angle_rad",
                                               "circle_end_error_pulses"}));
    EXPECT_LE(check_named(report, "circle_radial_error_pulses")["value"].get<double>(), 1.0);
    // A full circle of R = 5000: 2 pi, at least 2 pi less one pulse of arc (1/5000 rad).
    const auto sweep = check_named(report, "circle_swept_angle_rad");
    EXPECT_NEAR(sweep["value"].get<double>(), 2 * kPi, 1.0 / 5000);
    EXPECT_DOUBLE_EQ(sweep["limit"].get<double>(), 2 * kPi - 1.0 / 5000);
    EXPECT_EQ(check_named(report, "circle_end_error_pulses")["value"].get<double>(), 0.0);
    // The circle command's outcome is in the command log: Done, once the chip's BUSY fell.
    const auto& circle = m["commands"][1];
    EXPECT_EQ(circle["fb"], "MC_CircleCenterMove");
    EXPECT_EQ(circle["expect"], "done");
    EXPECT_EQ(circle["outcome"], "done");
    EXPECT_GT(circle["outcome_ms"].get<double>(), 10);
    EXPECT_LT(circle["outcome_ms"].get<double>(), 2500);
    std::ifstream csv(out / "trajectory.csv");
    std::string header;
    std::getline(csv, header);
    EXPECT_EQ(header, "t_s,axis,cmd_pulses,act_pulses");
    std::size_t rows = 0;
    for (std::string line; std::getline(csv, line);) ++rows;
    EXPECT_EQ(rows, 4 * m["samples"].get<std::size_t>());
    const std::string svg = test::slurp(out / "trajectory.svg");
    EXPECT_NE(svg.find("<polyline"), std::string::npos);
    EXPECT_NE(svg.find("axis 0 position"), std::string::npos);
    EXPECT_NE(svg.find("commanded"), std::string::npos);
}

TEST(MotionScenario, BadInputNamesFileAndLine) {
    const YAML::Node root = YAML::Load("motion:\n  duration_s: 1\n  commands:\n    - {at_ms: 5, fb: MC_Fly}\n");
    nlohmann::json report;
    EXPECT_EQ(run_motion_scenario(root, "bad.yaml", test::scratch_dir(), 0, report), 2);
    const std::string e = report["motion"]["error"];
    EXPECT_NE(e.find("bad.yaml:4"), std::string::npos) << e;
    EXPECT_NE(e.find("MC_Fly"), std::string::npos) << e;
    nlohmann::json r2;
    EXPECT_EQ(run_motion_scenario(YAML::Load("motion:\n  duration_s: 1\n  control_cycle_ms: -3\n"), "b2.yaml",
                                  test::scratch_dir(), 0, r2),
              2);
    EXPECT_NE(r2["motion"]["error"].get<std::string>().find("-3"), std::string::npos);
}

TEST(MotionScenario, FailingCheckReturnsOne) {
    const YAML::Node root = YAML::Load(
        "motion:\n  duration_s: 0.3\n  commands:\n    - {at_ms: 0, token: SV, data: '1'}\n"
        "    - {at_ms: 10, token: MA, data: '0,1000,20000,200000,200000'}\n"
        "  checks:\n    final_positions: [999]\n");
    nlohmann::json report;
    EXPECT_EQ(run_motion_scenario(root, "c.yaml", test::scratch_dir() / "fail", 0, report), 1);
    EXPECT_EQ(report["motion"]["final_cmd_pulses"][0], 1000);
}

TEST(MotionScenario, ExpectedErrorWithItsErrorIdPasses) {
    // MC_MoveAbsolute on axis 0 with no MC_Power: refused, ErrorID 0x7001 (Disabled), written in
    // hex as in docs/motion.md. Expected, so the run passes; expecting another ErrorID fails it.
    const std::string move = "motion:\n  duration_s: 0.02\n  commands:\n    - {at_ms: 0, fb: MC_MoveAbsolute, axis: 0,"
                             " position: 1, velocity: 1, acceleration: 1, deceleration: 1, expect: error, error_id: ";
    const auto out = test::scratch_dir() / "motion_expect";
    nlohmann::json report;
    ASSERT_EQ(run_motion_scenario(YAML::Load(move + "0x7001}\n"), "e.yaml", out, 0, report), 0) << report.dump(2);
    EXPECT_EQ(report["motion"]["commands"][0]["outcome"], "error");
    EXPECT_EQ(report["motion"]["commands"][0]["error_id"], 0x7001);
    EXPECT_EQ(report["motion"]["commands"][0]["outcome_ms"], 0.0);
}

TEST(MotionScenario, UnexpectedErrorIdFails) {
    const std::string move = "motion:\n  duration_s: 0.02\n  commands:\n    - {at_ms: 0, fb: MC_MoveAbsolute, axis: 0,"
                             " position: 1, velocity: 1, acceleration: 1, deceleration: 1, expect: error, error_id: ";
    nlohmann::json report;
    EXPECT_EQ(run_motion_scenario(YAML::Load(move + "0x7002}\n"), "e.yaml",
                                  test::scratch_dir() / "motion_expect2", 0, report),
              1);
    EXPECT_FALSE(check_named(report, "fb_outcomes_as_expected")["passed"].get<bool>());
}

/// The error run_motion_scenario() reports for the scenario text `yaml` (file "m.yaml"), or
/// "(exit N)" when it did not return 2.
std::string error_of(const std::string& yaml) {
    nlohmann::json report;
    const int rc = run_motion_scenario(YAML::Load(yaml), "m.yaml", test::scratch_dir(), 0, report);
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
    EXPECT_EQ(error_of("motion:\n  duration_s: 0.01\n  commands:\n    - {at_ms: 0, inject_fault: 0, code: 0x10000}\n"),
              "m.yaml:4: bad value for 'motion.commands[0].code': '0x10000'");
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
    // Expected outcomes: done, error or aborted; an ErrorID only with expect: error.
    const std::string move = "motion:\n  duration_s: 0.01\n  commands:\n    - {at_ms: 0, fb: MC_MoveAbsolute, axis: 0,"
                             " position: 1, velocity: 1, acceleration: 1, deceleration: 1, ";
    EXPECT_EQ(error_of(move + "expect: fine}\n"),
              "m.yaml:4: 'motion.commands[0].expect' must be 'done', 'error' or 'aborted', got 'fine'");
    EXPECT_EQ(error_of(move + "error_id: 4113}\n"),
              "m.yaml:4: 'motion.commands[0].error_id' is the ErrorID of 'expect: error'");
    EXPECT_EQ(error_of(move + "expect: error, error_id: 70000}\n"),
              "m.yaml:4: bad value for 'motion.commands[0].error_id': '70000'");
    EXPECT_EQ(error_of("motion:\n  duration_s: 0.01\n  commands:\n    - {at_ms: 0, token: SV, data: '1', expect: done}\n"),
              "m.yaml:4: unknown key 'motion.commands[0].expect'");
    // The circle check judges one circle.
    const std::string circle = "    - {at_ms: 0, fb: MC_CircleCenterMove, center_x: -10, center_y: 0, end_x: 0, end_y: 0,"
                               " velocity: 1, acceleration: 1, deceleration: 1}\n";
    EXPECT_EQ(error_of("motion:\n  duration_s: 0.01\n  commands:\n" + circle + circle +
                       "  checks:\n    circle: {center_x: -10, center_y: 0, radius: 10}\n"),
              "m.yaml:7: 'motion.checks.circle' judges one MC_CircleCenterMove; the scenario has 2");
    EXPECT_EQ(error_of("motion:\n  duration_s: 0.01\n  checks:\n    position_tolerance: 3\n"),
              "m.yaml:4: unknown key 'motion.checks.position_tolerance'");
}

} // namespace

/// cmd_pulses of axis `axis` in the last trajectory sample before it jumped to `preset` (the
/// position MC_Home sets at the home point; moving, it changes by a few pulses per sample).
static std::int64_t last_before_preset(const std::filesystem::path& csv_path, int axis, std::int64_t preset) {
    std::ifstream csv(csv_path);
    std::string line;
    std::getline(csv, line); // header t_s,axis,cmd_pulses,act_pulses
    std::int64_t last = 0;
    while (std::getline(csv, line)) {
        std::stringstream row(line);
        std::string t, a, cmd;
        std::getline(row, t, ','), std::getline(row, a, ','), std::getline(row, cmd, ',');
        if (std::stoi(a) != axis) continue;
        const std::int64_t p = std::stoll(cmd);
        if (p == preset && std::llabs(p - last) > 100) return last;
        last = p;
    }
    ADD_FAILURE() << "no preset to " << preset << " in " << csv_path;
    return 0;
}

// Home switch at -2500 (on at and below), Z where (position - 137) % 1000 == 0. Without Z the
// homing ends on the switch edge, -2500; with Z the search leaves the switch (+) and stops on the
// next Z pulse, -1863. The trajectory samples once per 1 ms cycle: at z_velocity 1000 pps
// (approach 2000 pps) the last sample before the preset is at most one (two) pulses short.
// (One simulation per test process: SystemC elaborates once.)
const char* const kHomeScenario = "motion:\n  duration_s: 5\n  axes: [{home: -2500, z_pitch: 1000, z_offset: 137}]\n"
                                  "  commands:\n    - {at_ms: 0, fb: MC_Power, axis: 0}\n"
                                  "    - {at_ms: 10, fb: MC_Home, axis: 0, position: -7, ";

TEST(MotionScenario, HomeWithZPhaseStopsOnTheEncoderZPulseOfTheAxisKeys) {
    const auto out = test::scratch_dir() / "home_z";
    nlohmann::json report;
    ASSERT_EQ(run_motion_scenario(YAML::Load(std::string(kHomeScenario) + "z_phase: true, z_velocity: 1000}\n"),
                                  "z.yaml", out, 0, report), 0) << report.dump(2);
    EXPECT_EQ(report["motion"]["final_cmd_pulses"][0], -7);
    const auto z = last_before_preset(out / "trajectory.csv", 0, -7);
    EXPECT_GE(z, -1864);
    EXPECT_LE(z, -1863);
}

TEST(MotionScenario, HomeWithoutZPhaseStopsOnTheSwitchEdge) {
    const auto out = test::scratch_dir() / "home_noz";
    nlohmann::json report;
    ASSERT_EQ(run_motion_scenario(YAML::Load(std::string(kHomeScenario) + "z_phase: false}\n"), "z.yaml", out, 0,
                                  report), 0) << report.dump(2);
    const auto sw = last_before_preset(out / "trajectory.csv", 0, -7);
    EXPECT_GE(sw, -2500);
    EXPECT_LE(sw, -2498);
}

TEST(MotionScenario, LineMoveOverThreeAxesEndsAtItsDistances) {
    const YAML::Node root = YAML::Load(
        "motion:\n  duration_s: 1.5\n  commands:\n"
        "    - {at_ms: 0, fb: MC_Power, axis: 0}\n    - {at_ms: 0, fb: MC_Power, axis: 1}\n"
        "    - {at_ms: 0, fb: MC_Power, axis: 3}\n"
        "    - {at_ms: 10, fb: MC_LineMove, axes: [3, 0, 1], distances: [12000, 3000, -4000], velocity: 20000,"
        " acceleration: 200000, deceleration: 200000}\n"
        "  checks:\n    final_positions: [3000, -4000, 0, 12000]\n");
    nlohmann::json report;
    ASSERT_EQ(run_motion_scenario(root, "l.yaml", test::scratch_dir() / "line_n", 0, report),
              0) << report.dump(2);
    EXPECT_EQ(report["motion"]["commands"][3]["fb"], "MC_LineMove");
    EXPECT_EQ(report["motion"]["commands"][3]["outcome"], "done");
}

TEST(MotionScenario, BadLineMoveNamesTheKey) {
    const std::string head = "motion:\n  duration_s: 0.01\n  commands:\n    - {at_ms: 0, fb: MC_LineMove, ";
    const std::string tail = ", velocity: 1, acceleration: 1, deceleration: 1}\n";
    auto error_of = [&](const std::string& args) {
        nlohmann::json report;
        EXPECT_EQ(run_motion_scenario(YAML::Load(head + args + tail), "lm.yaml",
                                      test::scratch_dir(), 0, report), 2);
        return report["motion"]["error"].get<std::string>();
    };
    EXPECT_NE(error_of("axes: [0], distances: [1]").find("lm.yaml:4: 'motion.commands[0].axes' must list 2 to 4 axes"),
              std::string::npos);
    EXPECT_NE(error_of("axes: [0, 1], distances: [1]").find("'motion.commands[0].distances' must hold one distance per axis (2)"),
              std::string::npos);
    EXPECT_NE(error_of("axes: [0, 0], distances: [1, 2]").find("names axis 0 twice"), std::string::npos);
    EXPECT_NE(error_of("axes: [0, 4], distances: [1, 2]").find("'motion.commands[0].axes[1]' must be an axis 0 to 3"),
              std::string::npos);
    EXPECT_NE(error_of("axes: [0, 1], distances: [1, 2.5]")
                  .find("'motion.commands[0].distances[1]' must be a whole number of pulses"),
              std::string::npos);
}

namespace {

// docs/motion.md's `motion:` example runs as shown: the circle, a drive fault whose cause clears
// (`clear_after: yes`), the move refused in ErrorStop (0x7002), MC_Reset back to Standstill and a
// move to 100 afterwards; every check passes.
TEST(MotionScenario, TheDocsExampleWithATransientFaultAndMcResetPasses) {
    const std::string doc = test::slurp(std::string(RCSIM_SOURCE_DIR) + "/docs/motion.md");
    const std::size_t from = doc.find("```yaml\nmotion:\n");
    ASSERT_NE(from, std::string::npos);
    const std::size_t begin = from + 8, end = doc.find("```", begin);
    const std::string yaml = doc.substr(begin, end - begin);
    ASSERT_NE(yaml.find("clear_after: yes"), std::string::npos);
    nlohmann::json report;
    const auto out = test::scratch_dir() / "motion_docs_example";
    ASSERT_EQ(run_motion_scenario(YAML::Load(yaml), "motion.md", out, 0, report), 0) << report.dump(2);
    const nlohmann::json& cmds = report["motion"]["commands"];
    int resets = 0;
    for (const auto& c : cmds)
        if (c.value("fb", "") == "MC_Reset") {
            EXPECT_EQ(c["outcome"], "done");
            ++resets;
        }
    EXPECT_EQ(resets, 1);
    EXPECT_EQ(report["motion"]["final_cmd_pulses"][0], 100);
    EXPECT_EQ(report["motion"]["state"], "STANDSTILL");
}

// Without clear_after the cause stays: MC_Reset answers Error 0x7103 (drive fault) and the axis
// stays in ErrorStop.
TEST(MotionScenario, LastingFaultKeepsMcResetFailing) {
    const std::string yaml =
        "motion:\n  duration_s: 0.3\n  commands:\n    - {at_ms: 0, token: SV, data: '1'}\n"
        "    - {at_ms: 20, inject_fault: 0, code: 0x7500}\n"
        "    - {at_ms: 50, fb: MC_Reset, axis: 0, expect: error, error_id: 0x7103}\n"
        "  checks:\n    final_state: ERRORSTOP\n";
    nlohmann::json report;
    const auto out = test::scratch_dir() / "motion_lasting_fault";
    EXPECT_EQ(run_motion_scenario(YAML::Load(yaml), "f.yaml", out, 0, report), 0) << report.dump(2);
}

} // namespace

namespace {

// MC_MoveVelocity from a scenario `fb:` (done at InVelocity, then stopped by MC_Halt),
// MC_SetPosition, and the reads: a parameter the axis does not have is an expected error 0x7006.
TEST(MotionScenario, MoveVelocitySetPositionAndReadsFromFb) {
    const std::string yaml =
        "motion:\n  duration_s: 0.6\n  commands:\n    - {at_ms: 0, token: SV, data: '1'}\n"
        "    - {at_ms: 10, fb: MC_MoveVelocity, axis: 0, velocity: 10000, acceleration: 100000,"
        " deceleration: 100000}\n"
        "    - {at_ms: 200, fb: MC_Halt, axis: 0, deceleration: 100000}\n"
        "    - {at_ms: 400, fb: MC_SetPosition, axis: 0, position: 0}\n"
        "    - {at_ms: 410, fb: MC_ReadStatus, axis: 0}\n"
        "    - {at_ms: 410, fb: MC_ReadParameter, axis: 0, parameter: 16, expect: error, error_id: 0x7006}\n"
        "  checks:\n    final_state: STANDSTILL\n    final_positions: [0]\n";
    nlohmann::json report;
    const auto out = test::scratch_dir() / "motion_fb_reads";
    ASSERT_EQ(run_motion_scenario(YAML::Load(yaml), "v.yaml", out, 0, report), 0) << report.dump(2);
    const nlohmann::json& c = report["motion"]["commands"];
    // MC_MoveVelocity: "done" at InVelocity, after its ramp from STD 100 (the scenario default)
    // to 10000 at 100000 pulses/s^2: 99 ms after 10 ms, seen at a control cycle of 1 ms.
    EXPECT_EQ(c[1]["fb"], "MC_MoveVelocity");
    EXPECT_EQ(c[1]["outcome"], "done");
    EXPECT_GE(c[1]["outcome_ms"].get<double>(), 108.0);
    EXPECT_LE(c[1]["outcome_ms"].get<double>(), 110.0);
    EXPECT_EQ(c[3]["outcome"], "done");
}

} // namespace

