// Merging run directories: flattening, the summary files, order and split independence.
#include "tests/support/files.h"
#include "models/plumbing/config_error.h"
#include "scenarios/sweep/merge.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace rcsim;
using namespace rcsim::sweep;
using json = nlohmann::json;

namespace {

using rcsim::test::slurp;

/// A run directory as rcsim sweep leaves it: run.json and report.json.
void make_run(const fs::path& dir, const std::string& id, double margin, bool passed, long rom) {
    fs::create_directories(dir / id);
    std::ofstream(dir / id / "run.json") << json{{"id", id}, {"entry", "g"}, {"parameters", {{"board.wait_states.rom", rom}}}};
    const json report = {{"scenario", id},
                         {"seed", 1},
                         {"table3", {{"margin_us", margin}, {"dpram_byte_us", nullptr}, {"not_measured", {{"x", "why"}}}}},
                         {"ports", json::array({{{"frames_delivered", 4}, {"overruns", 0}}, {{"frames_delivered", 5}, {"overruns", 1}}})},
                         {"checks", json::array({{{"name", "overruns"}, {"passed", passed}, {"value", 1}, {"limit", 0}}})},
                         {"checks_off", json::array({"frames_failed"})},
                         {"passed", passed}};
    std::ofstream(dir / id / "report.json") << report.dump(2);
}

} // namespace

TEST(Flatten, ScalarsByPathWithoutStringsOrChecks) {
    const json r = {{"a", {{"b", 1.5}, {"s", "text"}, {"n", nullptr}, {"t", true}}},
                    {"ports", json::array({{{"x", 1}}, {{"x", 2}}})},
                    {"checks", json::array({{{"name", "c"}, {"passed", true}}})},
                    {"passed", true}};
    const Figures f = flatten_figures(r);
    ASSERT_EQ(f.size(), 5u);
    EXPECT_EQ(f[0].first, "a.b");
    EXPECT_EQ(f[1].first, "a.n");
    EXPECT_TRUE(f[1].second.is_null()); // "not measured" is a figure too
    EXPECT_EQ(f[2].first, "a.t");
    EXPECT_EQ(f[3].first, "ports[0].x");
    EXPECT_EQ(f[4].second, json(2));
    const auto checks = report_checks(r);
    ASSERT_EQ(checks.size(), 1u);
    EXPECT_EQ(checks[0].first, "c");
}

// The latency causes explain figures: interrupts.SOURCE.worst is left out, its count is a figure.
TEST(Flatten, LatencyCausesAreNotFigures) {
    const json r = {{"interrupts",
                     {{"rs232_0",
                       {{"count", 3},
                        {"over_budget", 1},
                        {"worst", json::array({{{"latency_us", 500.0}, {"phases", json::array({{{"us", 1.0}}})}}})}}}}},
                    {"worst", 1}};
    const Figures f = flatten_figures(r);
    ASSERT_EQ(f.size(), 3u);
    EXPECT_EQ(f[0].first, "interrupts.rs232_0.count");
    EXPECT_EQ(f[1].first, "interrupts.rs232_0.over_budget");
    EXPECT_EQ(f[2].first, "worst"); // only under interrupts
}

