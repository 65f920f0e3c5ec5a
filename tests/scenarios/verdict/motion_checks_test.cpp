// The verdicts of a motion run (scenarios/verdict/motion_checks.h) on hand-made trajectories: the swept
// angle, the commanded arc, the end point, the expected outcomes. The same checks through the
// rcsim binary, made to fail one by one, are tests/scenarios/verdict/cases/motion_*.yaml.
#include "scenarios/verdict/motion_checks.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace rcsim;

namespace {

const double kPi = std::acos(-1.0);

/// Samples 1 ms apart on the circle of radius r around (cx, cy), from angle a0 through a1 (in
/// `n` equal steps), rounded to whole pulses as the CAMC-QI's counters are.
std::vector<motion::TrajectorySample> arc_samples(double cx, double cy, double r, double a0, double a1, int n) {
    std::vector<motion::TrajectorySample> s;
    for (int i = 0; i <= n; ++i) {
        const double a = a0 + (a1 - a0) * i / n;
        const std::int64_t x = std::llround(cx + r * std::cos(a)), y = std::llround(cy + r * std::sin(a));
        s.push_back({i * 1e-3, {x, y, 0, 0}, {x, y, 0, 0}});
    }
    return s;
}

const Check& named(const std::vector<Check>& checks, const std::string& name) {
    for (const Check& c : checks)
        if (c.name == name) return c;
    throw std::runtime_error("no check " + name);
}

TEST(MotionChecks, SweptAngleFollowsThePathInTheCommandedDirection) {
    // A full turn counter-clockwise is +2 pi seen counter-clockwise and -2 pi seen clockwise.
    const auto full = arc_samples(0, 0, 1000, 0, 2 * kPi, 2000);
    EXPECT_NEAR(swept_angle_rad(full, 0, 10, 0, 0, true), 2 * kPi, 1e-9);
    EXPECT_NEAR(swept_angle_rad(full, 0, 10, 0, 0, false), -2 * kPi, 1e-9);
    // The window: the first half of the samples is half a turn.
    EXPECT_NEAR(swept_angle_rad(full, 0, 1.0, 0, 0, true), kPi, 1e-9);
    // Twice round is 4 pi, not 2 pi (the angle is unwrapped, not a span of atan2 values).
    const auto twice = arc_samples(0, 0, 1000, 0, 4 * kPi, 4000);
    EXPECT_NEAR(swept_angle_rad(twice, 0, 10, 0, 0, true), 4 * kPi, 1e-9);
    // A path that never moves sweeps nothing.
    const auto still = arc_samples(0, 0, 1000, 0, 0, 100);
    EXPECT_EQ(swept_angle_rad(still, 0, 10, 0, 0, true), 0.0);
}

TEST(MotionChecks, CommandedArcAngle) {
    // End = start: the CAMC-QI's full circle.
    EXPECT_DOUBLE_EQ((CommandedArc{0, 0, -5000, 0, 0, 0, true}.sweep_rad()), 2 * kPi);
    EXPECT_DOUBLE_EQ((CommandedArc{0, 0, -5000, 0, 0, 0, false}.sweep_rad()), 2 * kPi);
    // From (0, 0) around (-5000, 0) to (-5000, 5000): a quarter counter-clockwise, three
    // quarters clockwise.
    EXPECT_NEAR((CommandedArc{0, 0, -5000, 0, -5000, 5000, true}.sweep_rad()), kPi / 2, 1e-12);
    EXPECT_NEAR((CommandedArc{0, 0, -5000, 0, -5000, 5000, false}.sweep_rad()), 3 * kPi / 2, 1e-12);
    EXPECT_DOUBLE_EQ((CommandedArc{0, 0, -5000, 0, -5000, 5000, true}.radius()), 5000);
}

TEST(MotionChecks, CircleChecksJudgeSweepRadiusAndEnd) {
    // A full circle of R = 1000 around (-1000, 0) from (0, 0).
    const CommandedArc full{0, 0, -1000, 0, 0, 0, true};
    const CircleLimits lim{-1000, 0, 1000, 1.0, 0};
    const auto done = circle_checks(lim, ArcRun{full, 0, 10}, arc_samples(-1000, 0, 1000, 0, 2 * kPi, 2000), "");
    for (const Check& c : done) EXPECT_TRUE(c.passed()) << to_json(c).dump();
    // The limit is one pulse of arc less than the full turn: 2 pi - 1/R.
    EXPECT_DOUBLE_EQ(named(done, "circle_swept_angle_rad").limit, 2 * kPi - 1.0 / 1000);

    // Stopped 90 degrees short: on the circle, but neither swept nor closed.
    const auto short_arc = arc_samples(-1000, 0, 1000, 0, 1.5 * kPi, 1500);
    const auto s = circle_checks(lim, ArcRun{full, 0, 10}, short_arc, "");
    EXPECT_TRUE(named(s, "circle_radial_error_pulses").passed());
    EXPECT_FALSE(named(s, "circle_swept_angle_rad").passed());
    EXPECT_NEAR(*named(s, "circle_swept_angle_rad").figure.value, 1.5 * kPi, 1e-9);
    // It ended at (-1000, -1000): 1000 pulses from the start on both axes.
    EXPECT_EQ(*named(s, "circle_end_error_pulses").figure.value, 1000.0);

    // A path one pulse of arc short of the full circle still passes the sweep (the limit), two
    // pulses short does not.
    const auto one_short = arc_samples(-1000, 0, 1000, 0, 2 * kPi - 1.0 / 1000, 2000);
    EXPECT_TRUE(named(circle_checks(lim, ArcRun{full, 0, 10}, one_short, ""), "circle_swept_angle_rad").passed());
    const auto two_short = arc_samples(-1000, 0, 1000, 0, 2 * kPi - 2.0 / 1000, 2000);
    EXPECT_FALSE(named(circle_checks(lim, ArcRun{full, 0, 10}, two_short, ""), "circle_swept_angle_rad").passed());

    // A circle of the wrong radius: the radial error is the 10 pulses of difference, give or take
    // the rounding of both coordinates to whole pulses (at most sqrt(0.5^2 + 0.5^2)).
    const auto wide = arc_samples(-1000, 0, 1010, kPi, 3 * kPi, 2000);
    EXPECT_NEAR(*named(circle_checks(lim, ArcRun{full, 0, 10}, wide, ""), "circle_radial_error_pulses").figure.value,
                10.0, std::sqrt(0.5));
}

TEST(MotionChecks, NoCircleCommandIsNotMeasured) {
    const auto c = circle_checks(CircleLimits{-1000, 0, 1000, 1, 0}, std::nullopt, {}, "no circle command");
    ASSERT_EQ(c.size(), 3u);
    for (const Check& k : c) {
        EXPECT_EQ(k.status, Check::Status::not_measured) << k.name;
        EXPECT_EQ(to_json(k)["reason"], "no circle command");
        EXPECT_TRUE(to_json(k)["value"].is_null());
    }
    EXPECT_DOUBLE_EQ(named(c, "circle_swept_angle_rad").limit, 2 * kPi - 1.0 / 1000);
}

TEST(MotionChecks, OutcomesMustBeTheExpectedOnes) {
    FbCommand c;
    c.outcome = FbOutcome::done;
    EXPECT_TRUE(c.as_expected()); // default: done
    c.outcome = FbOutcome::busy;
    EXPECT_FALSE(c.as_expected()); // no outcome by the end of the run
    c.expect = FbOutcome::error;
    c.outcome = FbOutcome::error;
    c.error_id = 4113;
    EXPECT_TRUE(c.as_expected()); // any ErrorID
    c.expect_error_id = 4113;
    EXPECT_TRUE(c.as_expected());
    c.expect_error_id = 4114;
    EXPECT_FALSE(c.as_expected()); // another ErrorID
    c.outcome = FbOutcome::done;
    EXPECT_FALSE(c.as_expected()); // the expected error did not happen
    c.expect = FbOutcome::aborted;
    c.expect_error_id.reset();
    EXPECT_FALSE(c.as_expected());
    c.outcome = FbOutcome::aborted;
    EXPECT_TRUE(c.as_expected());

    FbCommand ok, bad;
    ok.fb = bad.fb = "MC_MoveAbsolute";
    ok.outcome = FbOutcome::done;
    bad.index = 3;
    bad.outcome = FbOutcome::error;
    bad.error_id = 0x7001;
    const Check k = fb_outcome_check({ok, bad});
    EXPECT_FALSE(k.passed());
    EXPECT_EQ(*k.figure.value, 1.0);
    ASSERT_EQ(k.detail["unexpected"].size(), 1u);
    EXPECT_EQ(k.detail["unexpected"][0]["command"], 3);
    EXPECT_EQ(k.detail["unexpected"][0]["outcome"], "error");
    EXPECT_EQ(k.detail["unexpected"][0]["error_id"], 0x7001);
    EXPECT_TRUE(fb_outcome_check({ok}).passed());
}

TEST(MotionChecks, FinalStateAndPositions) {
    EXPECT_TRUE(final_state_check("STANDSTILL", "STANDSTILL").passed());
    const Check s = final_state_check("STANDSTILL", "ERRORSTOP");
    EXPECT_FALSE(s.passed());
    EXPECT_EQ(s.detail["got"], "ERRORSTOP");
    const Check p = final_positions_check({0, 100}, {0, 97, 5, 5}, 2);
    EXPECT_FALSE(p.passed());
    EXPECT_EQ(*p.figure.value, 3.0); // the largest difference over the listed axes only
    EXPECT_TRUE(final_positions_check({0, 100}, {0, 97, 5, 5}, 3).passed());
}

} // namespace
