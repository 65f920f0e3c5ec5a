// load_scenario() on bad scenario files: one ConfigError naming the file and line or the value
// (the same cases through the rcsim executable are in tests/scenarios/cli/bad_input.sh).
#include "models/plumbing/config_error.h"
#include "scenarios/config/scenario.h"
#include "tests/support/scenario_error.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace rcsim;

using test::scenario_error_of;
using test::scratch_dir;

TEST(ScenarioBadInput, EmptyFileIsAnErrorButEmptyMappingRunsDefaults) {
    EXPECT_NE(scenario_error_of("empty.yaml", "").find("empty.yaml: the scenario file is empty"), std::string::npos);
    EXPECT_NE(scenario_error_of("comment.yaml", "# only a comment\n").find("the scenario file is empty"), std::string::npos);
    const auto path = (scratch_dir() / "defaults.yaml").string();
    std::ofstream(path) << "{}\n";
    EXPECT_NO_THROW(load_scenario(path));
}

TEST(ScenarioBadInput, DirectoryIsNamed) {
    const auto dir = scratch_dir() / "a_dir.yaml";
    std::filesystem::create_directories(dir);
    try {
        load_scenario(dir.string());
        FAIL() << "no error for a directory";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("a_dir.yaml: is a directory"), std::string::npos) << e.what();
    }
}

TEST(ScenarioBadInput, NonScalarKeysNameFileAndLine) {
    EXPECT_NE(scenario_error_of("key.yaml", "duration_s: 1\n{[a]: 1}: 2\n").find("key.yaml:2: a key in 'top level' must be a plain name"),
              std::string::npos);
    const std::string tok = scenario_error_of("tok.yaml", "ports:\n  - host: protocol\n    tokens: {[a]: 1}\n");
    EXPECT_NE(tok.find("tok.yaml:3: a token must be two characters"), std::string::npos) << tok;
}

TEST(ScenarioBadInput, TokenWeightMustBeFinite) {
    for (const char* w : {".inf", ".nan", "-1", "0"}) {
        const std::string e =
            scenario_error_of("w.yaml", std::string("ports:\n  - host: protocol\n    tokens: {EC: ") + w + ", ST: 1}\n");
        EXPECT_NE(e.find("w.yaml:3: token 'EC' must be two characters with a finite weight > 0"), std::string::npos)
            << w << ": " << e;
    }
}

TEST(ScenarioBadInput, LogOnlyForTheProtocolHost) {
    for (const char* host : {"none", "raw"}) {
        const std::string e = scenario_error_of("log.yaml", std::string("ports:\n  - host: ") + host + "\n    log: x.log\n");
        EXPECT_NE(e.find("log.yaml:3: 'ports[0].log' is the protocol host's transaction log"), std::string::npos)
            << host << ": " << e;
    }
}

TEST(ScenarioBadInput, SerialFormatNamedOnce) {
    const std::string e = scenario_error_of("fmt.yaml", "ports:\n  - host: protocol\n    format: \"99999999999,8E1\"\n");
    EXPECT_NE(e.find("fmt.yaml:3: bad serial format '99999999999,8E1'"), std::string::npos) << e;
    EXPECT_EQ(e.find("bad serial format", e.find("bad serial format") + 1), std::string::npos) << e;
    const std::string z = scenario_error_of("fmt0.yaml", "ports:\n  - host: protocol\n    format: \"0,8E1\"\n");
    EXPECT_NE(z.find("fmt0.yaml:3: bad serial format '0,8E1'"), std::string::npos) << z;
}

TEST(ScenarioBadInput, NestedNonMappingNamesTheKeyWithoutTrailingDot) {
    const std::string e = scenario_error_of("board.yaml", "board: 5\n");
    EXPECT_NE(e.find("board.yaml:1: 'board' must be a mapping"), std::string::npos) << e;
}

