// load_scenario() on bad scenario files: one ConfigError naming the file and line or the value
// (the same cases through the rcsim executable are in tests/cli/bad_input.sh).
#include "models/config_error.h"
#include "scenarios/scenario.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace rcsim;

namespace {

std::filesystem::path scratch() {
    const auto d = std::filesystem::temp_directory_path() / "rcsim_scenario_bad_input";
    std::filesystem::create_directories(d);
    return d;
}

/// Writes `text` into scratch()/name and returns the message load_scenario() throws for it.
std::string error_of(const std::string& name, const std::string& text) {
    const auto path = (scratch() / name).string();
    std::ofstream(path) << text;
    try {
        load_scenario(path);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "(no error)";
}

} // namespace

TEST(ScenarioBadInput, EmptyFileIsAnErrorButEmptyMappingRunsDefaults) {
    EXPECT_NE(error_of("empty.yaml", "").find("empty.yaml: the scenario file is empty"), std::string::npos);
    EXPECT_NE(error_of("comment.yaml", "# only a comment\n").find("the scenario file is empty"), std::string::npos);
    const auto path = (scratch() / "defaults.yaml").string();
    std::ofstream(path) << "{}\n";
    EXPECT_NO_THROW(load_scenario(path));
}

TEST(ScenarioBadInput, DirectoryIsNamed) {
    const auto dir = scratch() / "a_dir.yaml";
    std::filesystem::create_directories(dir);
    try {
        load_scenario(dir.string());
        FAIL() << "no error for a directory";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("a_dir.yaml: is a directory"), std::string::npos) << e.what();
    }
}

TEST(ScenarioBadInput, NonScalarKeysNameFileAndLine) {
    EXPECT_NE(error_of("key.yaml", "duration_s: 1\n{[a]: 1}: 2\n").find("key.yaml:2: a key in 'top level' must be a plain name"),
              std::string::npos);
    const std::string tok = error_of("tok.yaml", "ports:\n  - host: protocol\n    tokens: {[a]: 1}\n");
    EXPECT_NE(tok.find("tok.yaml:3: a token must be two characters"), std::string::npos) << tok;
}

TEST(ScenarioBadInput, TokenWeightMustBeFinite) {
    for (const char* w : {".inf", ".nan", "-1", "0"}) {
        const std::string e =
            error_of("w.yaml", std::string("ports:\n  - host: protocol\n    tokens: {EC: ") + w + ", ST: 1}\n");
        EXPECT_NE(e.find("w.yaml:3: token 'EC' must be two characters with a finite weight > 0"), std::string::npos)
            << w << ": " << e;
    }
}

TEST(ScenarioBadInput, LogOnlyForTheProtocolHost) {
    for (const char* host : {"none", "raw"}) {
        const std::string e = error_of("log.yaml", std::string("ports:\n  - host: ") + host + "\n    log: x.log\n");
        EXPECT_NE(e.find("log.yaml:3: 'ports[0].log' is the protocol host's transaction log"), std::string::npos)
            << host << ": " << e;
    }
}

TEST(ScenarioBadInput, SerialFormatNamedOnce) {
    const std::string e = error_of("fmt.yaml", "ports:\n  - host: protocol\n    format: \"99999999999,8E1\"\n");
    EXPECT_NE(e.find("fmt.yaml:3: bad serial format '99999999999,8E1'"), std::string::npos) << e;
    EXPECT_EQ(e.find("bad serial format", e.find("bad serial format") + 1), std::string::npos) << e;
    const std::string z = error_of("fmt0.yaml", "ports:\n  - host: protocol\n    format: \"0,8E1\"\n");
    EXPECT_NE(z.find("fmt0.yaml:3: bad serial format '0,8E1'"), std::string::npos) << z;
}

TEST(ScenarioBadInput, NestedNonMappingNamesTheKeyWithoutTrailingDot) {
    const std::string e = error_of("board.yaml", "board: 5\n");
    EXPECT_NE(e.find("board.yaml:1: 'board' must be a mapping"), std::string::npos) << e;
}
