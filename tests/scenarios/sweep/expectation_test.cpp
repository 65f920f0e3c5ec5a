// Expected failures (docs/regression.md "Expected failures"): a run meets the sweep's expectation
// when exactly the checks it declares fail; the summary keeps the run's own status beside it.
#include "tests/support/files.h"
#include "scenarios/sweep/expectation.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;
using namespace rcsim::sweep;
using json = nlohmann::json;

namespace {

json check(const std::string& name, const std::string& status) {
    return {{"name", name}, {"passed", status == "passed"}, {"status", status}, {"value", 1}, {"limit", 0}};
}

/// A report with these checks and the verdict they make.
json report_with(const std::vector<json>& checks) {
    std::string verdict = "passed";
    for (const json& c : checks)
        if (c["status"] == "failed") verdict = "failed";
        else if (c["status"] != "passed" && verdict == "passed") verdict = "inconclusive";
    return {{"scenario", "r"}, {"checks", checks}, {"verdict", verdict}, {"passed", verdict == "passed"}};
}

const json kFaultsToday = report_with({check("overruns", "passed"), check("commands_delivered_exactly_once", "failed"),
                                       check("responses_delivered_exactly_once", "passed")});

} // namespace

TEST(Expectation, ExactlyTheDeclaredChecksFailingPassesTheRun) {
    const Expectation e = judge_expectation(kFaultsToday, {"commands_delivered_exactly_once"});
    EXPECT_EQ(e.outcome, "passed");
    EXPECT_TRUE(e.why.empty());
    EXPECT_TRUE(e.met());
    // Nothing declared, nothing failed: passed as before.
    EXPECT_EQ(judge_expectation(report_with({check("overruns", "passed")}), {}).outcome, "passed");
}

TEST(Expectation, ADeclaredCheckThatPassesFailsTheRunNamingIt) {
    const Expectation e =
        judge_expectation(kFaultsToday, {"commands_delivered_exactly_once", "responses_delivered_exactly_once"});
    EXPECT_EQ(e.outcome, "failed");
    EXPECT_FALSE(e.met());
    EXPECT_EQ(e.why, std::vector<std::string>{"check responses_delivered_exactly_once: expected to fail, passed"});
    // A declared check the report does not carry (switched off) cannot have failed as expected.
    EXPECT_EQ(judge_expectation(kFaultsToday, {"commands_delivered_exactly_once", "frames_failed"}).why,
              std::vector<std::string>{"check frames_failed: expected to fail, not in the report (switched off?)"});
}

TEST(Expectation, AnUndeclaredFailureFailsTheRunNamingIt) {
    const Expectation e = judge_expectation(kFaultsToday, {});
    EXPECT_EQ(e.outcome, "failed");
    EXPECT_EQ(e.why, std::vector<std::string>{"check commands_delivered_exactly_once: failed, not expected"});
    // Both at once: each named with its own reason.
    const json both = report_with({check("overruns", "failed"), check("frames_failed", "passed")});
    EXPECT_EQ(judge_expectation(both, {"frames_failed"}).why,
              (std::vector<std::string>{"check overruns: failed, not expected",
                                        "check frames_failed: expected to fail, passed"}));
}

TEST(Expectation, NotMeasuredAndNoReport) {
    const json unmeasured = report_with({check("table3_margin_us", "not measured"), check("overruns", "failed")});
    EXPECT_EQ(judge_expectation(unmeasured, {"overruns"}).outcome, "inconclusive"); // met, as the sweep treats it
    EXPECT_EQ(judge_expectation(unmeasured, {"overruns", "table3_margin_us"}).why,
              std::vector<std::string>{"check table3_margin_us: expected to fail, not measured"});
    EXPECT_EQ(judge_expectation(std::nullopt, {"overruns"}).outcome, "no report");
}

TEST(Expectation, SummaryKeepsTheRunsStatusBesideTheOutcome) {
    const fs::path d = rcsim::test::scratch_dir();
    for (const char* id : {"faults", "plain"}) {
        fs::create_directories(d / id);
        json meta = {{"id", id}, {"entry", id}, {"parameters", json::object()}};
        if (std::string(id) == "faults") meta["expect_fail"] = {"commands_delivered_exactly_once"};
        std::ofstream(d / id / "run.json") << meta;
        std::ofstream(d / id / "report.json") << kFaultsToday;
    }
    merge_runs({d.string()}, d);
    const json s = json::parse(rcsim::test::slurp(d / "summary.json"));
    EXPECT_EQ(s["failed"], 2); // the runs' own verdicts
    EXPECT_EQ(s["outcomes"]["passed"], 1);
    EXPECT_EQ(s["outcomes"]["failed"], 1);
    const json& faults = s["results"][0];
    EXPECT_EQ(faults["status"], "failed");
    EXPECT_EQ(faults["expected_failures"], json({"commands_delivered_exactly_once"}));
    EXPECT_EQ(faults["outcome"], "passed");
    EXPECT_EQ(s["results"][1]["outcome_why"], json({"check commands_delivered_exactly_once: failed, not expected"}));
    const std::string csv = rcsim::test::slurp(d / "summary.csv");
    EXPECT_NE(csv.find(",FAIL,PASS,PASS,commands_delivered_exactly_once,passed\n"), std::string::npos) << csv;
    const std::string html = rcsim::test::slurp(d / "summary.html");
    EXPECT_NE(html.find("<tr><td class=\"k\">faults</td>"), std::string::npos); // not red: as expected
    EXPECT_NE(html.find("<tr class=\"fail\"><td class=\"k\">plain</td>"), std::string::npos);
}