// A derived setting (-1 inside) is taken by leaving the key out; a written negative is an error.
TEST(ScenarioBadInput, DerivedSettingsRejectWrittenNegatives) {
    EXPECT_NE(scenario_error_of("rt.yaml", "realtime: -0.5\n").find("rt.yaml:1: 'realtime' = -0.5 must be 0 (off) or in [0.01, 1e6]"),
              std::string::npos);
    EXPECT_NE(scenario_error_of("rt1.yaml", "realtime: -1\n").find("rt1.yaml:1: 'realtime'"), std::string::npos);
    EXPECT_NE(scenario_error_of("bu.yaml", "budget_us: -0.5\n").find("bu.yaml:1: 'budget_us' = -0.5 is out of range"),
              std::string::npos);
    EXPECT_NE(scenario_error_of("lat.yaml", "checks: {max_char_latency_us: -1}\n").find("lat.yaml:1:"), std::string::npos);
    const auto path = (scratch_dir() / "ok.yaml").string();
    std::ofstream(path) << "realtime: 0\nbudget_us: 100\nchecks: {max_char_latency_us: 0}\n";
    const Scenario s = load_scenario(path);
    EXPECT_EQ(s.realtime, 0);
    EXPECT_EQ(s.budget_us, 100);
    EXPECT_EQ(s.checks.max_char_latency_us, 0);
}

// 8E1: START, data bits 0..7, parity, STOP = cells 0..10 (the line model's cells through the
// first STOP bit); 5N1: data bits 0..4, cells 0..6.
TEST(ScenarioBadInput, FaultBitsAreCheckedAgainstThePortsFormat) {
    auto fault = [](const std::string& fmt, const std::string& kind, int bit) {
        return "ports:\n  - host: raw\n    format: \"" + fmt + "\"\n    faults: [{kind: " + kind +
               ", bit: " + std::to_string(bit) + "}]\n";
    };
    EXPECT_EQ(scenario_error_of("c10.yaml", fault("9600,8E1", "flip_cell", 10)), "(no error)");
    EXPECT_NE(scenario_error_of("c11.yaml", fault("9600,8E1", "flip_cell", 11)).find("c11.yaml:4: 'ports[0].faults[0].bit' = 11 is not a cell of a 9600,8E1 character (0..10)"),
              std::string::npos);
    EXPECT_EQ(scenario_error_of("d7.yaml", fault("9600,8E1", "flip_data_bit", 7)), "(no error)");
    EXPECT_NE(scenario_error_of("d8.yaml", fault("9600,8E1", "flip_data_bit", 8)).find("(0..7)"), std::string::npos);
    EXPECT_EQ(scenario_error_of("c6.yaml", fault("9600,5N1", "flip_cell", 6)), "(no error)");
    EXPECT_NE(scenario_error_of("c7.yaml", fault("9600,5N1", "flip_cell", 7)).find("(0..6)"), std::string::npos);
    EXPECT_NE(scenario_error_of("d5.yaml", fault("9600,5N1", "flip_data_bit", 5)).find("(0..4)"), std::string::npos);
}

// One CPU clock at 8 MHz is 0.125 us: the shortest slice that holds a cycle.
TEST(ScenarioBadInput, QuantumIsAtLeastOneClock) {
    EXPECT_EQ(scenario_error_of("q1.yaml", "board: {quantum_us: 0.125}\n"), "(no error)");
    EXPECT_NE(scenario_error_of("q2.yaml", "board: {quantum_us: 0.12}\n").find("q2.yaml:1: 'board.quantum_us' = 0.12 must be at least one CPU clock"),
              std::string::npos);
    EXPECT_EQ(scenario_error_of("q3.yaml", "board: {cpu_hz: 1e6, quantum_us: 1}\n"), "(no error)");
    EXPECT_NE(scenario_error_of("q4.yaml", "board: {cpu_hz: 1e6, quantum_us: 0.5}\n").find("(1 us at 1000000 Hz)"),
              std::string::npos);
}
