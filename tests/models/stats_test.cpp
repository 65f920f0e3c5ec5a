#include "models/stats.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

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

namespace {

// The definition Samples keeps: every sample, sorted; nearest rank; the mean summed in order.
Summary summary_of_all(std::vector<double> v) {
    Summary s;
    s.count = v.size();
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    s.min = v.front();
    s.max = v.back();
    double sum = 0;
    for (double x : v) sum += x;
    s.mean = sum / static_cast<double>(v.size());
    auto rank = [&v](double pct) {
        const auto r = static_cast<std::size_t>(std::ceil(pct / 100.0 * static_cast<double>(v.size())));
        return v[std::clamp<std::size_t>(r, 1, v.size()) - 1];
    };
    s.p50 = rank(50);
    s.p99 = rank(99);
    return s;
}

// Like the run's latencies: whole 125 ns clocks from 6 to 1600 us, and about half of them a few
// picoseconds off the grid (an IR line that rose between two clocks).
std::vector<double> latencies(std::uint64_t seed, std::size_t n) {
    std::mt19937_64 rng(seed);
    std::vector<double> v;
    for (std::size_t i = 0; i < n; ++i) {
        const std::int64_t clocks = 48 + static_cast<std::int64_t>(rng() % 12800);
        const std::int64_t off = rng() % 2 ? static_cast<std::int64_t>(rng() % 125000) : 0;
        v.push_back(static_cast<double>(clocks * 125000 - off) / 1e6);
    }
    return v;
}

} // namespace

TEST(Samples, WhileExactTheSummaryIsThatOfEverySampleToTheBit) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
        const auto v = latencies(seed, 20000); // many merges of the pending batch, < capacity distinct
        Samples s(0.125, 1 << 15);
        for (double x : v) s.add(x);
        ASSERT_TRUE(s.exact());
        const Summary got = s.summary(), want = summary_of_all(v);
        EXPECT_EQ(got.count, want.count);
        EXPECT_EQ(got.min, want.min);
        EXPECT_EQ(got.max, want.max);
        EXPECT_EQ(got.mean, want.mean) << "the mean is summed over the sorted samples, as before";
        EXPECT_EQ(got.p50, want.p50);
        EXPECT_EQ(got.p99, want.p99);
    }
}

TEST(Samples, PastItsCapacityItKeepsValuesToHalfAResolution) {
    const auto v = latencies(9, 50000);
    Samples s(0.125, 1000);
    for (double x : v) s.add(x);
    EXPECT_FALSE(s.exact());
    const Summary got = s.summary(), want = summary_of_all(v);
    EXPECT_EQ(got.count, want.count);
    EXPECT_EQ(got.min, want.min);
    EXPECT_EQ(got.max, want.max);
    EXPECT_NEAR(got.mean, want.mean, 1e-9 * want.mean);
    EXPECT_NEAR(got.p50, want.p50, 0.0625);
    EXPECT_NEAR(got.p99, want.p99, 0.0625);
    // Memory: at most one value per resolution step of the span.
    EXPECT_LE(s.values().size(), static_cast<std::size_t>((want.max - want.min) / 0.125) + 2);
    std::uint64_t n = 0;
    for (const auto& [x, c] : s.values()) {
        EXPECT_EQ(x, std::nearbyint(x / 0.125) * 0.125) << "on the grid";
        n += c;
    }
    EXPECT_EQ(n, v.size());
}

TEST(Samples, ValuesOnTheGridStayExactWhenCoarsened) {
    // Service times are whole clocks: rounding leaves them as they are.
    std::mt19937_64 rng(3);
    std::vector<double> v;
    for (int i = 0; i < 30000; ++i) v.push_back(static_cast<double>(rng() % 40000) * 0.125);
    Samples s(0.125, 500);
    for (double x : v) s.add(x);
    EXPECT_FALSE(s.exact());
    const Summary got = s.summary(), want = summary_of_all(v);
    EXPECT_EQ(got.p50, want.p50);
    EXPECT_EQ(got.p99, want.p99);
    EXPECT_EQ(got.min, want.min);
    EXPECT_EQ(got.max, want.max);
}

TEST(Samples, TheSummaryIsAFunctionOfTheSamplesNotOfWhenItIsAsked) {
    for (std::size_t capacity : {std::size_t{1} << 15, std::size_t{300}}) {
        const auto v = latencies(11, 12000);
        Samples quiet(0.125, capacity), asked(0.125, capacity);
        for (std::size_t i = 0; i < v.size(); ++i) {
            quiet.add(v[i]);
            asked.add(v[i]);
            if (i % 997 == 0) (void)asked.summary(); // merges early
        }
        const Summary a = quiet.summary(), b = asked.summary();
        EXPECT_EQ(a.mean, b.mean);
        EXPECT_EQ(a.p50, b.p50);
        EXPECT_EQ(a.p99, b.p99);
        EXPECT_EQ(quiet.values(), asked.values());
    }
}

TEST(Samples, TheResolutionIsTheConstructors) {
    Samples s(1.0, 2); // whole units once there are more than two distinct values
    for (double x : {0.4, 1.4, 2.6, 2.6}) s.add(x);
    const Summary m = s.summary();
    EXPECT_FALSE(s.exact());
    EXPECT_EQ(s.resolution(), 1.0);
    const std::vector<std::pair<double, std::uint64_t>> want = {{0.0, 1}, {1.0, 1}, {3.0, 2}};
    EXPECT_EQ(s.values(), want);
    EXPECT_DOUBLE_EQ(m.min, 0.4); // min and max are kept exactly
    EXPECT_DOUBLE_EQ(m.max, 2.6);
    EXPECT_DOUBLE_EQ(m.p50, 1.0);
    EXPECT_DOUBLE_EQ(m.p99, 2.6); // 3.0, clamped into [min, max]
    EXPECT_DOUBLE_EQ(m.mean, (0.4 + 1.4 + 2.6 + 2.6) / 4);
    s.clear();
    EXPECT_TRUE(s.exact());
    EXPECT_EQ(s.count(), 0u);
}

// The over-budget counts of every output (report.json, the live page, Modbus) are this one count.
TEST(Samples, CountAboveCountsTheSamplesStrictlyOverTheLimit) {
    Samples s;
    EXPECT_EQ(s.count_above(0), 0u);
    for (double v : {1.0, 2.0, 2.0, 3.0, 381.875, 382.0}) s.add(v);
    EXPECT_EQ(s.count_above(0.5), 6u);
    EXPECT_EQ(s.count_above(2.0), 3u); // equal to the limit is not over it
    EXPECT_EQ(s.count_above(1.5), 5u);
    EXPECT_EQ(s.count_above(381.9), 1u);
    EXPECT_EQ(s.count_above(382.0), 0u);
}
