// PLCopen BufferMode (Part 1 §2.4.2, issue #49 item 2): the blending modes pass the junction of
// two moves without stopping, at the velocity Part 1 defines for each mode; invalid modes are
// refused. Expected junction speeds are the modes' definitions applied to the two Velocity inputs.
#include "tests/main_cpu/motion/motion_loop.h"

#include <cmath>
#include <initializer_list>

using namespace rcsim::motion;
using namespace rcsim::motion::test;

namespace {

/// One control cycle with the test's own blocks called after the controller's.
void step(MotionLoop& b, std::initializer_list<McExecuteFb*> fbs) {
    b.cycles(1);
    for (McExecuteFb* f : fbs) f->call();
}

struct Junction {
    double speed = -1;    // chip speed where the path passes the first move's end, pulses/s
    double min_speed = 1e9; // lowest chip speed between the first's cruise and that point
    std::int64_t end = 0; // where the second move ended
    bool second_active_before_first_done = false;
};

/// Two MC_MoveAbsolute on axis 0 from where it stands: +10000 at v1, then +10000 at v2 in `mode`,
/// the second commanded while the first runs. Rates 100000 pulses/s^2: the speed changes by at
/// most 100 pulses/s per 1 ms cycle.
Junction two_moves(MotionLoop& b, double v1, double v2, BufferMode mode) {
    const std::int64_t p0 = b.mc.chip().command_position(0), p1 = p0 + 10000, p2 = p1 + 10000;
    MC_MoveAbsolute m1, m2;
    m1.Axis = m2.Axis = &b.mc.axis(0);
    m1.Position = static_cast<std::int32_t>(p1), m1.Velocity = v1, m1.Acceleration = m1.Deceleration = 100000;
    m2.Position = static_cast<std::int32_t>(p2), m2.Velocity = v2, m2.Acceleration = m2.Deceleration = 100000;
    m2.Mode = mode;
    m1.Execute = true;
    step(b, {&m1, &m2});
    for (int i = 0; i < 250; ++i) step(b, {&m1, &m2}); // at v1 after 0.2 s
    m2.Execute = true;
    Junction j;
    double prev_speed = b.mc.chip().current_speed(0);
    std::int64_t prev_pos = b.mc.chip().command_position(0);
    for (int i = 0; i < 20000 && !m2.Done && !m2.Error; ++i) {
        step(b, {&m1, &m2});
        if (m2.Active && !m1.Done && !m1.CommandAborted && j.speed < 0) j.second_active_before_first_done = true;
        const double speed = b.mc.chip().current_speed(0);
        const std::int64_t pos = b.mc.chip().command_position(0);
        if (j.speed < 0) j.min_speed = std::min(j.min_speed, speed);
        if (j.speed < 0 && prev_pos < p1 && pos >= p1) // crossed between two samples: interpolate
            j.speed = prev_speed + (speed - prev_speed) * double(p1 - prev_pos) / double(pos - prev_pos);
        prev_speed = speed, prev_pos = pos;
    }
    EXPECT_TRUE(m1.Done || !m1.Execute);
    EXPECT_TRUE(m2.Done) << "mode " << int(mode);
    j.end = b.mc.chip().command_position(0) - p2;
    return j;
}

TEST(BufferMode, BlendingPassesTheJunctionAtTheModesVelocity) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        // Part 1: Low = the lower of both, Previous = the first's, Next = the second's, High = the
        // higher; each mode twice (faster first, then slower first) so that every mode differs.
        struct Case { BufferMode mode; double v1, v2, junction; };
        const Case cases[] = {
            {BufferMode::blending_low, 20000, 10000, 10000},      {BufferMode::blending_low, 10000, 20000, 10000},
            {BufferMode::blending_previous, 20000, 10000, 20000}, {BufferMode::blending_previous, 10000, 20000, 10000},
            {BufferMode::blending_next, 20000, 10000, 10000},     {BufferMode::blending_next, 10000, 20000, 20000},
            {BufferMode::blending_high, 20000, 10000, 20000},     {BufferMode::blending_high, 10000, 20000, 20000},
        };
        for (const Case& c : cases) {
            const Junction j = two_moves(b, c.v1, c.v2, c.mode);
            // 1 % (200 pulses/s): two cycles of the 100000 pulses/s^2 ramps around the sample.
            EXPECT_NEAR(j.speed, c.junction, 200) << "mode " << int(c.mode) << " " << c.v1 << " -> " << c.v2;
            // On the way the speed goes no lower than the first's cruise or the junction speed.
            EXPECT_GT(j.min_speed, std::min(c.v1, c.junction) - 200) << "never stops on the way";
            EXPECT_EQ(j.end, 0) << "the second move ends exactly on its Position";
            EXPECT_FALSE(j.second_active_before_first_done) << "Active only once it controls the axis";
        }
        // Buffered, the reference: the axis stops at the junction.
        const Junction j = two_moves(b, 20000, 10000, BufferMode::buffered);
        EXPECT_LT(j.min_speed, 200.0) << "buffered stops at the junction (STD = 100 pulses/s)";
        EXPECT_EQ(j.end, 0);
    });
}