TEST(Merge, SummaryRowsParametersFiguresChecks) {
    const fs::path d = rcsim::test::scratch_dir();
    make_run(d / "runs", "g-rom=0", 50.25, true, 0);
    make_run(d / "runs", "g-rom=1", -3, false, 1);
    fs::create_directories(d / "runs/g-rom=2"); // started, never finished
    std::ofstream(d / "runs/g-rom=2/run.json") << json{{"id", "g-rom=2"}, {"entry", "g"}, {"parameters", {{"board.wait_states.rom", 2}}}};
    EXPECT_EQ(merge_runs({(d / "runs").string()}, d / "runs"), 3u);
    const json s = json::parse(slurp(d / "runs/summary.json"));
    EXPECT_EQ(s["runs"], 3);
    EXPECT_EQ(s["passed"], 1);
    EXPECT_EQ(s["failed"], 1);
    EXPECT_EQ(s["no report"], 1);
    EXPECT_EQ(s["results"][1]["figures"]["table3.margin_us"], json(-3));
    EXPECT_TRUE(s["results"][1]["figures"]["table3.dpram_byte_us"].is_null());
    EXPECT_EQ(s["results"][1]["checks"]["overruns"]["passed"], false);
    EXPECT_EQ(s["results"][2]["status"], "no report");

    const std::string csv = slurp(d / "runs/summary.csv");
    std::istringstream lines(csv);
    std::string header, row0, row1, row2;
    std::getline(lines, header), std::getline(lines, row0), std::getline(lines, row1), std::getline(lines, row2);
    EXPECT_EQ(header, "id,entry,status,param:board.wait_states.rom,ports[0].frames_delivered,ports[0].overruns,"
                      "ports[1].frames_delivered,ports[1].overruns,seed,table3.dpram_byte_us,table3.margin_us,"
                      "check:overruns,expected_failures,outcome");
    EXPECT_EQ(row0, "g-rom=0,g,passed,0,4,0,5,1,1,,50.25,PASS,,passed");
    EXPECT_EQ(row1, "g-rom=1,g,failed,1,4,0,5,1,1,,-3.0,FAIL,,failed");
    EXPECT_EQ(row2, "g-rom=2,g,no report,2,,,,,,,,,,no report");

    const std::string html = slurp(d / "runs/summary.html");
    EXPECT_NE(html.find("<h2>Against board.wait_states.rom</h2>"), std::string::npos);
    EXPECT_NE(html.find("Table 3 margin [us]"), std::string::npos);
    EXPECT_NE(html.find("<tr class=\"fail\"><td class=\"k\">g-rom=1</td>"), std::string::npos);
    EXPECT_NE(html.find("stroke=\"#c82333\""), std::string::npos); // the failing run's cross
}

// An interrupted sweep marks the runs it did not complete (kNotRunMarker): "not run", counted,
// and the page says so; a run without the marker and without a report stays "no report".
TEST(Merge, NotRunRunsOfAnInterruptedSweep) {
    const fs::path d = rcsim::test::scratch_dir();
    make_run(d / "runs", "g-rom=0", 50.25, true, 0);
    fs::create_directories(d / "runs/g-rom=1");
    std::ofstream(d / "runs/g-rom=1/run.json") << json{{"id", "g-rom=1"}, {"entry", "g"}, {"parameters", {{"board.wait_states.rom", 1}}}};
    std::ofstream(d / "runs/g-rom=1" / kNotRunMarker) << "not run\n";
    merge_runs({(d / "runs").string()}, d / "runs");
    const json s = json::parse(slurp(d / "runs/summary.json"));
    EXPECT_EQ(s["not run"], 1);
    EXPECT_EQ(s["no report"], 0);
    EXPECT_EQ(s["results"][1]["status"], "not run");
    EXPECT_NE(slurp(d / "runs/summary.csv").find("\ng-rom=1,g,not run,1"), std::string::npos);
    EXPECT_NE(slurp(d / "runs/summary.html").find("1 not run (the sweep was interrupted)"), std::string::npos);
}

// Issue #51 item 3: interrupted and not-run runs are neither as expected nor not: the banner
// counts them apart, their rows are not red, the interrupted run's point is a grey ring, no cross.
TEST(Merge, InterruptedAndNotRunRunsAreDrawnAndCountedApart) {
    const fs::path d = rcsim::test::scratch_dir();
    make_run(d / "runs", "g-rom=0", 50.25, true, 0);
    make_run(d / "runs", "g-rom=1", 40, true, 1);
    json stopped = json::parse(slurp(d / "runs/g-rom=1/report.json"));
    stopped["verdict"] = "interrupted";
    std::ofstream(d / "runs/g-rom=1/report.json") << stopped.dump(2);
    for (int i = 2; i < 4; ++i) {
        const std::string id = "g-rom=" + std::to_string(i);
        fs::create_directories(d / "runs" / id);
        std::ofstream(d / "runs" / id / "run.json") << json{{"id", id}, {"entry", "g"}, {"parameters", {{"board.wait_states.rom", i}}}};
        std::ofstream(d / "runs" / id / kNotRunMarker) << "not run\n";
    }
    merge_runs({(d / "runs").string()}, d / "runs");
    const std::string html = slurp(d / "runs/summary.html");
    EXPECT_NE(html.find("; 1 as expected, 0 not, 3 interrupted/not run</div>"), std::string::npos) << html.substr(0, 1500);
    EXPECT_NE(html.find("<tr class=\"stopped\"><td class=\"k\">g-rom=1</td><td class=\"k\">interrupted</td>"),
              std::string::npos);
    EXPECT_NE(html.find("<tr class=\"stopped\"><td class=\"k\">g-rom=3</td><td class=\"k\">not run</td>"),
              std::string::npos);
    EXPECT_EQ(html.find("<tr class=\"fail\">"), std::string::npos);
    EXPECT_NE(html.find("<circle class=\"stopped\""), std::string::npos);
    EXPECT_EQ(html.find("stroke=\"#c82333\""), std::string::npos); // no "failed" cross
    EXPECT_NE(html.find("g-rom=1: 40; interrupted (figures so far)"), std::string::npos);
}

