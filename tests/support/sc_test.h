// rcsim — test harness for SystemC models.
//
// Every test executable links rcsim_test_support, whose sc_main runs GoogleTest. Any SystemC
// warning fails the running test (ADD_FAILURE) unless the test opts in with ScAllowWarnings; errors
// keep SystemC's default action (throw sc_report), so EXPECT_THROW can assert them and an
// unexpected one fails the test. CTest runs each TEST in its own process (gtest_discover_tests),
// so each test may elaborate its own modules and call sc_start.
#pragma once

#include <gtest/gtest.h>
#include <systemc>

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

/// Directory holding the SingleStepTests 8086 vectors, or "" when absent
/// ($RCSIM_SST_DIR, else ../shared/sst8086/v1 beside the source tree).
std::string sst_dir();

} // namespace rcsim::test
