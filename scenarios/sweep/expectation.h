// rcsim — a sweep's judgement of a run: the checks the sweep file says the run expects to fail
// (`expect_fail`, docs/regression.md "Expected failures") against the checks its report failed.
// The run's report keeps its own verdict; this is what the sweep's exit code and summaries use.
#pragma once

#include "scenarios/sweep/merge.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace rcsim::sweep {

struct Expectation {
    /// "passed": exactly the expected checks failed; "failed": not so (`why` says which check and
    /// how); "inconclusive": as expected, but a check no one expected to fail was not measured;
    /// "interrupted" or "no report": the run's own status, nothing to judge.
    std::string outcome;
    /// Per check not as expected: "check NAME: expected to fail, passed", "check NAME: failed,
    /// not expected", ...
    std::vector<std::string> why;
    bool met() const { return outcome == "passed" || outcome == "inconclusive"; }
};

/// Judges `report` (absent: the run did not finish) against the checks it expects to fail.
Expectation judge_expectation(const std::optional<nlohmann::json>& report, const std::vector<std::string>& expect_fail);

/// The checks a run directory expects to fail: run.json's "expect_fail" (none when absent).
std::vector<std::string> expected_failures(const RunRecord& run);

/// judge_expectation() of a run directory read back.
Expectation judge_run(const RunRecord& run);

} // namespace rcsim::sweep