// A BufferMode outside MC_BUFFER_MODE (0..5) is refused with its ErrorID: no motion.
TEST(BufferMode, AnInvalidModeIsRefusedWithItsErrorId) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveAbsolute m;
        m.Axis = &b.mc.axis(0);
        m.Position = 5000, m.Velocity = 10000, m.Acceleration = m.Deceleration = 100000;
        m.Mode = static_cast<BufferMode>(7);
        m.Execute = true;
        step(b, {&m});
        EXPECT_TRUE(m.Error);
        EXPECT_EQ(m.ErrorID, 0x7020);
        MC_CircleCenterMove c;
        c.AxisX = &b.mc.axis(0), c.AxisY = &b.mc.axis(1);
        c.CenterX = 1000, c.EndX = 2000, c.Velocity = 10000, c.Acceleration = c.Deceleration = 100000;
        c.Mode = static_cast<BufferMode>(6);
        c.Execute = true;
        MC_LineMove2 l;
        l.AxisX = &b.mc.axis(0), l.AxisY = &b.mc.axis(1);
        l.X = 1000, l.Velocity = 10000, l.Acceleration = l.Deceleration = 100000;
        l.Mode = static_cast<BufferMode>(255);
        l.Execute = true;
        MC_Halt h;
        h.Axis = &b.mc.axis(0);
        h.Mode = static_cast<BufferMode>(9);
        h.Execute = true;
        step(b, {&c, &l, &h});
        for (const McExecuteFb* f : {static_cast<McExecuteFb*>(&c), static_cast<McExecuteFb*>(&l),
                                     static_cast<McExecuteFb*>(&h)}) {
            EXPECT_TRUE(f->Error);
            EXPECT_EQ(f->ErrorID, 0x7020);
        }
        b.cycles(20);
        EXPECT_EQ(b.mc.chip().command_position(0), 0) << "nothing moved";
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
    });
}

/// Two tangent half circles of radius 2000 (an S: CCW about (2000, 0), then CW about (6000, 0))
/// at 10000 pulses/s along the path; the second commanded while the first runs.
struct Arcs {
    double junction_speed = -1, min_speed = 1e9;
    std::int64_t x = 0, y = 0;
};
Arcs two_half_circles(MotionLoop& b, BufferMode mode) {
    MC_CircleCenterMove c1, c2;
    for (MC_CircleCenterMove* c : {&c1, &c2}) {
        c->AxisX = &b.mc.axis(0), c->AxisY = &b.mc.axis(1);
        c->CenterX = 2000, c->CenterY = 0, c->EndX = 4000, c->EndY = 0;
        c->Velocity = 10000, c->Acceleration = c->Deceleration = 100000;
    }
    c1.Direction = dir_ccw;
    c2.Direction = dir_cw;
    c2.Mode = mode;
    c1.Execute = true;
    step(b, {&c1, &c2});
    for (int i = 0; i < 200; ++i) step(b, {&c1, &c2}); // at path speed after 0.1 s
    c2.Execute = true;
    Arcs a;
    for (int i = 0; i < 20000 && !c2.Done && !c2.Error; ++i) {
        step(b, {&c1, &c2});
        const double v = b.mc.chip().current_speed(0);
        if (a.junction_speed < 0) a.min_speed = std::min(a.min_speed, v);
        if (a.junction_speed < 0 && c1.Done) a.junction_speed = v; // the cycle after the junction
    }
    EXPECT_TRUE(c2.Done);
    a.x = b.mc.chip().command_position(0), a.y = b.mc.chip().command_position(1);
    return a;
}

