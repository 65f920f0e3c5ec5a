// The sweep file: axes, zip groups, ranges, base lists, ids, key paths, shards.
#include "models/plumbing/config_error.h"
#include "scenarios/sweep/sweep.h"
#include "tests/support/files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

namespace fs = std::filesystem;
using namespace rcsim;
using namespace rcsim::sweep;

namespace {

/// A scratch directory per test, with files written from text.
class SweepTest : public ::testing::Test {
protected:
    fs::path dir;
    void SetUp() override {
        dir = rcsim::test::scratch_dir();
        write("base.yaml", "name: base\nduration_s: 0.1\nports:\n  - {host: protocol, data_size: 8}\n"
                           "  - {host: protocol, data_size: 8}\n");
    }
    std::string write(const std::string& name, const std::string& text) {
        std::ofstream(dir / name) << text;
        return (dir / name).string();
    }
    /// The message of the ConfigError that loading `text` throws ("" if none).
    std::string error_of(const std::string& text) {
        try {
            load_sweep(write("bad.yaml", text));
        } catch (const ConfigError& e) {
            return e.what();
        }
        return "";
    }
};

std::vector<std::string> ids(const Sweep& s) {
    std::vector<std::string> out;
    for (const auto& r : s.runs) out.push_back(r.id);
    return out;
}

} // namespace

TEST_F(SweepTest, GridIsEveryCombinationFirstAxisSlowest) {
    const Sweep s = load_sweep(write("s.yaml", "name: g\nbase: base.yaml\naxes:\n"
                                               "  board.wait_states.rom: [0, 2]\n  ports[*].data_size: [16, 64, 256]\n"));
    EXPECT_EQ(ids(s), (std::vector<std::string>{"g-rom=0-data_size=16", "g-rom=0-data_size=64", "g-rom=0-data_size=256",
                                                "g-rom=2-data_size=16", "g-rom=2-data_size=64", "g-rom=2-data_size=256"}));
    const SweepRun& r = s.runs[4];
    EXPECT_EQ(r.scenario["board"]["wait_states"]["rom"].as<int>(), 2);
    EXPECT_EQ(r.scenario["ports"][0]["data_size"].as<int>(), 64);
    EXPECT_EQ(r.scenario["ports"][1]["data_size"].as<int>(), 64); // [*]: every port
    EXPECT_EQ(r.scenario["name"].as<std::string>(), r.id);        // the report names the run
    ASSERT_EQ(r.parameters.size(), 2u);
    EXPECT_EQ(r.parameters[0].first, "board.wait_states.rom");
}

TEST_F(SweepTest, ZipAxesMoveTogetherAndRangesCount) {
    const Sweep s = load_sweep(write("s.yaml", "base: base.yaml\naxes:\n  seed: {range: [3, 7, 2]}\n"
                                               "zip:\n  - {board.cpu_hz: [5e6, 8e6], board.uart_clock_hz: [9216000, 18432000]}\n"));
    // seed 3, 5, 7 x two zipped pairs = 6 runs, not 3 x 2 x 2.
    ASSERT_EQ(s.runs.size(), 6u);
    EXPECT_EQ(s.runs[1].id, "base-seed=3-cpu_hz=8e6-uart_clock_hz=18432000");
    EXPECT_EQ(s.runs[5].scenario["seed"].as<int>(), 7);
}

TEST_F(SweepTest, SameLastKeyUsesTheWholePathInIds) {
    const Sweep s = load_sweep(write("s.yaml", "base: base.yaml\nzip:\n"
                                               "  - {'ports[0].data_size': [1, 2], 'ports[1].data_size': [3, 4]}\n"));
    EXPECT_EQ(s.runs[0].id, "base-ports0.data_size=1-ports1.data_size=3");
}

