#include "scenarios/config/yaml_map.h"
#include "tests/support/files.h"
#include "tests/support/scenario_error.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace rcsim;

using rcsim::test::config_error_of;

TEST(YamlMap, ReadsTypedValuesWithDefaults) {
    YamlMap m(YAML::Load("duration_s: 2.5\nseed: 7\n"), "s.yaml", "");
    EXPECT_DOUBLE_EQ(m.get<double>("duration_s", 1.0), 2.5);
    EXPECT_EQ(m.get<int>("seed", 0), 7);
    EXPECT_EQ(m.get<std::string>("name", "x"), "x");
    m.finish();
}

TEST(YamlMap, BadValueNamesFileLineAndKey) {
    const std::string msg = config_error_of([] {
        YamlMap m(YAML::Load("a: 1\nseed: banana\n"), "s.yaml", "");
        m.get<int>("a", 0);
        m.get<int>("seed", 0);
    });
    EXPECT_NE(msg.find("s.yaml:2:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("seed"), std::string::npos) << msg;
    EXPECT_NE(msg.find("banana"), std::string::npos) << msg;
}

TEST(YamlMap, UnknownKeyIsRejected) {
    const std::string msg = config_error_of([] {
        YamlMap m(YAML::Load("ports:\n  baud: 9600\n  badu: 1\n"), "s.yaml", "");
        YamlMap p = m.map("ports");
        p.get<int>("baud", 0);
        p.finish();
    });
    EXPECT_NE(msg.find("s.yaml:3:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("ports.badu"), std::string::npos) << msg;
}

TEST(YamlMap, RangeCheckNamesValue) {
    const std::string msg = config_error_of([] {
        YamlMap m(YAML::Load("baud: -5\n"), "s.yaml", "");
        m.number("baud", 9600, 50, 1e6);
    });
    EXPECT_NE(msg.find("s.yaml:1:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("-5"), std::string::npos) << msg;
}

TEST(YamlMap, SyntaxErrorNamesLine) {
    const auto path = rcsim::test::scratch_dir() / "yaml_map_bad.yaml";
    std::ofstream(path) << "a: 1\nb: [1, 2\n";
    const std::string msg = config_error_of([&] { load_yaml_file(path.string()); });
    EXPECT_NE(msg.find("yaml_map_bad.yaml:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("syntax"), std::string::npos) << msg;
    EXPECT_NE(config_error_of([] { load_yaml_file("/nonexistent/x.yaml"); }).find("cannot open"), std::string::npos);
}

TEST(YamlMap, NonScalarKeyIsNamedByItsMappingsPath) {
    YamlMap top(YAML::Load("motion:\n  a: 1\n  {[x]: 1}: 2\n"), "s.yaml", "");
    YamlMap m = top.map("motion");
    m.get<int>("a", 0);
    EXPECT_EQ(config_error_of([&] { m.finish(); }), "s.yaml:3: a key in 'motion' must be a plain name, not '{[x]: 1}'");
}

TEST(YamlMap, NonMappingIsRejected) {
    EXPECT_NE(config_error_of([] { YamlMap m(YAML::Load("[1, 2]"), "s.yaml", "ports."); }).find("mapping"),
              std::string::npos);
}

TEST(YamlMap, RequireNumberNamesTheMissingKeyAtItsMapping) {
    YamlMap top(YAML::Load("motion:\n  control_cycle_ms: 1\n"), "s.yaml", "");
    YamlMap m = top.map("motion");
    EXPECT_DOUBLE_EQ(m.require_number("control_cycle_ms", 0, 10), 1.0);
    EXPECT_EQ(config_error_of([&] { m.require_number("duration_s", 0, 10); }),
              "s.yaml:2: missing required key 'motion.duration_s'");
    YamlMap r(YAML::Load("a: 1\nb: 11\n"), "s.yaml", "");
    EXPECT_EQ(config_error_of([&] { r.require_number("b", 0, 10); }), "s.yaml:2: 'b' = 11 is out of range [0, 10]");
}

TEST(YamlMap, ChoiceAcceptsOnlyTheNamedValues) {
    YamlMap m(YAML::Load("dir: cw\nmode: up\nside: top\n"), "s.yaml", "move.");
    EXPECT_EQ(m.choice("dir", "ccw", {"cw", "ccw"}), "cw");
    EXPECT_EQ(m.choice("absent", "ccw", {"cw", "ccw"}), "ccw");
    EXPECT_EQ(config_error_of([&] { m.choice("mode", "a", {"a", "b"}); }),
              "s.yaml:2: 'move.mode' must be 'a' or 'b', got 'up'");
    EXPECT_EQ(config_error_of([&] { m.choice("side", "left", {"left", "right", "bottom"}); }),
              "s.yaml:3: 'move.side' must be 'left', 'right' or 'bottom', got 'top'");
    m.finish(); // every key was read by choice()
}

TEST(YamlMap, ListReadsScalarsAndNamesTheBadElement) {
    YamlMap m(YAML::Load("p: [3, -4]\nq:\n  - 1\n  - x\nr: 5\ns: [1, 2, 3]\nt: [[1]]\n"), "s.yaml", "c.");
    EXPECT_EQ(m.list<long>("p"), (std::vector<long>{3, -4}));
    EXPECT_TRUE(m.list<long>("absent").empty());
    EXPECT_EQ(config_error_of([&] { m.list<long>("q"); }), "s.yaml:4: bad value for 'c.q[1]': 'x'");
    EXPECT_EQ(config_error_of([&] { m.list<long>("r"); }), "s.yaml:5: 'c.r' must be a list of values");
    EXPECT_EQ(config_error_of([&] { m.list<long>("s", 2); }), "s.yaml:6: 'c.s' must be a list of at most 2 values");
    EXPECT_EQ(config_error_of([&] { m.list<std::string>("t"); }), "s.yaml:7: bad value for 'c.t[0]': '[1]'");
    m.finish();
}

TEST(YamlMap, MapsNameEachElementByIndex) {
    YamlMap m(YAML::Load("cmds:\n  - {a: 1}\n  - {a: 2, b: 3}\nbad: [1]\nlong: [{}, {}]\n"), "s.yaml", "");
    std::vector<YamlMap> cmds = m.maps("cmds");
    ASSERT_EQ(cmds.size(), 2u);
    EXPECT_EQ(cmds[0].get<int>("a", 0), 1);
    cmds[0].finish();
    EXPECT_EQ(cmds[1].get<int>("a", 0), 2);
    EXPECT_EQ(config_error_of([&] { cmds[1].finish(); }), "s.yaml:3: unknown key 'cmds[1].b'");
    EXPECT_EQ(config_error_of([&] { m.maps("bad"); }), "s.yaml:4: 'bad[0]' must be a mapping");
    EXPECT_EQ(config_error_of([&] { m.maps("long", 1); }), "s.yaml:5: 'long' must be a list of at most 1 mappings");
    EXPECT_TRUE(m.maps("absent").empty());
    m.finish();
}

namespace {
/// load_yaml_file() on `text`; the message it throws, "" when none.
std::string load_error(const std::string& text) {
    const auto path = rcsim::test::scratch_dir() / "strict.yaml";
    std::ofstream(path) << text;
    return config_error_of([&] { load_yaml_file(path.string()); });
}
} // namespace

// yaml-cpp keeps both entries of a duplicated key and a lookup takes the first; the reader must
// refuse the file instead, at every depth and in flow mappings too.
TEST(YamlMap, DuplicateKeysAreErrorsAtTheSecondOccurrence) {
    EXPECT_NE(load_error("a: 1\nb: 2\na: 3\n").find("strict.yaml:3: duplicate key 'a' (first at line 1)"),
              std::string::npos);
    EXPECT_NE(load_error("x:\n  - {k: 1, k: 2}\n").find("strict.yaml:2: duplicate key 'k' (twice on this line)"),
              std::string::npos);
    EXPECT_NE(load_error("x:\n  y:\n    z: 1\n    z: 1\n").find("strict.yaml:4: duplicate key 'z'"), std::string::npos);
    EXPECT_EQ(load_error("a: 1\nb: {a: 2}\nc: [{a: 3}, {a: 4}]\n"), ""); // same name, different mappings
}

// An alias is its anchor's node: checked once, so a file of nested aliases stays linear.
TEST(YamlMap, AliasesAreCheckedOnce) {
    std::string text = "a0: &a0 {k: 1}\n";
    for (int i = 1; i < 30; ++i)
        text += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [*a" + std::to_string(i - 1) + ", *a" +
                std::to_string(i - 1) + "]\n"; // 2^29 paths through the aliases
    EXPECT_EQ(load_error(text), "");
}

TEST(YamlMap, SecondDocumentIsAnError) {
    EXPECT_NE(load_error("a: 1\n---\na: 2\n").find("strict.yaml:3: a second YAML document"), std::string::npos);
    EXPECT_EQ(load_error("---\na: 1\n"), ""); // one document with its start marker
}

TEST(YamlMap, InputMustBeARegularFileOfBoundedSize) {
    EXPECT_NE(config_error_of([] { load_yaml_file("/dev/zero"); }).find("/dev/zero: is not a regular file"),
              std::string::npos);
    const auto big = rcsim::test::scratch_dir() / "yaml_map_big.yaml";
    std::ofstream(big) << "a: 1\n";
    std::filesystem::resize_file(big, kMaxYamlFileBytes + 1);
    EXPECT_NE(config_error_of([&] { load_yaml_file(big.string()); }).find("a scenario file is at most 4194304 bytes"),
              std::string::npos);
    std::filesystem::remove(big);
}

TEST(YamlMap, IntegerRejectsFractionsAndOutOfRange) {
    YamlMap m(YAML::Load("a: 1.7\nb: 8e3\nc: -1\nd: .nan\n"), "s.yaml", "");
    EXPECT_EQ(config_error_of([&] { m.integer("a", 0, 0, 10); }), "s.yaml:1: 'a' = 1.7 must be a whole number in [0, 10]");
    EXPECT_EQ(m.integer("b", 0, 0, 10000), 8000u); // an exponent is fine when the value is whole
    EXPECT_NE(config_error_of([&] { m.integer("c", 0, 0, 10); }).find("s.yaml:3:"), std::string::npos);
    EXPECT_NE(config_error_of([&] { m.integer("d", 0, 0, 10); }).find("s.yaml:4:"), std::string::npos);
    EXPECT_EQ(m.integer("absent", 7, 0, 10), 7u);
}
