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

TEST(YamlMap, NonMappingIsRejected) {
    EXPECT_NE(message_of([] { YamlMap m(YAML::Load("[1, 2]"), "s.yaml", "ports."); }).find("mapping"),
              std::string::npos);
}