TEST_F(SweepTest, ListOfBaseFilesIsAnAxis) {
    write("other.yaml", "duration_s: 0.2\n");
    const Sweep s = load_sweep(write("s.yaml", "sweeps:\n  - base: [base.yaml, other.yaml]\n    axes: {seed: [1, 2]}\n"
                                               "  - {name: inline, base: {duration_s: 0.3}}\n"));
    EXPECT_EQ(ids(s), (std::vector<std::string>{"base-seed=1", "base-seed=2", "other-seed=1", "other-seed=2", "inline"}));
    EXPECT_EQ(s.runs[2].scenario["duration_s"].as<double>(), 0.2);
    EXPECT_EQ(s.runs[2].parameters[0].first, "base");
    EXPECT_EQ(s.runs[2].parameters[0].second.as<std::string>(), "other.yaml");
    EXPECT_EQ(s.runs[4].scenario["duration_s"].as<double>(), 0.3);
}

TEST_F(SweepTest, SetAppliesToEveryRunBeforeTheAxes) {
    const Sweep s = load_sweep(write("s.yaml", "set: {duration_s: 0.05, drain_s: 0}\nsweeps:\n"
                                               "  - {base: base.yaml, set: {seed: 9}, axes: {drain_s: [0.5]}}\n"));
    ASSERT_EQ(s.runs.size(), 1u);
    EXPECT_EQ(s.runs[0].scenario["duration_s"].as<double>(), 0.05);
    EXPECT_EQ(s.runs[0].scenario["seed"].as<int>(), 9);
    EXPECT_EQ(s.runs[0].scenario["drain_s"].as<double>(), 0.5); // the axis wins over set
}

TEST_F(SweepTest, RelativeInputFilesBecomeAbsoluteOutputsStayRelative) {
    fs::create_directories(dir / "sub");
    write("sub/b.yaml", "rom: my.rom\nports:\n  - {host: replay, file: s.log}\n  - {host: protocol, log: h.log}\n");
    const Sweep s = load_sweep(write("s.yaml", "base: sub/b.yaml\n"));
    const YAML::Node sc = s.runs[0].scenario;
    EXPECT_EQ(sc["rom"].as<std::string>(), (fs::absolute(dir) / "sub/my.rom").lexically_normal().string());
    EXPECT_EQ(sc["ports"][0]["file"].as<std::string>(), (fs::absolute(dir) / "sub/s.log").lexically_normal().string());
    EXPECT_EQ(sc["ports"][1]["log"].as<std::string>(), "h.log"); // lands in the run directory
}

TEST_F(SweepTest, AStructuredTextProgramBecomesAbsolute) {
    fs::create_directories(dir / "sub");
    write("sub/m.yaml", "motion:\n  program: st/p.st\n");
    write("sub/b.yaml", "main_cpu:\n  program: q.st\n");
    const Sweep s = load_sweep(write("s.yaml", "sweeps:\n  - {base: sub/m.yaml}\n  - {base: sub/b.yaml}\n"));
    EXPECT_EQ(s.runs[0].scenario["motion"]["program"].as<std::string>(),
              (fs::absolute(dir) / "sub/st/p.st").lexically_normal().string());
    EXPECT_EQ(s.runs[1].scenario["main_cpu"]["program"].as<std::string>(),
              (fs::absolute(dir) / "sub/q.st").lexically_normal().string());
}

