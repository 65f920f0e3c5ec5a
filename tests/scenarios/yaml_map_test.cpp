#include "scenarios/yaml_map.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace rcsim;

namespace {
std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}
} // namespace

TEST(YamlMap, ReadsTypedValuesWithDefaults) {
    YamlMap m(YAML::Load("duration_s: 2.5\nseed: 7\n"), "s.yaml", "");
    EXPECT_DOUBLE_EQ(m.get<double>("duration_s", 1.0), 2.5);
    EXPECT_EQ(m.get<int>("seed", 0), 7);
    EXPECT_EQ(m.get<std::string>("name", "x"), "x");
    m.finish();
}

TEST(YamlMap, BadValueNamesFileLineAndKey) {
    const std::string msg = message_of([] {
        YamlMap m(YAML::Load("a: 1\nseed: banana\n"), "s.yaml", "");
        m.get<int>("a", 0);
        m.get<int>("seed", 0);
    });
    EXPECT_NE(msg.find("s.yaml:2:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("seed"), std::string::npos) << msg;
    EXPECT_NE(msg.find("banana"), std::string::npos) << msg;
}

TEST(YamlMap, UnknownKeyIsRejected) {
    const std::string msg = message_of([] {
        YamlMap m(YAML::Load("ports:\n  baud: 9600\n  badu: 1\n"), "s.yaml", "");
        YamlMap p = m.map("ports");
        p.get<int>("baud", 0);
        p.finish();
    });
    EXPECT_NE(msg.find("s.yaml:3:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("ports.badu"), std::string::npos) << msg;
}

TEST(YamlMap, RangeCheckNamesValue) {
    const std::string msg = message_of([] {
        YamlMap m(YAML::Load("baud: -5\n"), "s.yaml", "");
        m.number("baud", 9600, 50, 1e6);
    });
    EXPECT_NE(msg.find("s.yaml:1:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("-5"), std::string::npos) << msg;
}

TEST(YamlMap, SyntaxErrorNamesLine) {
    const auto path = std::filesystem::temp_directory_path() / "rcsim_yaml_map_bad.yaml";
    std::ofstream(path) << "a: 1\nb: [1, 2\n";
    const std::string msg = message_of([&] { load_yaml_file(path.string()); });
    EXPECT_NE(msg.find("rcsim_yaml_map_bad.yaml:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("syntax"), std::string::npos) << msg;
    EXPECT_NE(message_of([] { load_yaml_file("/nonexistent/x.yaml"); }).find("cannot open"), std::string::npos);
}

TEST(YamlMap, NonScalarKeyIsNamedByItsMappingsPath) {
    YamlMap top(YAML::Load("motion:\n  a: 1\n  {[x]: 1}: 2\n"), "s.yaml", "");
    YamlMap m = top.map("motion");
    m.get<int>("a", 0);
    EXPECT_EQ(message_of([&] { m.finish(); }), "s.yaml:3: a key in 'motion' must be a plain name, not '{[x]: 1}'");
}

TEST(YamlMap, NonMappingIsRejected) {
    EXPECT_NE(message_of([] { YamlMap m(YAML::Load("[1, 2]"), "s.yaml", "ports."); }).find("mapping"),
              std::string::npos);
}

TEST(YamlMap, RequireNumberNamesTheMissingKeyAtItsMapping) {
    YamlMap top(YAML::Load("motion:\n  control_cycle_ms: 1\n"), "s.yaml", "");
    YamlMap m = top.map("motion");
    EXPECT_DOUBLE_EQ(m.require_number("control_cycle_ms", 0, 10), 1.0);
    EXPECT_EQ(message_of([&] { m.require_number("duration_s", 0, 10); }),
              "s.yaml:2: missing required key 'motion.duration_s'");
    YamlMap r(YAML::Load("a: 1\nb: 11\n"), "s.yaml", "");
    EXPECT_EQ(message_of([&] { r.require_number("b", 0, 10); }), "s.yaml:2: 'b' = 11 is out of range [0, 10]");
}

TEST(YamlMap, ChoiceAcceptsOnlyTheNamedValues) {
    YamlMap m(YAML::Load("dir: cw\nmode: up\nside: top\n"), "s.yaml", "move.");
    EXPECT_EQ(m.choice("dir", "ccw", {"cw", "ccw"}), "cw");
    EXPECT_EQ(m.choice("absent", "ccw", {"cw", "ccw"}), "ccw");
    EXPECT_EQ(message_of([&] { m.choice("mode", "a", {"a", "b"}); }),
              "s.yaml:2: 'move.mode' must be 'a' or 'b', got 'up'");
    EXPECT_EQ(message_of([&] { m.choice("side", "left", {"left", "right", "bottom"}); }),
              "s.yaml:3: 'move.side' must be 'left', 'right' or 'bottom', got 'top'");
    m.finish(); // every key was read by choice()
}

TEST(YamlMap, ListReadsScalarsAndNamesTheBadElement) {
    YamlMap m(YAML::Load("p: [3, -4]\nq:\n  - 1\n  - x\nr: 5\ns: [1, 2, 3]\nt: [[1]]\n"), "s.yaml", "c.");
    EXPECT_EQ(m.list<long>("p"), (std::vector<long>{3, -4}));
    EXPECT_TRUE(m.list<long>("absent").empty());
    EXPECT_EQ(message_of([&] { m.list<long>("q"); }), "s.yaml:4: bad value for 'c.q[1]': 'x'");
    EXPECT_EQ(message_of([&] { m.list<long>("r"); }), "s.yaml:5: 'c.r' must be a list of values");
    EXPECT_EQ(message_of([&] { m.list<long>("s", 2); }), "s.yaml:6: 'c.s' must be a list of at most 2 values");
    EXPECT_EQ(message_of([&] { m.list<std::string>("t"); }), "s.yaml:7: bad value for 'c.t[0]': '[1]'");
    m.finish();
}

TEST(YamlMap, MapsNameEachElementByIndex) {
    YamlMap m(YAML::Load("cmds:\n  - {a: 1}\n  - {a: 2, b: 3}\nbad: [1]\nlong: [{}, {}]\n"), "s.yaml", "");
    std::vector<YamlMap> cmds = m.maps("cmds");
    ASSERT_EQ(cmds.size(), 2u);
    EXPECT_EQ(cmds[0].get<int>("a", 0), 1);
    cmds[0].finish();
    EXPECT_EQ(cmds[1].get<int>("a", 0), 2);
    EXPECT_EQ(message_of([&] { cmds[1].finish(); }), "s.yaml:3: unknown key 'cmds[1].b'");
    EXPECT_EQ(message_of([&] { m.maps("bad"); }), "s.yaml:4: 'bad[0]' must be a mapping");
    EXPECT_EQ(message_of([&] { m.maps("long", 1); }), "s.yaml:5: 'long' must be a list of at most 1 mappings");
    EXPECT_TRUE(m.maps("absent").empty());
    m.finish();
}
