#include "models/clock.h"

#include <gtest/gtest.h>

using namespace rcsim;

TEST(Clock, EightMegahertzIs125NsExactly) {
    Clock c(8'000'000);
    EXPECT_TRUE(c.exact());
    EXPECT_EQ(c.period_ps(), 125000u);
    EXPECT_EQ(c.cycles(1), sc_core::sc_time(125, sc_core::SC_NS));
    EXPECT_EQ(c.cycles(8'000'000), sc_core::sc_time(1, sc_core::SC_SEC)); // beyond the table
    EXPECT_EQ(c.cycles(511), ps(511 * 125000ULL));                        // last table entry
}

TEST(Clock, ConvertsTimeBackToCycles) {
    Clock c(8'000'000);
    EXPECT_EQ(c.to_cycles(ns(1000)), 8u);
    EXPECT_EQ(c.to_cycles(ns(1100)), 8u);
    EXPECT_EQ(c.to_cycles_ceil(ns(1100)), 9u);
    EXPECT_EQ(c.to_cycles_ceil(ns(1000)), 8u);
}

TEST(Clock, InexactPeriodIsRoundedToNearestPicosecond) {
    Clock c(18'432'000);
    EXPECT_FALSE(c.exact());
    EXPECT_EQ(c.period_ps(), 54253u); // 54253.47 ps
}

// The integer helpers agree with SystemC's own units (which go through double).
TEST(Clock, TimeHelpersAreTheirUnits) {
    EXPECT_EQ(ns(7), sc_core::sc_time(7, sc_core::SC_NS));
    EXPECT_EQ(us(7), sc_core::sc_time(7, sc_core::SC_US));
    EXPECT_EQ(ms(7), sc_core::sc_time(7, sc_core::SC_MS));
    EXPECT_EQ(ms(3'600'000), sc_core::sc_time(3600, sc_core::SC_SEC)); // an hour, far from overflow
}

TEST(Clock, RejectsZeroFrequency) { EXPECT_THROW(Clock(0), std::invalid_argument); }
