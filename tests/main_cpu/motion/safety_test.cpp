// Emergency stop (docs/motion.md "Safety"): the ES token and MC_Stop with Emergency latch ErrorStop
// on every axis, moving or not, whatever state it was in, and motion stays refused (BCH 05,
// ErrorID 0x7002) until RS resets the axis.
#include "tests/main_cpu/motion/motion_loop.h"

using namespace rcsim::motion;
using namespace rcsim::motion::test;

namespace {

const std::string error_stop_reply = std::to_string(err::axis_error_stop); // 0x7002 = 28674

/// ES, then: every axis in ErrorStop, the chip idle, motion refused on every axis, still so a
/// while later; RS on all axes brings each back to `after_reset`.
void expect_latched_until_reset(MotionLoop& b, AxisState after_reset, const char* what) {
    SCOPED_TRACE(what);
    EXPECT_EQ(b.mc.command("ES", "").bch, 0x00);
    for (unsigned a = 0; a < 4; ++a) {
        EXPECT_EQ(b.mc.axis(a).state(), AxisState::error_stop) << "axis " << a; // at once, not next cycle
        EXPECT_FALSE(b.mc.chip().busy(a)) << "axis " << a;
    }
    std::array<std::int64_t, 4> at{};
    for (unsigned a = 0; a < 4; ++a) at[a] = b.mc.chip().pulse_count(a); // CNT1 may be preset to CNT2 at re-enable
    for (unsigned a = 0; a < 4; ++a) {
        const auto r = b.mc.command("MA", std::to_string(a) + ",500,1000,10000,10000");
        EXPECT_EQ(r.bch, 0x05) << "axis " << a;
        EXPECT_EQ(r.data, error_stop_reply) << "axis " << a;
    }
    EXPECT_EQ(b.mc.command("ML", "100,100,1000,10000,10000").bch, 0x05);
    b.cycles(50);
    for (unsigned a = 0; a < 4; ++a) {
        EXPECT_EQ(b.mc.axis(a).state(), AxisState::error_stop) << "axis " << a; // latched
        EXPECT_EQ(b.mc.chip().pulse_count(a), at[a]) << "axis " << a;   // no pulse: nothing moved
    }
    EXPECT_EQ(b.mc.state(), "ERRORSTOP");
    ASSERT_EQ(b.mc.command("RS", "15").bch, 0x00);
    b.until([&] {
        for (unsigned a = 0; a < 4; ++a)
            if (b.mc.axis(a).state() != after_reset) return false;
        return true;
    }, 100);
    for (unsigned a = 0; a < 4; ++a) EXPECT_EQ(b.mc.axis(a).state(), after_reset) << "axis " << a;
}

TEST(Safety, EsLatchesErrorStopOnEveryAxisFromEveryState) {
    run_motion([](MotionLoop& b) {
        // Disabled: ErrorStop too (Note 1); the reset leads back to Disabled (Note 3).
        b.cycles(2);
        expect_latched_until_reset(b, AxisState::disabled, "disabled");
        b.power_on();

        expect_latched_until_reset(b, AxisState::standstill, "standstill");

        ASSERT_EQ(b.mc.command("HM", "1").bch, 0x00); // no home sensor: the search runs on
        b.cycles(20);
        ASSERT_EQ(b.mc.axis(0).state(), AxisState::homing);
        expect_latched_until_reset(b, AxisState::standstill, "homing");

        ASSERT_EQ(b.mc.command("MA", "2,50000,20000,100000,100000").bch, 0x00);
        b.cycles(20);
        ASSERT_EQ(b.mc.axis(2).state(), AxisState::discrete_motion);
        expect_latched_until_reset(b, AxisState::standstill, "discrete motion");

        ASSERT_EQ(b.mc.command("MV", "3,-20000,100000,100000").bch, 0x00);
        b.cycles(20);
        ASSERT_EQ(b.mc.axis(3).state(), AxisState::continuous_motion);
        expect_latched_until_reset(b, AxisState::standstill, "continuous motion");

        ASSERT_EQ(b.mc.command("ML", "40000,30000,20000,100000,100000").bch, 0x00);
        b.cycles(20);
        ASSERT_EQ(b.mc.axis(1).state(), AxisState::synchronized_motion);
        expect_latched_until_reset(b, AxisState::standstill, "synchronized motion");

        MC_MoveRelative& m = b.mc.blocks(3).move_rel;
        m.Distance = 50000, m.Velocity = 20000, m.Acceleration = 100000, m.Deceleration = 100000;
        m.Execute = true;
        b.cycles(20);
        MC_Stop& s = b.mc.blocks(3).stop;
        s.Deceleration = 1000; // a long ramp: still Stopping when ES comes
        s.Execute = true;
        b.cycles(3);
        ASSERT_EQ(b.mc.axis(3).state(), AxisState::stopping);
        ASSERT_TRUE(b.mc.chip().busy(3));
        expect_latched_until_reset(b, AxisState::standstill, "stopping");
        s.Execute = m.Execute = false;
        b.cycles(2);

        // Already in ErrorStop for another cause: it stays there and keeps its ErrorID.
        b.mc.drive(0).inject_fault(0x7500);
        b.mc.drive(0).clear_fault_cause();
        b.cycles(3);
        ASSERT_EQ(b.mc.axis(0).state(), AxisState::error_stop);
        EXPECT_EQ(b.mc.command("ES", "").bch, 0x00);
        EXPECT_EQ(b.mc.axis(0).error_id(), err::drive_fault);
        EXPECT_EQ(b.mc.axis(1).error_id(), err::emergency_stop);
        expect_latched_until_reset(b, AxisState::standstill, "error stop");

        // After the reset motion is accepted again.
        EXPECT_EQ(b.mc.command("MA", "2,700,10000,100000,100000").bch, 0x00);
        b.until([&] { return b.mc.axis(2).state() == AxisState::standstill; });
        EXPECT_EQ(b.mc.chip().command_position(2), 700);
    });
}

TEST(Safety, StopWithEmergencyStopsEveryAxisAtOnceAndLatchesErrorStop) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        ASSERT_EQ(b.mc.command("MA", "0,80000,20000,100000,100000").bch, 0x00);
        b.cycles(100);
        ASSERT_TRUE(b.mc.chip().busy(0));
        const std::int64_t at = b.mc.chip().command_position(0);
        // The emergency form on an idle axis (2) stops the moving one (0) at once.
        MC_Stop& s = b.mc.blocks(2).stop;
        s.Emergency = true;
        s.Execute = true;
        s.call();
        EXPECT_TRUE(s.Done);
        EXPECT_FALSE(s.Error);
        EXPECT_FALSE(b.mc.chip().busy(0));
        EXPECT_EQ(b.mc.chip().command_position(0), at); // immediate: not one pulse of ramp
        for (unsigned a = 0; a < 4; ++a) {
            EXPECT_EQ(b.mc.axis(a).state(), AxisState::error_stop) << a;
            EXPECT_EQ(b.mc.axis(a).error_id(), err::emergency_stop) << a;
        }
        b.cycles(1); // the token's block shows the Error for the one call that set it
        EXPECT_TRUE(b.mc.blocks(0).move_abs.Error);
        EXPECT_EQ(b.mc.blocks(0).move_abs.ErrorID, err::emergency_stop);
        MC_MoveRelative r;
        r.Axis = &b.mc.axis(2);
        r.Distance = 10, r.Velocity = 100, r.Acceleration = 1000, r.Deceleration = 1000;
        r.Execute = true;
        r.call();
        EXPECT_EQ(r.ErrorID, err::axis_error_stop);
        // Never refused: again from ErrorStop (and from Disabled) it reports Done.
        s.Execute = false;
        s.call();
        s.Execute = true;
        s.call();
        EXPECT_TRUE(s.Done);
        EXPECT_FALSE(s.Error);
    });
}

} // namespace
