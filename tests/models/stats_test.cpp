#include "models/stats.h"

#include <gtest/gtest.h>

using namespace rcsim;

TEST(Samples, SummaryUsesNearestRank) {
    Samples s;
    for (int i = 100; i >= 1; --i) s.add(i);
    const Summary m = s.summary();
    EXPECT_EQ(m.count, 100u);
    EXPECT_DOUBLE_EQ(m.min, 1);
    EXPECT_DOUBLE_EQ(m.max, 100);
    EXPECT_DOUBLE_EQ(m.mean, 50.5);
    EXPECT_DOUBLE_EQ(m.p50, 50);
    EXPECT_DOUBLE_EQ(m.p99, 99);
}

TEST(Samples, EmptySummaryIsZero) {
    const Summary m = Samples{}.summary();
    EXPECT_EQ(m.count, 0u);
    EXPECT_EQ(to_json(m)["max"], 0.0);
}
