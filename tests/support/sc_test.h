// rcsim — test harness for SystemC models.
//
// Every test executable links rcsim_test_support, whose sc_main runs GoogleTest. Any SystemC
// warning fails the running test (ADD_FAILURE) unless the test opts in with ScAllowWarnings; errors
// keep SystemC's default action (throw sc_report), so EXPECT_THROW can assert them and an
// unexpected one fails the test. CTest runs each TEST in its own process (gtest_discover_tests),
// so each test may elaborate its own modules and call sc_start.
//
// A test body that runs as a SystemC thread starts with spawn_checked (or, if it loops by design,
// spawn_forever), never with a bare sc_spawn or SC_THREAD: a body stuck in a wait() that never
// returns would otherwise skip every EXPECT after that wait without a trace.
#pragma once

#include <gtest/gtest.h>
#include <systemc>

#include <functional>
#include <string>
#include <vector>

namespace rcsim::test {

/// While alive, SystemC warnings are recorded instead of failing the test.
class ScAllowWarnings {
public:
    ScAllowWarnings();
    ~ScAllowWarnings();
    const std::vector<std::string>& messages() const;
};

/// Spawns `body` as a SystemC thread that must run to its end: when the test ends (after its last
/// sc_start), a checked body that has not returned fails the test, named by its process name.
/// Call it before sc_start (from a module's constructor it spawns a child of that module, as
/// SC_THREAD does) or from a running thread. `name` nullptr: SystemC picks a unique one.
sc_core::sc_process_handle spawn_checked(std::function<void()> body, const char* name = nullptr);

/// Spawns a thread that by design never returns (a device's service loop, an edge logger); the
/// completion check leaves it out. The name says at the call site that the loop is intended.
sc_core::sc_process_handle spawn_forever(std::function<void()> body, const char* name = nullptr);

/// Fails the running test once for every spawn_checked body that has not returned, then forgets
/// them all. Runs when each test ends; a test may call it earlier (outside sc_start). Nothing is
/// checked unless sc_start has returned normally: a test that never starts the simulation has
/// run no body, and one whose sc_start threw has the exception as its verdict.
void expect_bodies_finished();

/// Directory holding the SingleStepTests 8086 vectors, or "" when absent
/// ($RCSIM_SST_DIR, else ../shared/sst8086/v1 beside the source tree).
std::string sst_dir();

} // namespace rcsim::test
