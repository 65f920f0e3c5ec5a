// Issue 49 items 5 and 7: PLCopen Part 1 v2.0 parameters (MC_WriteParameter / MC_ReadParameter
// numbers 2-7, 9, 13, 15), software limits, following-error monitoring, the application's velocity
// and rate limits, and the CiA402 quick stop (0x605A) and disable operation (0x605C) option codes.
// Expected values: Part 1's table and state rules, CiA402's option codes, stop distance v^2 / 2a.
#include "tests/main_cpu/motion/motion_loop.h"

#include <cmath>

using namespace rcsim::motion;
using namespace rcsim::motion::test;

namespace {

std::uint16_t write(McAxis& a, int number, double value) {
    MC_WriteParameter w;
    w.Axis = &a, w.ParameterNumber = number, w.Value = value, w.Execute = true;
    w.call();
    EXPECT_EQ(w.Done, w.ErrorID == 0);
    return w.ErrorID;
}

double read(McAxis& a, int number) {
    MC_ReadParameter r;
    r.Axis = &a, r.ParameterNumber = number, r.Enable = true;
    r.call();
    EXPECT_TRUE(r.Valid) << "parameter " << number << " ErrorID " << r.ErrorID;
    return r.Value;
}

// Part 1's numbers read back what was written (2 answered 0x7006 before issue 49); read-only
// numbers and values out of range are refused.
TEST(AxisLimits, WriteParameterAndReadParameterByPartOneNumbers) {
    run_motion([](MotionLoop& b) {
        McAxis& a = b.mc.axis(0);
        EXPECT_EQ(write(a, 2, 5000), 0);
        EXPECT_EQ(write(a, 3, -4000), 0);
        EXPECT_EQ(write(a, 4, 1), 0);
        EXPECT_EQ(write(a, 6, 1), 0);
        EXPECT_EQ(write(a, 7, 250), 0);
        EXPECT_EQ(write(a, 9, 30000), 0);
        EXPECT_EQ(write(a, 13, 123456), 0);
        EXPECT_EQ(write(a, 15, 654321), 0);
        EXPECT_EQ(read(a, 2), 5000);
        EXPECT_EQ(read(a, 3), -4000);
        EXPECT_EQ(read(a, 4), 1);
        EXPECT_EQ(read(a, 5), 0);
        EXPECT_EQ(read(a, 6), 1);
        EXPECT_EQ(read(a, 7), 250);
        EXPECT_EQ(read(a, 9), 30000);
        EXPECT_EQ(read(a, 13), 123456);
        EXPECT_EQ(read(a, 15), 654321);
        EXPECT_EQ(write(a, 1, 0), err::parameter_read_only);   // CommandedPosition
        EXPECT_EQ(write(a, 8, 1), err::parameter_read_only);   // MaxVelocitySystem
        EXPECT_EQ(write(a, 4, 2), err::parameter_value);       // a BOOL
        EXPECT_EQ(write(a, 7, -1), err::parameter_value);      // a lag is positive
        EXPECT_EQ(write(a, 9, 2e7), err::parameter_value);     // above MaxVelocitySystem
        EXPECT_EQ(write(a, 16, 1), err::parameter_unsupported);
        EXPECT_EQ(write(a, 0x605A, 9), err::parameter_value);  // CiA402: 0..8
        EXPECT_EQ(write(a, 0x605A, 6), 0);
        EXPECT_EQ(read(a, 0x605A), 6);
    });
}

// A move whose end is past an enabled software limit is refused at the block: Error with the
// limit's ErrorID, the axis stays in Standstill and no pulse is sent.
TEST(AxisLimits, MoveBeyondAnEnabledSoftwareLimitIsRefused) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        McAxis& a = b.mc.axis(0);
        write(a, 2, 5000), write(a, 4, 1), write(a, 3, -5000), write(a, 5, 1);
        MC_MoveAbsolute& m = b.mc.blocks(0).move_abs;
        m.Position = 5001, m.Velocity = 20000, m.Acceleration = m.Deceleration = 200000;
        m.Execute = true;
        b.cycles(2);
        EXPECT_TRUE(m.Error);
        EXPECT_EQ(m.ErrorID, err::sw_limit_positive);
        EXPECT_EQ(a.state(), AxisState::standstill);
        MC_MoveRelative& r = b.mc.blocks(0).move_rel;
        r.Distance = -5001, r.Velocity = 20000, r.Acceleration = r.Deceleration = 200000;
        r.Execute = true;
        b.cycles(2);
        EXPECT_EQ(r.ErrorID, err::sw_limit_negative);
        EXPECT_EQ(b.mc.chip().pulse_count(0), 0);
        m.Execute = false, b.cycles(1);
        m.Position = 5000, m.Execute = true; // on the limit: allowed
        b.until([&] { return m.Done || m.Error; }, 2000);
        EXPECT_TRUE(m.Done);
        EXPECT_EQ(b.mc.chip().command_position(0), 5000);
    });
}

