// Tests of the harness's completion check for SystemC test bodies (spawn_checked): in process
// through expect_bodies_finished, and end to end by running sc_test_child's tests, whose verdict
// comes from the check that runs when each test ends.
#include "tests/support/sc_test.h"

#include <gtest/gtest-spi.h>

#include <cstdio>
#include <string>
#include <sys/wait.h>

using rcsim::test::expect_bodies_finished;
using rcsim::test::spawn_checked;

namespace {

sc_core::sc_event g_never; // nothing notifies it

struct ChildRun {
    int exit_code = -1;
    std::string output;
};

/// Runs one test of sc_test_child ("Suite.Name") in its own process.
ChildRun run_child(const std::string& test) {
    const std::string cmd = std::string("'") + RCSIM_SC_TEST_CHILD + "' --gtest_filter=" + test + " 2>&1";
    ChildRun r;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    char buf[4096];
    for (std::size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;) r.output.append(buf, n);
    const int status = pclose(p);
    if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
    return r;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

} // namespace

TEST(SpawnChecked, StuckBodyFailsNamingIt) {
    spawn_checked([] { sc_core::wait(g_never); }, "stuck_body");
    sc_core::sc_start();
    EXPECT_NONFATAL_FAILURE(expect_bodies_finished(), "SystemC thread 'stuck_body' did not run to completion");
    // Reported once: the check forgets what it reported, so the end-of-test check finds nothing.
    expect_bodies_finished();
}

TEST(SpawnChecked, FinishedBodyAddsNoFailure) {
    spawn_checked([] { sc_core::wait(sc_core::sc_time(10, sc_core::SC_NS)); }, "done_body");
    sc_core::sc_start();
    expect_bodies_finished(); // a failure here fails this test
}

// End to end: the listener fails the test (exit status 1, "[  FAILED  ]") and names the body;
// the EXPECT after the stuck wait() never ran, which is the failure the check exists to expose.
TEST(SpawnChecked, ChildWithStuckBodyFails) {
    const ChildRun r = run_child("SpawnCheckedChild.StuckInAWaitFails");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "SystemC thread 'stuck_body' did not run to completion")) << r.output;
    EXPECT_TRUE(contains(r.output, "[  FAILED  ] SpawnCheckedChild.StuckInAWaitFails")) << r.output;
    EXPECT_FALSE(contains(r.output, "unreachable")) << r.output;
}

TEST(SpawnChecked, ChildCutShortBySimulationEndFails) {
    const ChildRun r = run_child("SpawnCheckedChild.CutShortBySimulationEndFails");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "SystemC thread 'late_body' did not run to completion")) << r.output;
}

TEST(SpawnChecked, ChildWithStuckNestedBodyFailsNamingOnlyIt) {
    const ChildRun r = run_child("SpawnCheckedChild.StuckNestedBodyFails");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "'outer_body.inner_body' did not run to completion")) << r.output;
    EXPECT_FALSE(contains(r.output, "'outer_body' did not")) << r.output;
}

TEST(SpawnChecked, ChildWithFinishedBodyPasses) {
    const ChildRun r = run_child("SpawnCheckedChild.FinishedBodyPasses");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "[       OK ] SpawnCheckedChild.FinishedBodyPasses")) << r.output;
}

TEST(SpawnChecked, ChildWithForeverBodyPasses) {
    const ChildRun r = run_child("SpawnCheckedChild.ForeverBodyPasses");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "[       OK ] SpawnCheckedChild.ForeverBodyPasses")) << r.output;
}

// Exemptions: a test that never starts the simulation, and one whose simulation an error ended
// (the test's verdict is that error), have no unfinished bodies to report.
TEST(SpawnChecked, ChildThatNeverStartsTheSimulationPasses) {
    const ChildRun r = run_child("SpawnCheckedChild.NeverStartedSimulationPasses");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "[       OK ] SpawnCheckedChild.NeverStartedSimulationPasses")) << r.output;
}

TEST(SpawnChecked, ChildWhoseSimulationAnExpectedErrorEndedPasses) {
    const ChildRun r = run_child("SpawnCheckedChild.ExpectedErrorEndingTheSimulationPasses");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "[       OK ] SpawnCheckedChild.ExpectedErrorEndingTheSimulationPasses"))
        << r.output;
}

// A UBSan report must turn its test red in the sanitizer build (make test-asan), not scroll by.
TEST(SanitizerBuild, UndefinedBehaviourFailsTheTest) {
#ifndef RCSIM_SANITIZE_BUILD
    GTEST_SKIP() << "not a sanitizer build (RCSIM_SANITIZE=OFF)";
#else
    const ChildRun r = run_child("SanitizerChild.SignedOverflow");
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "runtime error: signed integer overflow")) << r.output;
    EXPECT_FALSE(contains(r.output, "[       OK ]")) << r.output;
#endif
}
