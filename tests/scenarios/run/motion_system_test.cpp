// The motion layer in a communication run (scenarios/verdict/motion_figures.h): command latency pairing,
// the script's report, and the scenario keys of scripted hosts and main_cpu.motion, bad ones
// named with file and line.
#include "models/plumbing/config_error.h"
#include "scenarios/run/motion_run.h"
#include "scenarios/verdict/motion_figures.h"
#include "scenarios/config/scenario.h"
#include "tests/support/files.h"
#include "tests/support/scenario_error.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace rcsim;
using sc_core::sc_time;

namespace {

using test::scenario_error_of;

} // namespace

// Moves answered BCH 00 pair with the motion layer's accepted moves in order; a refused move
// (BCH 05), a non-move (EC) and a move sent without waiting (-1: the host cannot know it was
// accepted) are skipped; a move whose first pulse never came has no latency.
TEST(MotionSystem, LatencyPairsAcceptedMovesInOrder) {
    ScriptResult host;
    host.commands = {{"SV", ms(1), 0}, {"MA", ms(10), 0}, {"MA", ms(20), 5}, {"EC", ms(25), 0},
                     {"MC", ms(30), 0}, {"MR", ms(40), -1}, {"MR", ms(50), 0}};
    std::vector<motion::MoveRecord> moves = {{"MA", ms(12), us(14'500)}, {"MC", ms(31), ms(33)}, {"MR", ms(52), std::nullopt}};
    const std::vector<double> lat = command_latencies_us(host, moves);
    ASSERT_EQ(lat.size(), 2u);
    EXPECT_DOUBLE_EQ(lat[0], 4500.0);
    EXPECT_DOUBLE_EQ(lat[1], 3000.0);
}

TEST(MotionSystem, ScriptJsonSaysWhereItFailed) {
    ScriptResult r;
    r.steps = 3, r.completed = 1, r.failed = true, r.failed_step = 1, r.failed_line = 14;
    r.failure = "MC answered BCH 04";
    const nlohmann::json j = script_json(r);
    EXPECT_EQ(j["completed"], 1);
    EXPECT_EQ(j["failure"]["line"], 14);
    EXPECT_EQ(j["failure"]["reason"], "MC answered BCH 04");
    EXPECT_TRUE(j["finished_ms"].is_null());
    r.failed = false, r.completed = 3, r.finished_at = us(1'234'500);
    EXPECT_EQ(script_json(r)["finished_ms"], 1234.5);
}

TEST(MotionSystem, ShippedOverSerialScenarioLoads) {
    const Scenario s = load_scenario(std::string(RCSIM_SOURCE_DIR) + "/scenarios/xy_plotter_over_serial.yaml");
    EXPECT_TRUE(s.main_motion);
    ASSERT_EQ(s.ports[0].protocol.traffic.pattern, HostTraffic::Pattern::script);
    const auto& script = s.ports[0].protocol.traffic.script;
    ASSERT_GE(script.size(), 3u);
    EXPECT_EQ(script[0].token, "SV");
    EXPECT_EQ(script[0].expect_bch, 0);
    EXPECT_EQ(script[1].kind, ScriptStep::Kind::wait_state);
    EXPECT_GT(script[1].line, 0);
    ASSERT_TRUE(s.checks.circle);
    EXPECT_EQ(s.checks.circle->radius, 5000);
    const motion::MotionConfig c = motion_config(s);
    EXPECT_EQ(c.cost.bus_cycle, sc_time(62.5, sc_core::SC_NS)); // 16 MHz
    EXPECT_EQ(c.cost.fb_call, s.board.main.fb_call);
}

TEST(MotionSystem, ScriptStepsAreReadWithTheirLines) {
    const std::string e = scenario_error_of("two.yaml", "ports:\n  - host: protocol\n    traffic: script\n    script:\n"
                                               "      - {token: EC}\n      - {delay_ms: 5, token: EC}\n");
    EXPECT_NE(e.find("two.yaml:6: a script step has exactly one of"), std::string::npos) << e;
    const std::string d = scenario_error_of("data.yaml", "ports:\n  - host: protocol\n    traffic: script\n    script:\n"
                                                "      - {token: EC, data: \"\\x01\"}\n");
    EXPECT_NE(d.find("data.yaml:5: this command cannot be sent"), std::string::npos) << d;
    const std::string n = scenario_error_of("none.yaml", "ports:\n  - host: protocol\n    traffic: script\n    script:\n"
                                                "      - {token: EC, wait: none, expect_bch: 0}\n");
    EXPECT_NE(n.find("none.yaml:5: 'ports[0].script[0].expect_bch' needs 'wait: response'"), std::string::npos) << n;
    const std::string c = scenario_error_of("csp.yaml", "main_cpu: {csp: {radius: 10}}\n");
    EXPECT_NE(c.find("csp.yaml:1: 'main_cpu.csp' is a path of the motion layer"), std::string::npos) << c;
    const std::string o = scenario_error_of("sync.yaml", "main_cpu: {motion: true, cycle_period_us: 1000, csp: {sync_offset_us: 1000}}\n");
    EXPECT_NE(o.find("sync.yaml:1: 'main_cpu.csp.sync_offset_us' must be shorter"), std::string::npos) << o;
    EXPECT_EQ(scenario_error_of("ok.yaml", "main_cpu: {motion: true, csp: {radius: 10}}\nports:\n  - host: protocol\n"
                                  "    traffic: script\n    script:\n      - {wait_state: STANDSTILL}\n"),
              "(no error)");
}

// The motion scenario's observer, and motion.trajectory: trajectory.csv every 10th sample (and the last), every pulse in
// trajectory_pulses.csv: a move of 300 pulses on axis 0 gives 300 rows of +1.
TEST(MotionSystem, TrajectoryOptionsShapeTheFiles) {
    const YAML::Node root = YAML::Load(
        "name: opts\n"
        "motion:\n"
        "  duration_s: 0.2\n"
        "  trajectory: {csv_every: 10, pulse_trace: true}\n"
        "  commands:\n"
        "    - {at_ms: 0, fb: MC_Power, axis: 0}\n"
        "    - {at_ms: 10, fb: MC_MoveRelative, axis: 0, distance: 300, velocity: 10000, acceleration: 100000,\n"
        "       deceleration: 100000}\n");
    const auto out = test::scratch_dir();
    nlohmann::json report;
    std::size_t snapshots = 0;
    motion::MotionSnapshot last;
    ASSERT_EQ(run_motion_scenario(root, "opts.yaml", out, 1, report,
                                  [&](const motion::MotionSnapshot& s) { ++snapshots, last = s; }),
              0)
        << report.dump(2);
    const std::size_t samples = report["motion"]["samples"];
    // The observer sees every control cycle, the last one with the move done.
    EXPECT_EQ(snapshots, samples);
    EXPECT_EQ(last.cmd[0], 300);
    EXPECT_EQ(last.axis_state[0], motion::AxisState::standstill);
    EXPECT_DOUBLE_EQ(last.t_s, 0.2);
    auto lines = [](const std::filesystem::path& f) {
        std::ifstream in(f);
        std::size_t n = 0;
        for (std::string l; std::getline(in, l);) ++n;
        return n;
    };
    // 4 axes a row set; samples 0, 10, 20, ... and the last.
    const std::size_t kept = (samples - 1) / 10 + 1 + ((samples - 1) % 10 != 0);
    EXPECT_EQ(lines(out / "trajectory.csv"), 1 + 4 * kept);
    EXPECT_EQ(lines(out / "trajectory_pulses.csv"), 1u + 300u);
    EXPECT_TRUE(std::filesystem::exists(out / "trajectory_time.svg"));
    EXPECT_NE(test::slurp(out / "trajectory.svg").find(">opts</text>"), std::string::npos) << "titled with the scenario's name";
}

TEST(MotionSystem, TrajectoryOptionsAreChecked) {
    const std::string z = scenario_error_of("every.yaml", "main_cpu: {motion: true, trajectory: {csv_every: 0}}\n");
    EXPECT_NE(z.find("every.yaml:1: 'main_cpu.trajectory.csv_every' = 0"), std::string::npos) << z;
    const std::string m = scenario_error_of("nomotion.yaml", "main_cpu: {trajectory: {pulse_trace: true}}\n");
    EXPECT_NE(m.find("nomotion.yaml:1: 'main_cpu.trajectory' needs 'main_cpu.motion: true'"), std::string::npos) << m;
}