TEST(BufferMode, TwoTangentHalfCirclesBlendWithoutStopping) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        const Arcs a = two_half_circles(b, BufferMode::blending_low);
        // Both at 10000: every blending mode passes the tangent junction at 10000 pulses/s.
        EXPECT_NEAR(a.junction_speed, 10000, 100);
        EXPECT_GT(a.min_speed, 9900) << "the path speed stays at Velocity through the junction";
        EXPECT_EQ(a.x, 8000) << "the S ends exactly 4 radii on";
        EXPECT_EQ(a.y, 0);
    });
}

TEST(BufferMode, TwoTangentHalfCirclesBufferedStopAtTheJunction) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        const Arcs a = two_half_circles(b, BufferMode::buffered);
        EXPECT_LT(a.min_speed, 200) << "buffered: the path stops between the arcs";
        EXPECT_EQ(a.x, 8000);
        EXPECT_EQ(a.y, 0);
    });
}

} // namespace

namespace {

// Aborting takes over from the present state (Part 1 §2.4.2, issue #49 item 3): a new target or
// velocity goes on from the present velocity, no stop in between.
TEST(Aborting, ARetargetContinuesFromThePresentVelocity) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveAbsolute m1, m2;
        m1.Axis = m2.Axis = &b.mc.axis(0);
        m1.Position = 20000, m1.Velocity = 10000, m1.Acceleration = m1.Deceleration = 100000;
        m2.Position = 30000, m2.Velocity = 15000, m2.Acceleration = m2.Deceleration = 100000;
        m1.Execute = true;
        for (int i = 0; i < 300; ++i) step(b, {&m1, &m2}); // cruising at 10000 (ramp 0.1 s)
        m2.Execute = true;
        double min_speed = 1e9;
        bool aborted = false;
        for (int i = 0; i < 5000 && !m2.Done; ++i) {
            step(b, {&m1, &m2});
            aborted |= m1.CommandAborted;
            // Until the final ramp (15000^2 / 200000 = 1125 pulses before the end).
            if (b.mc.chip().command_position(0) < 30000 - 1200) min_speed = std::min(min_speed, b.mc.chip().current_speed(0));
        }
        EXPECT_TRUE(aborted);
        EXPECT_TRUE(m2.Done);
        EXPECT_GE(min_speed, 10000 - 100) << "never below the first move's velocity: no stop";
        EXPECT_EQ(b.mc.chip().command_position(0), 30000);
    });
}

TEST(Aborting, AVelocityChangeContinuesFromThePresentVelocity) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveVelocity v1, v2;
        v1.Axis = v2.Axis = &b.mc.axis(0);
        v1.Velocity = 10000, v2.Velocity = 15000;
        v1.Acceleration = v1.Deceleration = v2.Acceleration = v2.Deceleration = 100000;
        v1.Execute = true;
        for (int i = 0; i < 300; ++i) step(b, {&v1, &v2});
        ASSERT_TRUE(v1.InVelocity);
        v2.Execute = true;
        double min_speed = 1e9;
        for (int i = 0; i < 300; ++i) {
            step(b, {&v1, &v2});
            min_speed = std::min(min_speed, b.mc.chip().current_speed(0));
        }
        EXPECT_TRUE(v2.InVelocity);
        EXPECT_EQ(b.mc.chip().current_speed(0), 15000);
        EXPECT_GE(min_speed, 10000 - 100) << "10000 -> 15000 without passing through 0";
    });
}

// Reversing (or a target too close to stop at) cannot take over: the old way, ramp down and
// start again, and the end is still exact.
TEST(Aborting, AReversingRetargetStillStopsFirst) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveAbsolute m1, m2;
        m1.Axis = m2.Axis = &b.mc.axis(0);
        m1.Position = 20000, m1.Velocity = 10000, m1.Acceleration = m1.Deceleration = 100000;
        m2.Position = 1000, m2.Velocity = 10000, m2.Acceleration = m2.Deceleration = 100000;
        m1.Execute = true;
        for (int i = 0; i < 300; ++i) step(b, {&m1, &m2});
        m2.Execute = true;
        double min_speed = 1e9;
        for (int i = 0; i < 5000 && !m2.Done; ++i) {
            step(b, {&m1, &m2});
            if (b.mc.chip().command_position(0) > 2000) min_speed = std::min(min_speed, b.mc.chip().current_speed(0));
        }
        EXPECT_TRUE(m2.Done);
        EXPECT_LT(min_speed, 200);
        EXPECT_EQ(b.mc.chip().command_position(0), 1000);
    });
}

} // namespace