TEST_F(SweepTest, BadSweepFilesNameFileAndLine) {
    EXPECT_NE(error_of("base: base.yaml\naxes:\n  seed: [1, 2]\nzip:\n  - {seed: [1, 2], drain_s: [1]}\n")
                  .find("bad.yaml:5: zip axis 'drain_s' has 1 values, 'seed' has 2"),
              std::string::npos);
    EXPECT_NE(error_of("base: base.yaml\naxis: {seed: [1]}\n").find("bad.yaml:2: unknown key 'axis'"), std::string::npos);
    EXPECT_NE(error_of("base: base.yaml\naxes:\n  seed: 5\n").find("bad.yaml:3: axis 'seed': values must be a non-empty list"),
              std::string::npos);
    EXPECT_NE(error_of("base: base.yaml\naxes:\n  seed: [[1]]\n").find("bad.yaml:3: axis 'seed': a value must be a scalar"),
              std::string::npos);
    EXPECT_NE(error_of("base: base.yaml\naxes:\n  seed: {range: [5, 1]}\n").find("bad.yaml:3: axis 'seed': range step"),
              std::string::npos);
    EXPECT_NE(error_of("base: base.yaml\naxes:\n\n  ports[5].data_size: [1]\n")
                  .find("bad.yaml:4: run 'base-data_size=1': 'ports[5].data_size': 'ports' has 2 elements, no [5]"),
              std::string::npos);
    EXPECT_NE(error_of("base: base.yaml\naxes:\n  duration_s.x: [1]\n").find("bad.yaml:3: run"), std::string::npos);
    EXPECT_NE(error_of("base: missing.yaml\n").find("missing.yaml: cannot open"), std::string::npos);
    EXPECT_NE(error_of("axes: {seed: [1]}\n").find("bad.yaml:1: missing required key 'base'"), std::string::npos);
    EXPECT_NE(error_of("sweeps:\n  - {base: base.yaml}\n  - {base: base.yaml}\n").find("bad.yaml:3: two runs have the id 'base'"),
              std::string::npos);
    EXPECT_NE(error_of("base: base.yaml\nsweeps: []\n").find("bad.yaml:1: 'base' belongs inside an entry"), std::string::npos);
    EXPECT_NE(error_of("base: base.yaml\naxes: [1]\n").find("bad.yaml:2: 'axes' must map"), std::string::npos);
}

TEST_F(SweepTest, MaterialisedScenarioIsCheckedAndNamesTheSweepLine) {
    const Sweep s = load_sweep(write("s.yaml", "base: base.yaml\n\naxes:\n  board.wait_states.rom: [1, 99]\n"));
    materialise(s, s.runs[0], dir / "out");
    EXPECT_TRUE(fs::exists(dir / "out" / s.runs[0].id / "scenario.yaml"));
    EXPECT_TRUE(fs::exists(dir / "out" / s.runs[0].id / "run.json"));
    try {
        materialise(s, s.runs[1], dir / "out");
        FAIL() << "wait_states.rom 99 is out of range [0, 64]";
    } catch (const ConfigError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("s.yaml:4: run 'base-rom=99': "), std::string::npos) << m; // the axis's line
        EXPECT_NE(m.find("'board.wait_states.rom' = 99 must be a whole number in [0, 64]"), std::string::npos) << m;
    }
}

