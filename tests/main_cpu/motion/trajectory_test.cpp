// The trajectory recorder's bounded memory (main_cpu/motion/trajectory.h, issue #48 item 3): the
// pictures' samples stay under the cap and keep every peak, the latest samples and the judged
// window are kept whole, the largest following error is exact.
#include "main_cpu/motion/trajectory.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace rcsim::motion {
namespace {

constexpr std::size_t kCap = 1024, kRecent = 64;

/// Sample `i` of a run of 1 ms cycles: axis 0 ramps, axis 1 follows a sine, the actual position
/// one pulse behind; at `spike` the actual position of axis 1 is `jump` pulses off.
void add(TrajectoryRecorder& r, std::int64_t i, std::int64_t spike = -1, std::int64_t jump = 0) {
    const std::int64_t x = i, y = std::llround(1000 * std::sin(double(i) / 500));
    r.add(double(i) * 1e-3, {x, y}, {x - 1, y - (i == spike ? jump : 0)});
}

TEST(TrajectoryRecorder, ShortRunKeepsEverySample) {
    TrajectoryRecorder r(kCap, kRecent);
    for (int i = 0; i < 500; ++i) add(r, i);
    EXPECT_FALSE(r.reduced());
    const auto v = r.plot_samples();
    ASSERT_EQ(v.size(), 500u);
    for (int i = 0; i < 500; ++i) EXPECT_DOUBLE_EQ(v[std::size_t(i)].t_s, i * 1e-3);
    EXPECT_EQ(r.count(), 500u);
}

// 200 times the cap: the pictures' samples stay at most the cap, in time order, from the first
// sample to the last.
TEST(TrajectoryRecorder, LongRunPicturesStayUnderTheCap) {
    TrajectoryRecorder r(kCap, kRecent);
    const std::int64_t n = 200 * std::int64_t(kCap);
    for (std::int64_t i = 0; i < n; ++i) add(r, i);
    EXPECT_TRUE(r.reduced());
    const auto v = r.plot_samples();
    EXPECT_LE(v.size(), kCap);
    EXPECT_GT(v.size(), kCap / 8) << "the pictures keep enough for their 640 columns";
    EXPECT_DOUBLE_EQ(v.front().t_s, 0);
    EXPECT_DOUBLE_EQ(v.back().t_s, double(n - 1) * 1e-3);
    EXPECT_TRUE(std::is_sorted(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.t_s < b.t_s; }));
    EXPECT_EQ(r.count(), std::uint64_t(n));
}

// A one-cycle following-error spike of 37 pulses deep in a long run survives the reduction, with
// its velocity (37 pulses in 1 ms, then back): a picture shows the peak, not an average.
TEST(TrajectoryRecorder, PeaksSurviveTheReduction) {
    TrajectoryRecorder r(kCap, kRecent);
    const std::int64_t n = 100 * std::int64_t(kCap), spike = n / 2 + 17;
    for (std::int64_t i = 0; i < n; ++i) add(r, i, spike, 37);
    const auto v = r.plot_samples();
    double worst = 0, fastest = 0;
    for (const auto& s : v) {
        worst = std::max(worst, double(s.cmd[1] - s.act[1]));
        if (s.has_velocity) fastest = std::max(fastest, std::abs(s.vel_act[1]));
    }
    EXPECT_DOUBLE_EQ(worst, 37.0);
    EXPECT_GE(fastest, 37.0 / 1e-3);
    EXPECT_DOUBLE_EQ(r.max_following_error(), 37.0);
}

TEST(TrajectoryRecorder, KeepsTheLatestSamples) {
    TrajectoryRecorder r(kCap, kRecent);
    for (int i = 0; i < 1000; ++i) add(r, i);
    ASSERT_EQ(r.recent().size(), kRecent);
    EXPECT_EQ(r.recent_first(), 1000u - kRecent);
    EXPECT_DOUBLE_EQ(r.recent().front().t_s, double(1000 - kRecent) * 1e-3);
    ASSERT_NE(r.last(), nullptr);
    EXPECT_DOUBLE_EQ(r.last()->t_s, 0.999);
    EXPECT_DOUBLE_EQ(r.last(1)->t_s, 0.998);
    EXPECT_EQ(r.last(kRecent), nullptr);
    // Velocity from the previous cycle: axis 0 ramps one pulse a cycle, 1000 pulses/s.
    EXPECT_TRUE(r.last()->has_velocity);
    EXPECT_NEAR(r.last()->vel_cmd[0], 1000.0, 1e-9);
}

// The window (the circle the checks judge) keeps every sample, however long the run around it.
TEST(TrajectoryRecorder, WindowKeepsEverySampleInIt) {
    TrajectoryRecorder r(kCap, kRecent);
    for (int i = 0; i < 5000; ++i) add(r, i);
    r.start_window();
    for (int i = 5000; i < 8000; ++i) add(r, i);
    r.end_window();
    for (int i = 8000; i < 20000; ++i) add(r, i);
    ASSERT_EQ(r.window().size(), 3000u);
    EXPECT_DOUBLE_EQ(r.window().front().t_s, 5.0);
    EXPECT_DOUBLE_EQ(r.window().back().t_s, 7.999);
    r.start_window(); // a new window drops the last one's
    add(r, 20000);
    EXPECT_EQ(r.window().size(), 1u);
}

TEST(TrajectoryRecorder, SinksGetEverySampleInOrder) {
    TrajectoryRecorder r(kCap, kRecent);
    std::vector<double> seen;
    r.on_sample([&seen](const TrajectorySample& s) { seen.push_back(s.t_s); });
    for (int i = 0; i < 3000; ++i) add(r, i);
    ASSERT_EQ(seen.size(), 3000u);
    EXPECT_DOUBLE_EQ(seen[2999], 2.999);
}

} // namespace
} // namespace rcsim::motion
