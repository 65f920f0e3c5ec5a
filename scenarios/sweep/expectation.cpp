#include "scenarios/sweep/expectation.h"

#include <set>

namespace rcsim::sweep {

namespace {

/// A check's status as report.json gives it: "passed", "failed" or "not measured"; a report from
/// before statuses has `passed` only.
std::string check_status(const nlohmann::json& check) {
    if (check.contains("status") && check["status"].is_string()) return check["status"].get<std::string>();
    return check.value("passed", false) ? "passed" : "failed";
}

} // namespace

Expectation judge_expectation(const std::optional<nlohmann::json>& report, const std::vector<std::string>& expect_fail) {
    if (!report) return {"no report", {"the run did not finish (no report.json)"}};
    const std::string verdict = report->value("verdict", std::string());
    if (verdict == "interrupted") return {"interrupted", {"the run was interrupted"}};

    Expectation e;
    std::set<std::string> expected(expect_fail.begin(), expect_fail.end()), seen;
    bool unmeasured = false, any_failed = false;
    for (const auto& [name, check] : report_checks(*report)) {
        seen.insert(name);
        const std::string status = check_status(check);
        any_failed = any_failed || status == "failed";
        if (expected.count(name)) {
            if (status == "passed") e.why.push_back("check " + name + ": expected to fail, passed");
            else if (status != "failed") e.why.push_back("check " + name + ": expected to fail, not measured");
        } else if (status == "failed") {
            e.why.push_back("check " + name + ": failed, not expected");
        } else if (status != "passed") {
            unmeasured = true;
        }
    }
    for (const std::string& name : expected)
        if (!seen.count(name)) e.why.push_back("check " + name + ": expected to fail, not in the report (switched off?)");
    // A report that failed without naming a failed check (no checks array) cannot meet anything.
    if (!any_failed && verdict == "failed") e.why.push_back("the run failed: " + report->value("verdict_reason", std::string("?")));
    e.outcome = !e.why.empty() ? "failed" : unmeasured ? "inconclusive" : "passed";
    return e;
}

std::vector<std::string> expected_failures(const RunRecord& run) {
    std::vector<std::string> names;
    if (!run.meta.is_object() || !run.meta.contains("expect_fail") || !run.meta["expect_fail"].is_array()) return names;
    for (const auto& n : run.meta["expect_fail"])
        if (n.is_string()) names.push_back(n.get<std::string>());
    return names;
}

Expectation judge_run(const RunRecord& run) { return judge_expectation(run.report, expected_failures(run)); }

} // namespace rcsim::sweep