// MC_MoveVelocity toward an enabled limit: ErrorStop with its ErrorID once the command passes it,
// at most one 1 ms control cycle of travel (v * 1 ms) beyond.
TEST(AxisLimits, ContinuousMoveStopsAtTheSoftwareLimit) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        McAxis& a = b.mc.axis(0);
        write(a, 2, 5000), write(a, 4, 1);
        MC_MoveVelocity& v = b.mc.blocks(0).move_vel;
        v.Velocity = 20000, v.Acceleration = v.Deceleration = 200000;
        v.Execute = true;
        b.until([&] { return a.state() == AxisState::error_stop; }, 2000);
        EXPECT_EQ(a.error_id(), err::sw_limit_positive);
        EXPECT_TRUE(v.Error);
        const std::int64_t at = b.mc.chip().command_position(0);
        EXPECT_GT(at, 5000);
        EXPECT_LE(at, 5000 + 20000 * 0.001 + 1);
    });
}

// Following error: a drive lagging T = 50 ms behind at v = 20000 pulses/s trails by v*T = 1000
// pulses; with MaxPositionLag 500 and monitoring on, the axis goes to ErrorStop with 0x7112; with
// monitoring off the same move ends Done (one SystemC run per test).
void lagging_move(bool monitor) {
    MotionConfig cfg;
    cfg.drive.following_lag_s = 0.05;
    run_motion([monitor](MotionLoop& b) {
        b.power_on();
        McAxis& a = b.mc.axis(0);
        write(a, 7, 500), write(a, 6, monitor);
        MC_MoveRelative& m = b.mc.blocks(0).move_rel;
        m.Distance = 20000, m.Velocity = 20000, m.Acceleration = m.Deceleration = 200000;
        m.Execute = true;
        b.until([&] { return m.Done || m.Error; }, 3000);
        if (monitor) {
            EXPECT_TRUE(m.Error);
            EXPECT_EQ(m.ErrorID, err::following_error);
            EXPECT_EQ(a.state(), AxisState::error_stop);
            EXPECT_EQ(a.error_id(), err::following_error);
        } else {
            EXPECT_TRUE(m.Done);
        }
    }, cfg);
}

TEST(AxisLimits, FollowingErrorAboveMaxPositionLagIsAnAxisError) { lagging_move(true); }
TEST(AxisLimits, FollowingErrorUnmonitoredIsNoError) { lagging_move(false); }

// Velocity and rates above MaxVelocityAppl / MaxAccelerationAppl / MaxDecelerationAppl are
// refused at the block, each with its ErrorID; at the limit they are taken.
TEST(AxisLimits, VelocityAndRatesAboveTheApplicationLimitsAreRefused) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        McAxis& a = b.mc.axis(0);
        write(a, 9, 10000), write(a, 13, 100000), write(a, 15, 50000);
        MC_MoveRelative& m = b.mc.blocks(0).move_rel;
        const auto run = [&](double v, double acc, double dec) {
            m.Execute = false, b.cycles(1);
            m.Distance = 1000, m.Velocity = v, m.Acceleration = acc, m.Deceleration = dec;
            m.Execute = true, b.cycles(1);
            const std::uint16_t e = m.ErrorID;
            b.until([&] { return !m.Busy; }, 2000);
            return e;
        };
        EXPECT_EQ(run(10001, 100000, 50000), err::velocity_above_limit);
        EXPECT_EQ(run(10000, 100001, 50000), err::acceleration_above_limit);
        EXPECT_EQ(run(10000, 100000, 50001), err::deceleration_above_limit);
        EXPECT_EQ(run(10000, 100000, 50000), 0);
        EXPECT_EQ(a.state(), AxisState::standstill);
    });
}

} // namespace
