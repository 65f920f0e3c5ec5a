// models/plumbing/sim_time_text.h: simulated times as issue #51 item 3 writes them.
#include "models/plumbing/sim_time_text.h"

#include <gtest/gtest.h>

#include <limits>

namespace rcsim {
namespace {

TEST(SimTimeText, GroupsMillisecondsMicrosecondsNanoseconds) {
    // The issue's own example: 1466138.750 us.
    EXPECT_EQ(sim_time_text(1.46613875), "1.466 138 750 s");
    EXPECT_EQ(sim_time_text_us(1466138.750), "1.466 138 750 s");
    EXPECT_EQ(sim_time_text_us(5146975.5), "5.146 975 500 s");
}

TEST(SimTimeText, LeavesOutTrailingGroupsOfZerosButKeepsMilliseconds) {
    EXPECT_EQ(sim_time_text(2), "2.000 s");
    EXPECT_EQ(sim_time_text(0), "0.000 s");
    EXPECT_EQ(sim_time_text(0.05), "0.050 s");
    EXPECT_EQ(sim_time_text_us(382), "0.000 382 s");
    EXPECT_EQ(sim_time_text_us(0.125), "0.000 000 125 s"); // one 8 MHz clock
    EXPECT_EQ(sim_time_text(3600), "3600.000 s");
}

TEST(SimTimeText, RoundsToTheNanosecond) {
    EXPECT_EQ(sim_time_text(1.0000000004), "1.000 s");
    EXPECT_EQ(sim_time_text(0.9999999996), "1.000 s"); // the carry reaches the seconds
    EXPECT_EQ(sim_time_text_us(1.0006), "0.000 001 001 s");
}

TEST(SimTimeText, NegativeAndNotANumber) {
    EXPECT_EQ(sim_time_text(-0.0015), "-0.001 500 s");
    EXPECT_EQ(sim_time_text(-0.0000000001), "0.000 s"); // no "-0.000"
    EXPECT_EQ(sim_time_text(std::numeric_limits<double>::quiet_NaN()), "-");
    EXPECT_EQ(sim_time_text(std::numeric_limits<double>::infinity()), "-");
    EXPECT_EQ(sim_time_text(2e10), "20000000000.000 s"); // beyond 64-bit nanoseconds: no groups, no overflow
}

} // namespace
} // namespace rcsim
