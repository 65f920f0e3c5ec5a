// The chart module's nice axes and decimation (scenarios/report/svg.h): known answers of the nice-step
// and nice-range rules, min/max per pixel column keeping every extreme, and trajectory pictures
// of a long run staying under 2 MB.
#include "scenarios/report/svg.h"
#include "scenarios/report/trajectory_report.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace rcsim;
using namespace rcsim::svg;

// A step of 1, 2 or 5 x 10^k at least span / target.
TEST(SvgNice, StepKnownAnswers) {
    EXPECT_DOUBLE_EQ(nice_step(1100, 8), 200);  // 137.5 -> 200
    EXPECT_DOUBLE_EQ(nice_step(11, 5), 5);      // 2.2 -> 5
    EXPECT_DOUBLE_EQ(nice_step(0.9, 3), 0.5);   // 0.3 -> 0.5
    EXPECT_DOUBLE_EQ(nice_step(100, 10), 10);   // 10 -> 10
    EXPECT_DOUBLE_EQ(nice_step(12000, 8), 2000); // 1500 -> 2000
}

// The bounds out to multiples of the step: an axis starts and ends on a tick.
TEST(SvgNice, RangeKnownAnswers) {
    auto eq = [](NiceRange r, double lo, double hi, double step) {
        EXPECT_DOUBLE_EQ(r.lo, lo);
        EXPECT_DOUBLE_EQ(r.hi, hi);
        EXPECT_DOUBLE_EQ(r.step, step);
    };
    eq(nice_range(0, 1000, 8), 0, 1000, 200);
    eq(nice_range(-10500, 500, 8), -12000, 2000, 2000); // the circle of the paper, start at 0
    eq(nice_range(3, 97, 10), 0, 100, 10);
    eq(nice_range(0.013, 0.087, 4), 0, 0.1, 0.02);
    eq(nice_range(5, 5, 5), 4, 6, 1);   // no span: one step either side
    eq(nice_range(-31, 32, 4), -40, 40, 20); // 15.75 -> 20
}

TEST(SvgDecimation, ColumnsKeepEveryExtremeInTimeOrder) {
    ColumnDecimator d(0, 1, 500);
    const int n = 1000000;
    for (int i = 0; i < n; ++i) {
        const double t = i / double(n);
        double v = std::sin(20 * t);
        if (i == 123457) v = 1000; // one-sample spikes must survive
        if (i == 777777) v = -500;
        d.add(t, v);
    }
    const auto p = d.points();
    EXPECT_LE(p.size(), 4u * 500u);
    EXPECT_EQ(d.samples(), std::size_t(n));
    double hi = -1e9, lo = 1e9, t_hi = 0, t_lo = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p[i].second > hi) hi = p[i].second, t_hi = p[i].first;
        if (p[i].second < lo) lo = p[i].second, t_lo = p[i].first;
        if (i) {
            EXPECT_LE(p[i - 1].first, p[i].first) << "time order";
        }
    }
    EXPECT_EQ(hi, 1000);
    EXPECT_DOUBLE_EQ(t_hi, 123457 / double(n));
    EXPECT_EQ(lo, -500);
    EXPECT_DOUBLE_EQ(t_lo, 777777 / double(n));
    EXPECT_EQ(p.front().first, 0.0);                 // the first sample
    EXPECT_DOUBLE_EQ(p.back().first, (n - 1) / double(n)); // and the last
}

TEST(SvgDecimation, PathMergesNeighboursAndBecomesCellsWhenLong) {
    PathDecimator p(100, 100, 0.5, 50, 2);
    p.add({10, 10});
    p.add({10.2, 10.3}); // closer than 0.5 px: merged
    p.add({11, 10});
    EXPECT_FALSE(p.as_cells());
    EXPECT_EQ(p.points().size(), 2u);
    // Round and round a circle: the polyline outgrows 50 points, then only cells are kept.
    for (int i = 0; i < 10000; ++i) {
        const double a = i * 0.05;
        p.add({50 + 30 * std::cos(a), 50 + 30 * std::sin(a)});
    }
    ASSERT_TRUE(p.as_cells());
    EXPECT_TRUE(p.points().empty());
    const auto cells = p.cells();
    EXPECT_GT(cells.size(), 50u);
    // A circle of radius 30 px crosses about 2 pi 30 / 2 px cells, with the diagonals at most
    // twice that; far fewer than the 51 x 51 grid.
    EXPECT_LE(cells.size(), 2u * 95u + 2u);
}

// A long run (200000 control cycles of 10 us, 20 laps of the paper's circle with a one-pulse
// wobble on the actual path): both pictures stay under 2 MB.
TEST(SvgDecimation, LongRunPicturesStayUnderTwoMegabytes) {
    motion::TrajectoryRecorder r;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        const double a = 20 * 6.283185307179586 * i / n;
        const std::int64_t x = std::llround(-5000 + 5000 * std::cos(a)), y = std::llround(5000 * std::sin(a));
        r.add(i * 1e-5, {x, y, 0, 0}, {x + (i % 3) - 1, y - (i % 2), 0, 0});
    }
    const std::string xy = trajectory_svg(r, 0, 1, "long");
    const std::string time = trajectory_time_svg(r, "long", CircleOverlay{-5000, 0, 5000, 0, 2});
    EXPECT_LT(xy.size(), 2u << 20) << xy.size();
    EXPECT_LT(time.size(), 2u << 20) << time.size();
    // The 20 laps are drawn from the recorder's reduced samples (main_cpu/motion/trajectory.h).
    EXPECT_TRUE(r.reduced());
    EXPECT_TRUE(xy.find("<polyline") != std::string::npos || xy.find("<path fill=") != std::string::npos) << xy;
}
