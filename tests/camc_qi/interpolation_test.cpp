// Tests of the CAMC-QI interpolators: thousands of seeded random cases against independent
// oracles (a step-by-step DDA accumulator, the ideal line/circle, the step-count formula).
#include "camc_qi/interpolation.h"
#include "tests/support/sc_test.h"

#include <cmath>
#include <cstdlib>
#include <random>

using namespace rcsim::camc;

namespace {

std::int64_t iabs(std::int64_t v) { return v < 0 ? -v : v; }

// ---------------------------------------------------------------------------------------------
// Linear

/// The chip's DDA as a step-by-step oracle: long axis every step, others by accumulator.
struct DdaOracle {
    std::array<std::int64_t, 4> pos{}, acc{};
    std::array<std::int64_t, 4> d{};
    std::int64_t L = 0;
    unsigned n = 0;
    DdaOracle(const std::int64_t* delta, unsigned axes) : n(axes) {
        for (unsigned i = 0; i < axes; ++i) {
            d[i] = delta[i];
            L = std::max(L, iabs(delta[i]));
        }
    }
    void step() {
        for (unsigned i = 0; i < n; ++i) {
            acc[i] += iabs(d[i]);
            if (2 * acc[i] >= L) {
                pos[i] += d[i] < 0 ? -1 : 1;
                acc[i] -= L;
            }
        }
    }
};

TEST(LinearInterpolation, RandomCasesMatchDdaStayWithinHalfPulseAndEndExactly) {
    std::mt19937_64 rng(0x6c696e65);
    int cases = 0;
    for (int c = 0; c < 4000; ++c) {
        const unsigned axes = 2 + static_cast<unsigned>(rng() % 3);
        const std::int64_t span = (c % 4 == 0) ? 5 : (c % 4 == 1 ? 200 : 3000);
        std::int64_t delta[4];
        for (unsigned i = 0; i < axes; ++i)
            delta[i] = static_cast<std::int64_t>(rng() % (2 * span + 1)) - span;
        LinearPath path(delta, axes);
        DdaOracle dda(delta, axes);
        ASSERT_EQ(path.steps(), static_cast<std::uint64_t>(dda.L));
        const double L = static_cast<double>(dda.L);
        for (std::uint64_t k = 1; k <= path.steps(); ++k) {
            dda.step();
            double dist2 = 0, len2 = 0, dot = 0;
            for (unsigned i = 0; i < axes; ++i) {
                const std::int64_t p = path.position(i, k);
                ASSERT_EQ(p, dda.pos[i]) << "case " << c << " axis " << i << " step " << k;
                ASSERT_LE(iabs(p - path.position(i, k - 1)), 1); // one pulse per step at most
                const double ideal = static_cast<double>(delta[i]) * static_cast<double>(k) / L;
                ASSERT_LE(std::abs(static_cast<double>(p) - ideal), 0.5 + 1e-12);
                dot += static_cast<double>(p) * static_cast<double>(delta[i]);
                len2 += static_cast<double>(delta[i]) * static_cast<double>(delta[i]);
                dist2 += static_cast<double>(p) * static_cast<double>(p);
            }
            // Perpendicular distance to the ideal line through the origin.
            const double perp2 = dist2 - dot * dot / len2;
            ASSERT_LE(perp2, 0.25 * axes + 1e-9);
        }
        for (unsigned i = 0; i < axes; ++i) ASSERT_EQ(path.position(i, path.steps()), delta[i]);
        ++cases;
    }
    EXPECT_EQ(cases, 4000);
}

TEST(LinearInterpolation, LargeDistancesSampledAndPaperPlotterLine) {
    std::mt19937_64 rng(7);
    for (int c = 0; c < 2000; ++c) {
        std::int64_t delta[2] = {static_cast<std::int64_t>(rng() % 2000000001) - 1000000000,
                                 static_cast<std::int64_t>(rng() % 2000000001) - 1000000000};
        LinearPath path(delta, 2);
        const double L = static_cast<double>(path.steps());
        for (int s = 0; s < 50; ++s) {
            const std::uint64_t k = rng() % (path.steps() + 1);
            for (unsigned i = 0; i < 2; ++i) {
                const double ideal = static_cast<double>(delta[i]) * static_cast<double>(k) / L;
                ASSERT_LE(std::abs(static_cast<double>(path.position(i, k)) - ideal), 0.5 + 1e-6);
            }
        }
        EXPECT_EQ(path.position(0, path.steps()), delta[0]);
        EXPECT_EQ(path.position(1, path.steps()), delta[1]);
    }
    // A belt plotter at 80 pulses/mm (3200 microsteps a turn, 40 mm a turn): (0,0)->(100,60) mm =
    // (8000, 4800) pulses: 8000 steps (the long axis), Y emits 4800.
    const std::int64_t d[2] = {8000, 4800};
    LinearPath line(d, 2);
    EXPECT_EQ(line.steps(), 8000u);
    EXPECT_EQ(line.position(1, 8000), 4800);
}

TEST(LinearInterpolation, BadAxisCountAndRangeAreRejected) {
    const std::int64_t d[5] = {1, 2, 3, 4, 5};
    EXPECT_THROW(LinearPath(d, 5), InterpolationError);
    EXPECT_THROW(LinearPath(d, 0), InterpolationError);
    const std::int64_t big[2] = {max_coordinate + 1, 0};
    try {
        LinearPath p(big, 2);
        FAIL();
    } catch (const InterpolationError& e) {
        EXPECT_NE(std::string(e.what()).find(std::to_string(max_coordinate + 1)), std::string::npos);
    }
}

// ---------------------------------------------------------------------------------------------
// Circular

/// Walks `path` step by step and checks the step invariants; returns the max radial error.
double check_walk(CirclePath& path, std::uint64_t expected_steps, const char* what) {
    const double R = std::sqrt(static_cast<double>(path.radius_squared()));
    double worst = 0;
    Point prev = path.at(0);
    EXPECT_EQ(prev, path.start());
    for (std::uint64_t k = 1; k <= expected_steps; ++k) {
        const Point p = path.at(k);
        const std::int64_t dx = iabs(p.x - prev.x), dy = iabs(p.y - prev.y);
        // Exactly one short-axis pulse every step, the long axis zero or one.
        EXPECT_TRUE((dx == 1 && dy <= 1) || (dy == 1 && dx <= 1)) << what << " step " << k;
        const double r = std::sqrt(static_cast<double>(p.x) * p.x + static_cast<double>(p.y) * p.y);
        worst = std::max(worst, std::abs(r - R));
        prev = p;
    }
    return worst;
}

Point random_start(std::mt19937_64& rng, std::int64_t rmax) {
    for (;;) {
        const Point p{static_cast<std::int64_t>(rng() % (2 * rmax + 1)) - rmax,
                      static_cast<std::int64_t>(rng() % (2 * rmax + 1)) - rmax};
        if (p != Point{}) return p;
    }
}

TEST(CircularInterpolation, FullCirclesCloseWithFormulaStepsAndUnitRadialError) {
    std::mt19937_64 rng(0x63697263);
    double worst = 0;
    int octant_hits[8] = {};
    for (int c = 0; c < 3000; ++c) {
        const std::int64_t rmax = c % 3 == 0 ? 3 : (c % 3 == 1 ? 60 : 2500);
        const Point s = random_start(rng, rmax);
        const ArcDirection dir = (rng() & 1) ? ArcDirection::cw : ArcDirection::ccw;
        ++octant_hits[octant_of(s, dir)];
        CirclePath full(s, s, dir);
        const std::uint64_t steps = circle_step_count(s, s, dir);
        ASSERT_EQ(full.steps(), steps);
        ASSERT_EQ(full.walk_to_end(), steps) << "start " << s.x << "," << s.y;
        ASSERT_EQ(full.walked_end(), s); // the circle closes exactly
        worst = std::max(worst, check_walk(full, steps, "full circle"));
        // Every axis emits 4R pulses per full circle when the start is on an axis; in general the
        // formula and the real-number sum (4*sqrt(2)*R) differ by < 1 per diagonal border (4).
        EXPECT_LE(std::abs(static_cast<double>(steps) - circle_step_count_real(s, s, dir)), 4.0 + 1e-9)
            << s.x << "," << s.y;
    }
    for (int o = 0; o < 8; ++o) EXPECT_GT(octant_hits[o], 100) << "octant " << o;
    EXPECT_LE(worst, 1.0); // MCX514: radial error within 1 LSB
}

TEST(CircularInterpolation, RandomArcsAcrossOctantsEndExactlyWithFormulaSteps) {
    std::mt19937_64 rng(0x61726373);
    int multi_octant = 0, same_octant = 0;
    for (int c = 0; c < 4000; ++c) {
        const std::int64_t rmax = c % 4 == 0 ? 4 : (c % 4 == 1 ? 100 : 1500);
        const Point s = random_start(rng, rmax);
        const ArcDirection dir = (rng() & 1) ? ArcDirection::cw : ArcDirection::ccw;
        // The end point: a random point of the track (taken from a full-circle walk).
        CirclePath full(s, s, dir);
        const std::uint64_t j = 1 + rng() % full.steps();
        const Point e = full.at(j);
        const std::uint64_t steps = circle_step_count(s, e, dir);
        ASSERT_EQ(steps, j) << "start " << s.x << "," << s.y << " end " << e.x << "," << e.y;
        CirclePath arc(s, e, dir);
        ASSERT_EQ(arc.walk_to_end(), steps);
        ASSERT_EQ(arc.walked_end(), e);
        const int so = octant_of(s, dir), eo = end_octant_of(e, dir);
        (so == eo && j < full.steps() / 8 ? same_octant : multi_octant)++;
    }
    EXPECT_GT(multi_octant, 1000);
    EXPECT_GT(same_octant, 50);
}

TEST(CircularInterpolation, EndPointsRoundedFromAnglesEndWithinOnePulse) {
    // A host computes the end point from an angle and rounds it: the chip stops when the short
    // axis reaches the end's short coordinate; the long axis lands within one pulse of it.
    std::mt19937_64 rng(42);
    const double pi = std::acos(-1.0);
    int accepted = 0;
    for (int c = 0; c < 3000; ++c) {
        const double R = 5.0 + static_cast<double>(rng() % 20000);
        const double a = (rng() % 36000) * pi / 18000, b = (rng() % 36000) * pi / 18000;
        const Point s{std::llround(R * std::cos(a)), std::llround(R * std::sin(a))};
        const Point e{std::llround(R * std::cos(b)), std::llround(R * std::sin(b))};
        const ArcDirection dir = (c & 1) ? ArcDirection::cw : ArcDirection::ccw;
        std::uint64_t steps = 0;
        try {
            steps = circle_step_count(s, e, dir);
        } catch (const InterpolationError&) {
            continue; // the rounded end fell just outside the track's reach in its octant
        }
        CirclePath arc(s, e, dir);
        ASSERT_EQ(arc.walk_to_end(), steps);
        const Point got = arc.walked_end();
        EXPECT_LE(iabs(got.x - e.x), 1) << c;
        EXPECT_LE(iabs(got.y - e.y), 1) << c;
        ++accepted;
    }
    EXPECT_GT(accepted, 2700); // nearly every rounded end is on the track
}

TEST(CircularInterpolation, WalkedEndInClosedFormIsWhereTheWalkStops) {
    // circle_walked_end() (no walk) against the interpolator's own walk, for ends on and off the
    // track, radii from 1 pulse (whose border steps lag the track) up; off-track ends exist.
    std::mt19937_64 rng(7);
    const double pi = std::acos(-1.0);
    int off_track = 0, checked = 0;
    for (int c = 0; c < 2000; ++c) {
        const double R = 1.0 + static_cast<double>(rng() % (c < 500 ? 12 : 5000));
        const double a = (rng() % 3600) * pi / 1800, b = (rng() % 3600) * pi / 1800;
        const Point s{std::llround(R * std::cos(a)), std::llround(R * std::sin(a))};
        const Point e{std::llround(R * std::cos(b)), std::llround(R * std::sin(b))};
        if (s == Point{} || e == Point{}) continue;
        const ArcDirection dir = (c & 1) ? ArcDirection::cw : ArcDirection::ccw;
        CircleWalk w;
        try {
            w = circle_walk(s, e, dir);
        } catch (const InterpolationError&) {
            continue;
        }
        CirclePath arc(s, e, dir);
        ASSERT_EQ(arc.walk_to_end(), w.steps) << c;
        ASSERT_EQ(arc.walked_end(), w.end) << c << " R " << R;
        EXPECT_EQ(circle_walked_end(s, e, dir), w.end);
        off_track += w.end != e;
        ++checked;
    }
    EXPECT_GT(checked, 1500);
    EXPECT_GT(off_track, 10);
}

TEST(CircularInterpolation, PaperAndChipFigures) {
    // Full circle R=1000 from (R,0) (centre at (-1000,0) from the start): 4*sqrt(2)*R = 5657
    // steps to within the rounding of the 4 diagonal borders; each axis emits 4R pulses.
    const Point s{1000, 0};
    const std::uint64_t n = circle_step_count(s, s, ArcDirection::ccw);
    EXPECT_NEAR(static_cast<double>(n), 4 * std::sqrt(2.0) * 1000, 2.0);
    CirclePath full(s, s, ArcDirection::ccw);
    std::int64_t px = 0, py = 0;
    Point prev = full.at(0);
    for (std::uint64_t k = 1; k <= n; ++k) {
        const Point p = full.at(k);
        px += iabs(p.x - prev.x);
        py += iabs(p.y - prev.y);
        prev = p;
    }
    EXPECT_EQ(px, 4000);
    EXPECT_EQ(py, 4000);
    // Quarter arc R=4000: each 45-degree octant takes R*sin(45) = R/sqrt(2) steps of its short axis,
    // two octants sqrt(2)*4000 = 5657 steps (camc_qi/README.md), each axis 4000 pulses.
    const std::uint64_t q = circle_step_count({4000, 0}, {0, 4000}, ArcDirection::ccw);
    EXPECT_NEAR(static_cast<double>(q), std::sqrt(2.0) * 4000, 1.0);
    // The plotter circle: R=5000.
    EXPECT_NEAR(static_cast<double>(circle_step_count({5000, 0}, {5000, 0}, ArcDirection::cw)),
                4 * std::sqrt(2.0) * 5000, 2.0);
    // MCX514's example: start (0,0), centre (-200,500), end (-702,299), CCW: ends when Y = 299.
    // That end lies 2.2 pulses outside the track; the long axis stays on the track.
    const Point st{200, -500}, en{-702 + 200, 299 - 500};
    CirclePath ex(st, en, ArcDirection::ccw);
    ex.walk_to_end();
    EXPECT_EQ(ex.walked_end().y, en.y);
    const double r = std::hypot(static_cast<double>(ex.walked_end().x), static_cast<double>(ex.walked_end().y));
    EXPECT_LE(std::abs(r - std::sqrt(static_cast<double>(ex.radius_squared()))), 1.0);
    EXPECT_EQ(ex.walked_end().x, -500);
}

TEST(CircularInterpolation, LargeRadiiFullCircleAndQuarter) {
    for (std::int64_t R : {1000000LL, 12345678LL}) {
        const Point s{R, 0};
        CirclePath full(s, s, ArcDirection::ccw);
        const std::uint64_t n = full.steps();
        EXPECT_NEAR(static_cast<double>(n), 4 * std::sqrt(2.0) * static_cast<double>(R), 4.0);
        if (R <= 1000000) {
            EXPECT_EQ(full.walk_to_end(), n);
            EXPECT_EQ(full.walked_end(), s);
        }
        // Random spot checks of the walk's radial error.
        double worst = 0;
        for (std::uint64_t k = 0; k <= n; k += n / 997 + 1) {
            const Point p = full.at(k);
            const double r = std::hypot(static_cast<double>(p.x), static_cast<double>(p.y));
            worst = std::max(worst, std::abs(r - static_cast<double>(R)));
        }
        EXPECT_LE(worst, 1.0);
    }
}

TEST(CircularInterpolation, TinyRadii) {
    // R=1: four diagonal steps round the circle.
    EXPECT_EQ(circle_step_count({1, 0}, {1, 0}, ArcDirection::ccw), 4u);
    EXPECT_EQ(circle_step_count({1, 0}, {0, 1}, ArcDirection::ccw), 1u);
    EXPECT_EQ(circle_step_count({1, 0}, {0, -1}, ArcDirection::cw), 1u);
    CirclePath p({1, 1}, {1, 1}, ArcDirection::cw);
    EXPECT_EQ(p.walk_to_end(), p.steps());
    EXPECT_EQ(p.walked_end(), (Point{1, 1}));
}

TEST(CircularInterpolation, BadDataIsRejectedWithTheOffendingValue) {
    EXPECT_THROW(circle_step_count({0, 0}, {1, 0}, ArcDirection::cw), InterpolationError);
    EXPECT_THROW(circle_step_count({10, 0}, {0, 0}, ArcDirection::cw), InterpolationError);
    try {
        // End octant 0 (Y short) at Y = 4000, but the track leaves octant 0 near Y = 707.
        circle_step_count({1000, 0}, {5000, 4000}, ArcDirection::ccw);
        FAIL();
    } catch (const InterpolationError& e) {
        EXPECT_NE(std::string(e.what()).find("5000,4000"), std::string::npos) << e.what();
    }
    EXPECT_THROW(circle_step_count({max_coordinate + 1, 0}, {1, 0}, ArcDirection::cw), InterpolationError);
}

TEST(CircularInterpolation, OctantNumbering) {
    // Octant n covers [45n, 45n+45) degrees CCW from +X; border points open the next octant for
    // CCW motion and close the previous one for CW motion.
    EXPECT_EQ(octant_of({10, 0}, ArcDirection::ccw), 0);
    EXPECT_EQ(octant_of({10, 0}, ArcDirection::cw), 7);
    EXPECT_EQ(octant_of({10, 10}, ArcDirection::ccw), 1);
    EXPECT_EQ(octant_of({10, 10}, ArcDirection::cw), 0);
    EXPECT_EQ(octant_of({0, 10}, ArcDirection::ccw), 2);
    EXPECT_EQ(octant_of({-10, 3}, ArcDirection::ccw), 3);
    EXPECT_EQ(octant_of({-10, -3}, ArcDirection::ccw), 4);
    EXPECT_EQ(octant_of({-3, -10}, ArcDirection::ccw), 5);
    EXPECT_EQ(octant_of({3, -10}, ArcDirection::ccw), 6);
    EXPECT_EQ(octant_of({10, -3}, ArcDirection::ccw), 7);
    EXPECT_EQ(end_octant_of({0, 10}, ArcDirection::ccw), 1);
    for (int o : {0, 3, 4, 7}) EXPECT_TRUE(y_is_short(o));
    for (int o : {1, 2, 5, 6}) EXPECT_FALSE(y_is_short(o));
}

} // namespace