TEST_F(SweepTest, RefusedValueOfAStarAxisOrSetNamesItsLine) {
    const Sweep s = load_sweep(write("s.yaml", "base: base.yaml\nset:\n  drain_s: -1\naxes:\n  ports[*].data_size: [9999]\n"));
    auto error = [&](const SweepRun& r) {
        try {
            materialise(s, r, dir / "out");
        } catch (const ConfigError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    // drain_s -1 is refused first (the scenario reads it before the ports): the set: line.
    EXPECT_NE(error(s.runs[0]).find("s.yaml:3: run"), std::string::npos) << error(s.runs[0]);
    const Sweep t = load_sweep(write("t.yaml", "base: base.yaml\naxes:\n  seed: [1]\n  ports[*].data_size: [9999]\n"));
    try {
        materialise(t, t.runs[0], dir / "out");
        FAIL() << "data_size 9999 is out of range";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("t.yaml:4: run"), std::string::npos) << e.what(); // ports[0].data_size
    }
}

TEST_F(SweepTest, StaleRunsOfAnEarlierSweepAreRemoved) {
    const Sweep s = load_sweep(write("s.yaml", "base: base.yaml\naxes: {seed: [1]}\n"));
    fs::create_directories(dir / "out/old");
    std::ofstream(dir / "out/old/run.json") << "{}";
    fs::create_directories(dir / "out/notes"); // no run.json: not ours
    materialise(s, s.runs[0], dir / "out");
    remove_stale_runs(s, dir / "out");
    EXPECT_FALSE(fs::exists(dir / "out/old"));
    EXPECT_TRUE(fs::exists(dir / "out/notes"));
    EXPECT_TRUE(fs::exists(dir / "out/base-seed=1"));
}

TEST(SetPath, CreatesMappingsIndexesListsAndRefusesWhatDoesNotFit) {
    YAML::Node doc = YAML::Load("ports: [{a: 1}, {a: 2}]\nx: 5\n");
    set_path(doc, "board.wait_states.rom", YAML::Node(3));
    EXPECT_EQ(doc["board"]["wait_states"]["rom"].as<int>(), 3);
    set_path(doc, "ports[1].a", YAML::Node(7));
    EXPECT_EQ(doc["ports"][0]["a"].as<int>(), 1);
    EXPECT_EQ(doc["ports"][1]["a"].as<int>(), 7);
    set_path(doc, "ports[*].b", YAML::Node(4));
    EXPECT_EQ(doc["ports"][0]["b"].as<int>(), 4);
    EXPECT_EQ(doc["ports"][1]["b"].as<int>(), 4);
    EXPECT_THROW(set_path(doc, "ports[2].a", YAML::Node(1)), std::invalid_argument);
    EXPECT_THROW(set_path(doc, "x.y", YAML::Node(1)), std::invalid_argument);
    EXPECT_THROW(set_path(doc, "x[0]", YAML::Node(1)), std::invalid_argument);
    EXPECT_THROW(set_path(doc, "ports[a].b", YAML::Node(1)), std::invalid_argument);
    EXPECT_THROW(set_path(doc, "a.", YAML::Node(1)), std::invalid_argument);
}

TEST(ScalarJson, NumbersBooleansAndQuotedStrings) {
    EXPECT_EQ(scalar_json(YAML::Load("16")), nlohmann::json(16));
    EXPECT_TRUE(scalar_json(YAML::Load("16")).is_number_integer());
    EXPECT_EQ(scalar_json(YAML::Load("5e6")), nlohmann::json(5e6));
    EXPECT_EQ(scalar_json(YAML::Load("true")), nlohmann::json(true));
    EXPECT_EQ(scalar_json(YAML::Load("'16'")), nlohmann::json("16"));
    EXPECT_EQ(scalar_json(YAML::Load("9600,8E1")), nlohmann::json("9600,8E1"));
}

TEST(Shard, FromArgumentSlurmAndKubernetes) {
    std::map<std::string, std::string> env;
    auto get = [&env](const char* k) { return env.count(k) ? env[k].c_str() : nullptr; };
    EXPECT_EQ(shard_from("", std::nullopt, get).count, 1u);
    Shard s = shard_from("2/5", std::nullopt, get);
    EXPECT_EQ(s.index, 2u);
    EXPECT_EQ(s.count, 5u);
    env = {{"SLURM_ARRAY_TASK_ID", "4"}, {"SLURM_ARRAY_TASK_COUNT", "4"}, {"SLURM_ARRAY_TASK_MIN", "1"}};
    s = shard_from("", std::nullopt, get); // --array=1-4: task 4 is the last of four
    EXPECT_EQ(s.index, 3u);
    EXPECT_EQ(s.count, 4u);
    EXPECT_EQ(shard_from("0/2", std::nullopt, get).count, 2u); // --shard wins over the environment
    env = {{"JOB_COMPLETION_INDEX", "1"}};
    s = shard_from("", 3, get);
    EXPECT_EQ(s.index, 1u);
    EXPECT_EQ(s.count, 3u);
    EXPECT_EQ(shard_from("", std::nullopt, get).count, 1u); // an index without --shards: no shard
    env.clear();
    EXPECT_THROW(shard_from("", 3, get), ConfigError); // --shards without an index
    EXPECT_THROW(shard_from("3/3", std::nullopt, get), ConfigError);
    EXPECT_THROW(shard_from("1/0", std::nullopt, get), ConfigError);
    EXPECT_THROW(shard_from("1", std::nullopt, get), ConfigError);
    EXPECT_THROW(shard_from("-1/2", std::nullopt, get), ConfigError);
    env = {{"SLURM_ARRAY_TASK_ID", "x"}, {"SLURM_ARRAY_TASK_COUNT", "2"}};
    EXPECT_THROW(shard_from("", std::nullopt, get), ConfigError);
}

TEST(Shard, UnionOfAllShardsIsEveryRunOnce) {
    for (std::size_t total : {0u, 1u, 7u, 20u})
        for (std::size_t n : {1u, 3u, 8u, 25u}) {
            std::multiset<std::size_t> seen;
            for (std::size_t k = 0; k < n; ++k)
                for (std::size_t i : shard_runs(total, {k, n})) seen.insert(i);
            ASSERT_EQ(seen.size(), total) << total << " runs, " << n << " shards";
            for (std::size_t i = 0; i < total; ++i) EXPECT_EQ(seen.count(i), 1u);
        }
}

TEST(ShellQuote, QuotesOnlyWhatNeedsIt) {
    EXPECT_EQ(shell_quote("/a/b-rom=1.yaml"), "/a/b-rom=1.yaml");
    EXPECT_EQ(shell_quote("a b"), "'a b'");
    EXPECT_EQ(shell_quote("it's"), "'it'\\''s'");
    EXPECT_EQ(shell_quote(""), "''");
}

TEST_F(SweepTest, ExpectFailOnAnEntryAppliesToEveryRunAndGoesToRunJson) {
    const Sweep s = load_sweep(write("s.yaml", "sweeps:\n  - name: f\n    base: base.yaml\n"
                                               "    expect_fail: [frames_failed, commands_delivered_exactly_once]\n"
                                               "    axes: {seed: [1, 2]}\n  - {name: g, base: base.yaml}\n"));
    ASSERT_EQ(s.runs.size(), 3u);
    const std::vector<std::string> both{"commands_delivered_exactly_once", "frames_failed"}; // sorted
    EXPECT_EQ(s.runs[0].expect_fail, both);
    EXPECT_EQ(s.runs[1].expect_fail, both);
    EXPECT_TRUE(s.runs[2].expect_fail.empty());
    EXPECT_EQ(run_json(s.runs[0])["expect_fail"], nlohmann::json(both));
    EXPECT_FALSE(run_json(s.runs[2]).contains("expect_fail")); // run.json of other runs unchanged
}

TEST_F(SweepTest, ExpectFailWhenAppliesOnlyToRunsWithThatAxisValue) {
    const Sweep s = load_sweep(write("s.yaml", "name: g\nbase: base.yaml\nexpect_fail: [overruns]\naxes:\n"
                                               "  board.wait_states.rom: [0, 2]\n  seed: [1, 2]\nexpect_fail_when:\n"
                                               "  - {axis: board.wait_states.rom, value: 2, checks: [table3_margin_us]}\n"
                                               "  - {axis: seed, value: 1, checks: [port1_char_latency_max_us]}\n"));
    std::map<std::string, std::vector<std::string>> by_id;
    for (const auto& r : s.runs) by_id[r.id] = r.expect_fail;
    using names = std::vector<std::string>;
    EXPECT_EQ(by_id["g-rom=0-seed=1"], (names{"overruns", "port1_char_latency_max_us"}));
    EXPECT_EQ(by_id["g-rom=0-seed=2"], (names{"overruns"}));
    EXPECT_EQ(by_id["g-rom=2-seed=1"], (names{"overruns", "port1_char_latency_max_us", "table3_margin_us"}));
    EXPECT_EQ(by_id["g-rom=2-seed=2"], (names{"overruns", "table3_margin_us"}));
    // The base as an axis: `axis: base`, the file as written.
    write("other.yaml", "duration_s: 0.1\nports:\n  - {host: protocol}\n");
    const Sweep b = load_sweep(write("b.yaml", "sweeps:\n  - base: [base.yaml, other.yaml]\n    expect_fail_when:\n"
                                               "      - {axis: base, value: other.yaml, checks: [bus_errors]}\n"));
    ASSERT_EQ(b.runs.size(), 2u);
    EXPECT_TRUE(b.runs[0].expect_fail.empty());
    EXPECT_EQ(b.runs[1].expect_fail, (names{"bus_errors"}));
}

TEST_F(SweepTest, ExpectFailOfAnUnknownCheckNamesFileLineAndName) {
    EXPECT_NE(error_of("base: base.yaml\nexpect_fail:\n  - frames_failed\n  - frames_faild\n")
                  .find("bad.yaml:4: 'expect_fail': 'frames_faild' is not a check name"),
              std::string::npos);
    EXPECT_NE(error_of("base: base.yaml\naxes: {seed: [1]}\nexpect_fail_when:\n  - {axis: seed, value: 1, checks: [nope]}\n")
                  .find("bad.yaml:4: 'expect_fail_when.checks': 'nope' is not a check name"),
              std::string::npos);
    // char_latency_max_us switches the per-port checks off; a report names them port<n>_...
    EXPECT_NE(error_of("base: base.yaml\nexpect_fail: [char_latency_max_us]\n").find("bad.yaml:2: "), std::string::npos);
    EXPECT_NE(error_of("base: base.yaml\nexpect_fail: frames_failed\n").find("bad.yaml:2: 'expect_fail' must be a non-empty list"),
              std::string::npos);
    EXPECT_NE(error_of("base: base.yaml\naxes: {seed: [1]}\nexpect_fail_when:\n  - {axis: sead, value: 1, checks: [overruns]}\n")
                  .find("bad.yaml:4: expect_fail_when: 'sead' is not an axis of this entry"),
              std::string::npos);
    EXPECT_NE(error_of("base: base.yaml\naxes: {seed: [1]}\nexpect_fail_when:\n  - {axis: seed, value: 3, checks: [overruns]}\n")
                  .find("bad.yaml:4: expect_fail_when: '3' is not a value of the axis 'seed'"),
              std::string::npos);
    EXPECT_NE(error_of("sweeps:\n  - {base: base.yaml}\nexpect_fail: [overruns]\n").find("bad.yaml:3: 'expect_fail' belongs inside an entry"),
              std::string::npos);
}

TEST_F(SweepTest, ASearchEntryIsOneRunThatRunsRcsimSearch) {
    const Sweep s = load_sweep(write("s.yaml", "sweeps:\n"
                                               "  - name: worst\n    base: base.yaml\n"
                                               "    search: {maximize: interrupts.rs232_0.latency_us.max, runs: 12, seed: 3}\n"
                                               "  - {name: plain, base: base.yaml}\n"));
    ASSERT_EQ(s.runs.size(), 2u);
    const SweepRun& w = s.runs[0];
    ASSERT_TRUE(w.search);
    EXPECT_FALSE(s.runs[1].search);
    const auto argv = run_argv("rcsim", dir, w, "");
    const std::vector<std::string> want{"rcsim", "search", (dir / "worst" / "scenario.yaml").string(), "--maximize",
                                        "interrupts.rs232_0.latency_us.max", "--runs", "12", "--seed", "3", "--jobs", "1",
                                        "--out", (dir / "worst").string(), "--reproducible", "--as-run"};
    EXPECT_EQ(argv, want);
    const nlohmann::json j = run_json(w);
    EXPECT_EQ(j["search"]["figure"], "interrupts.rs232_0.latency_us.max");
    EXPECT_EQ(j["search"]["direction"], "maximize");
    EXPECT_EQ(j["search"]["runs"], 12);
    EXPECT_EQ(run_argv("rcsim", dir, s.runs[1], "")[1], "run");
}

TEST_F(SweepTest, ASearchEntryNamesOneFigureAndTakesNoAxes) {
    EXPECT_NE(error_of("base: base.yaml\nsearch: {runs: 4}\n").find("one of 'maximize: FIGURE' and 'minimize: FIGURE'"),
              std::string::npos);
    EXPECT_NE(error_of("base: base.yaml\nsearch: {maximize: a, minimize: b}\n").find("one of"), std::string::npos);
    const std::string axes = error_of("base: base.yaml\naxes: {seed: [1, 2]}\nsearch: {maximize: a}\n");
    EXPECT_NE(axes.find("bad.yaml:3:"), std::string::npos) << axes;
    EXPECT_NE(axes.find("takes no axes"), std::string::npos) << axes;
    EXPECT_NE(error_of("base: base.yaml\nsearch: {maximize: a, runs: 1}\n").find("runs"), std::string::npos);
    EXPECT_NE(error_of("base: base.yaml\nsearch: {maximize: a, budget: 4}\n").find("budget"), std::string::npos);
}
