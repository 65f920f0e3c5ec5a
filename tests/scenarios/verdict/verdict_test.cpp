// The run's verdict from its checks (verdict/checks.h): FAILED when one failed, else INCONCLUSIVE
// when one was not measured, else PASSED; INTERRUPTED whatever they say when a signal stopped the
// run. Exit codes 0, 1, 4, 128 + signal (docs/scenarios.md "Verdicts and exit codes").
#include "scenarios/verdict/checks.h"
#include "scenarios/verdict/judge.h"

#include <gtest/gtest.h>

namespace {

using rcsim::judge_run;
using rcsim::Verdict;
using json = nlohmann::json;

json check(const char* name, const char* status, const char* reason = "") {
    json c = {{"name", name}, {"status", status}, {"passed", std::string(status) == "passed"}};
    if (*reason) c["reason"] = reason;
    return c;
}

TEST(Verdict, EveryCheckHeldIsPassed) {
    const auto v = judge_run(json::array({check("overruns", "passed"), check("bus_errors", "passed")}), 0);
    EXPECT_EQ(v.verdict, Verdict::passed);
    EXPECT_EQ(v.reason, "");
    EXPECT_EQ(rcsim::exit_code_of(v, 0), 0);
    EXPECT_EQ(judge_run(json::array(), 0).verdict, Verdict::passed);
}

TEST(Verdict, AFailureOutranksANotMeasuredFigure) {
    const auto v = judge_run(json::array({check("table3_margin_us", "not measured", "no samples"),
                                          check("overruns", "failed"), check("frames_failed", "failed")}),
                             0);
    EXPECT_EQ(v.verdict, Verdict::failed);
    EXPECT_EQ(v.reason, "failed: overruns, frames_failed");
    EXPECT_EQ(rcsim::exit_code_of(v, 0), 1);
}

TEST(Verdict, NothingFailedButSomethingNotMeasuredIsInconclusive) {
    const json checks = json::array({check("overruns", "passed"),
                                      check("table3_margin_us", "not measured", "no RS-232 receive interrupt"),
                                      check("table3_worst_margin_us", "not measured", "no RS-232 receive interrupt")});
    const auto v = judge_run(checks, 0);
    EXPECT_EQ(v.verdict, Verdict::inconclusive);
    EXPECT_EQ(v.reason, "table3_margin_us: no RS-232 receive interrupt; not measured: table3_margin_us, "
                        "table3_worst_margin_us");
    EXPECT_EQ(rcsim::exit_code_of(v, 0), 4);
    // The scenario's own reason, when it gave the controller nothing to measure, leads.
    EXPECT_EQ(judge_run(checks, 0, "no host sent traffic").reason,
              "no host sent traffic; not measured: table3_margin_us, table3_worst_margin_us");
}

TEST(Verdict, ASignalMakesItInterruptedAndSaysWhatCompleted) {
    const auto v = judge_run(json::array({check("overruns", "failed")}), 2);
    EXPECT_EQ(v.verdict, Verdict::interrupted);
    EXPECT_EQ(v.reason, "stopped by SIGINT; what completed: failed (failed: overruns)");
    EXPECT_EQ(rcsim::exit_code_of(v, 2), 130);
    const auto t = judge_run(json::array({check("overruns", "passed")}), 15);
    EXPECT_EQ(t.reason, "stopped by SIGTERM; what completed: passed");
    EXPECT_EQ(rcsim::exit_code_of(t, 15), 143);
}

TEST(Verdict, ReportJsonCarriesVerdictReasonAndPassed) {
    json r;
    rcsim::put_verdict(r, {Verdict::inconclusive, "why"});
    EXPECT_EQ(r["verdict"], "inconclusive");
    EXPECT_EQ(r["verdict_reason"], "why");
    EXPECT_EQ(r["passed"], false);
    rcsim::put_verdict(r, {Verdict::passed, ""});
    EXPECT_EQ(r["passed"], true);
}

} // namespace

// Live (the page, the API, Modbus), a failure stands only when no later event can undo it.
TEST(JudgeSoFar, AMinimumNotReachedYetIsNotAFailureYet) {
    const rcsim::Check c = rcsim::as_so_far(rcsim::Check::at_least("frames_delivered", rcsim::Figure::of(0), 3));
    EXPECT_EQ(c.status, rcsim::Check::Status::not_measured);
    EXPECT_NE(c.figure.reason.find("not final before the end of the run"), std::string::npos);
}

TEST(JudgeSoFar, AMeanMarginCanStillComeGood) {
    const rcsim::Check c = rcsim::as_so_far(rcsim::Check::at_least("table3_margin_us", rcsim::Figure::of(-5), 0));
    EXPECT_EQ(c.status, rcsim::Check::Status::not_measured);
}

TEST(JudgeSoFar, AMaximumOrACountOverItsLimitFailsAtOnce) {
    EXPECT_EQ(rcsim::as_so_far(rcsim::Check::at_most("overruns", rcsim::Figure::of(1), 0)).status,
              rcsim::Check::Status::failed);
    EXPECT_EQ(rcsim::as_so_far(rcsim::Check::at_most("interrupt_blocking_max_us", rcsim::Figure::of(500), 381.9)).status,
              rcsim::Check::Status::failed);
    EXPECT_EQ(rcsim::as_so_far(rcsim::Check::at_least("table3_worst_margin_us", rcsim::Figure::of(-1), 0)).status,
              rcsim::Check::Status::failed);
}

TEST(JudgeSoFar, APassStaysAPass) {
    EXPECT_TRUE(rcsim::as_so_far(rcsim::Check::at_least("frames_delivered", rcsim::Figure::of(3), 3)).passed());
}
