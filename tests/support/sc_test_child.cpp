// Tests run by sc_test_support_test, one per process, to observe the completion check from
// outside: each is expected to pass or fail as its name says.
#include "tests/support/sc_test.h"

#include <climits>

using rcsim::test::spawn_checked;
using rcsim::test::spawn_forever;

namespace {
sc_core::sc_event g_never; // nothing notifies it
} // namespace

// The body stops in a wait() that never returns: its EXPECT is skipped, the check reports it.
TEST(SpawnCheckedChild, StuckInAWaitFails) {
    spawn_checked(
        [] {
            sc_core::wait(g_never);
            ADD_FAILURE() << "unreachable: nothing notifies the event";
        },
        "stuck_body");
    sc_core::sc_start();
}

// The simulation ends (sc_start with a limit) while the body still has time to wait.
TEST(SpawnCheckedChild, CutShortBySimulationEndFails) {
    spawn_checked([] { sc_core::wait(sc_core::sc_time(2, sc_core::SC_US)); }, "late_body");
    sc_core::sc_start(sc_core::sc_time(1, sc_core::SC_US));
}

TEST(SpawnCheckedChild, FinishedBodyPasses) {
    bool ran = false;
    spawn_checked(
        [&] {
            sc_core::wait(sc_core::sc_time(10, sc_core::SC_NS));
            ran = true;
        },
        "done_body");
    sc_core::sc_start();
    EXPECT_TRUE(ran);
}

// A body spawned from a running thread is checked like one spawned before sc_start.
TEST(SpawnCheckedChild, StuckNestedBodyFails) {
    spawn_checked([] { spawn_checked([] { sc_core::wait(g_never); }, "inner_body"); }, "outer_body");
    sc_core::sc_start();
}

TEST(SpawnCheckedChild, ForeverBodyPasses) {
    spawn_forever(
        [] {
            for (;;) sc_core::wait(g_never);
        },
        "server_loop");
    sc_core::sc_start();
}

#ifdef RCSIM_SANITIZE_BUILD
// Signed overflow, which UBSan reports. If the report did not end the program, the sum would wrap
// and the test would pass: the sanitizer build must make it fail instead.
TEST(SanitizerChild, SignedOverflow) {
    volatile int big = INT_MAX;
    const int sum = big + 1;
    EXPECT_EQ(sum, INT_MIN);
}
#endif

// The body never runs: the test checks elaboration only.
TEST(SpawnCheckedChild, NeverStartedSimulationPasses) {
    spawn_checked([] { ADD_FAILURE() << "unreachable: the simulation is never started"; }, "unstarted_body");
}

// An error ends the simulation: the test expects it, the stuck body is its consequence.
TEST(SpawnCheckedChild, ExpectedErrorEndingTheSimulationPasses) {
    spawn_checked([] { sc_core::wait(g_never); }, "stuck_body");
    spawn_checked(
        [] {
            sc_core::wait(sc_core::sc_time(5, sc_core::SC_NS));
            SC_REPORT_ERROR("/rcsim/test", "deliberate error");
        },
        "failing_body");
    EXPECT_THROW(sc_core::sc_start(), sc_core::sc_report);
}