TEST(Merge, SameRunsInAnyOrderOrSplitGiveTheSameBytes) {
    const fs::path d = rcsim::test::scratch_dir();
    for (int i = 0; i < 6; ++i) make_run(d / "all", "g-rom=" + std::to_string(i), 10.0 / (i + 1), i != 3, i);
    // The same runs split over two directories, the second listed first.
    for (int i = 0; i < 6; ++i) {
        const std::string id = "g-rom=" + std::to_string(i);
        fs::create_directories(d / (i % 2 ? "a" : "b") / id);
        fs::copy(d / "all" / id, d / (i % 2 ? "a" : "b") / id, fs::copy_options::recursive);
    }
    fs::create_directories(d / "out1");
    fs::create_directories(d / "out2");
    merge_runs({(d / "all").string()}, d / "out1");
    merge_runs({(d / "b").string(), (d / "a").string()}, d / "out2");
    for (const char* f : {"summary.json", "summary.csv", "summary.html"}) {
        EXPECT_EQ(slurp(d / "out1" / f), slurp(d / "out2" / f)) << f;
        EXPECT_GT(slurp(d / "out1" / f).size(), 200u) << f;
    }
}

TEST(Merge, TheSameRunTwiceIsAnError) {
    const fs::path d = rcsim::test::scratch_dir();
    make_run(d / "a", "r", 1, true, 0);
    make_run(d / "b", "r", 1, true, 0);
    try {
        collect_runs({(d / "a").string(), (d / "b").string()});
        FAIL() << "duplicate run accepted";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("run 'r' is also in"), std::string::npos) << e.what();
    }
    EXPECT_THROW(collect_runs({(d / "missing").string()}), ConfigError);
}

TEST(ReadJson, SyntaxErrorNamesTheLine) {
    const fs::path d = rcsim::test::scratch_dir();
    std::ofstream(d / "r.json") << "{\n  \"a\": 1,\n  \"b\": ]\n}\n";
    try {
        read_json_file(d / "r.json");
        FAIL() << "bad JSON accepted";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("r.json:3: bad JSON: syntax error"), std::string::npos) << e.what();
    }
}

// Issue #51 item 3: numbers in run ids compare by value (seed=1, 2, 10, 11), text as text.
TEST(RunOrder, NumbersInIdsCompareByValueTextAsText) {
    std::vector<std::string> ids = {"s-seed=11", "s-seed=2", "s-seed=10", "s-seed=1", "grid-rom=0-data_size=128",
                                    "grid-rom=0-data_size=16", "x=-0.5", "x=0.25", "x=1e-3", "port=b", "port=a"};
    std::sort(ids.begin(), ids.end(), run_id_less);
    const std::vector<std::string> want = {"grid-rom=0-data_size=16", "grid-rom=0-data_size=128", "port=a", "port=b",
                                           "s-seed=1", "s-seed=2", "s-seed=10", "s-seed=11", "x=-0.5", "x=1e-3",
                                           "x=0.25"};
    EXPECT_EQ(ids, want);
    EXPECT_FALSE(run_id_less("a", "a"));
    EXPECT_TRUE(run_id_less("a", "a-seed=1")); // a prefix first
}

TEST(RunOrder, TheSummaryListsSeedsInNumericOrder) {
    const fs::path dir = rcsim::test::scratch_dir();
    for (const char* id : {"s-seed=10", "s-seed=2", "s-seed=1", "s-seed=11"}) make_run(dir, id, 10, true, 0);
    const json s = summary_json(collect_runs({dir.string()}));
    std::vector<std::string> order;
    for (const auto& r : s["results"]) order.push_back(r["id"]);
    EXPECT_EQ(order, (std::vector<std::string>{"s-seed=1", "s-seed=2", "s-seed=10", "s-seed=11"}));
}
