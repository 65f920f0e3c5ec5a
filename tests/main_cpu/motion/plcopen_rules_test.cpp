// PLCopen Part 1 rules (docs/motion.md): reset with the power off (Note 3), visibility and reset of
// Error and CommandAborted (§2.4.1), MC_Stop from Standstill and Homing, MC_Halt aborted, release
// of Stopping and of a buffered command on Done AND NOT Execute (Note 6, Table 4), and the AXL
// ErrorIDs 4114 (accel/decel time 0, AXT_RT_MOTION_INVALID_ACCELTIME) and 4253 (velocity above
// the maximum, AXT_RT_MOTION_VELOCITY_OUTOFBOUND).
#include "tests/main_cpu/motion/motion_loop.h"

using namespace rcsim::motion;
using namespace rcsim::motion::test;

namespace {

TEST(PLCopenRules, ResetWithThePowerOffLeadsToDisabled) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        b.mc.drive(0).inject_fault(0x7500);
        b.mc.drive(0).clear_fault_cause();
        b.cycles(3);
        ASSERT_EQ(b.mc.axis(0).state(), AxisState::error_stop);
        b.mc.power(0).Enable = false;
        b.cycles(2);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::error_stop); // power off does not leave ErrorStop
        MC_Reset& r = b.mc.blocks(0).reset;
        r.Execute = true;
        b.until([&] { return r.Done || r.Error; }, 50);
        EXPECT_TRUE(r.Done);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::disabled); // Note 3
        EXPECT_EQ(b.mc.axis(0).error_id(), 0);
    });
}

TEST(PLCopenRules, ErrorAndCommandAbortedShowForOneCallAfterAnEarlyFallingEdgeThenReset) {
    MotionConfig cfg;
    cfg.switches[0].pelm = 3000;
    run_motion([](MotionLoop& b) {
        b.power_on();
        // Error, with Execute already low when it appears: a move into PELM (at 3000).
        MC_MoveRelative& r = b.mc.blocks(0).move_rel;
        r.Distance = 10000, r.Velocity = 20000, r.Acceleration = 100000, r.Deceleration = 100000;
        r.Execute = true;
        b.cycles(1);
        EXPECT_TRUE(r.Busy);
        r.Execute = false;
        b.until([&] { return r.Error; }, 2000);
        EXPECT_TRUE(r.Error); // visible although Execute is low
        EXPECT_EQ(r.ErrorID, err::limit_positive);
        b.cycles(1);
        EXPECT_FALSE(r.Error); // and reset at the next call
        EXPECT_EQ(r.ErrorID, 0);
        ASSERT_EQ(b.mc.command("RS", "1").bch, 0x00);
        b.until([&] { return b.mc.axis(0).state() == AxisState::standstill; }, 100);
        // CommandAborted with Execute high stays; reset on the falling edge.
        MC_MoveAbsolute& m = b.mc.blocks(0).move_abs;
        m.Position = -50000, m.Velocity = 20000, m.Acceleration = 100000, m.Deceleration = 100000;
        m.Execute = true;
        b.cycles(5);
        MC_MoveAbsolute other;
        other.Axis = &b.mc.axis(0);
        other.Position = 0, other.Velocity = 20000, other.Acceleration = 100000, other.Deceleration = 100000;
        other.Execute = true;
        other.call();
        b.cycles(3);
        EXPECT_TRUE(m.CommandAborted);
        EXPECT_FALSE(m.Busy || m.Done || m.Error);
        m.Execute = false;
        b.cycles(1);
        EXPECT_FALSE(m.CommandAborted);
    }, cfg);
}

TEST(PLCopenRules, StopFromStandstillAndFromHoming) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_Stop& s = b.mc.blocks(1).stop;
        s.Execute = true;
        b.cycles(2);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::stopping); // from Standstill
        EXPECT_TRUE(s.Done);
        b.cycles(5);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::stopping); // held while Execute
        s.Execute = false;
        b.cycles(1);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::standstill);

        MC_Home& h = b.mc.blocks(1).home; // no home switch: still searching when stopped
        h.Execute = true;
        b.cycles(50);
        ASSERT_EQ(b.mc.axis(1).state(), AxisState::homing);
        s.Execute = true;
        b.cycles(2);
        EXPECT_TRUE(h.CommandAborted);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::stopping);
        b.until([&] { return s.Done; });
        EXPECT_FALSE(b.mc.chip().busy(1));
        s.Execute = false;
        b.cycles(1);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::standstill);
    });
}

TEST(PLCopenRules, HaltIsAbortedByAnotherMove) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveAbsolute& m = b.mc.blocks(2).move_abs;
        m.Position = 100000, m.Velocity = 20000, m.Acceleration = 100000, m.Deceleration = 100000;
        m.Execute = true;
        b.cycles(300);
        MC_Halt& h = b.mc.blocks(2).halt;
        h.Deceleration = 2000; // a long ramp, so that the next move comes during it
        h.Execute = true;
        b.cycles(5);
        ASSERT_TRUE(h.Busy);
        MC_MoveRelative& r = b.mc.blocks(2).move_rel;
        r.Distance = 1000, r.Velocity = 20000, r.Acceleration = 100000, r.Deceleration = 100000;
        r.Execute = true;
        b.cycles(2);
        EXPECT_TRUE(h.CommandAborted);
        EXPECT_FALSE(h.Done);
        b.until([&] { return r.Done; });
        EXPECT_EQ(b.mc.axis(2).state(), AxisState::standstill);
    });
}

TEST(PLCopenRules, StoppingEndsOnDoneAndNotExecuteAndReleasesABufferedMove) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveAbsolute& m = b.mc.blocks(3).move_abs;
        m.Position = 100000, m.Velocity = 20000, m.Acceleration = 100000, m.Deceleration = 100000;
        m.Execute = true;
        b.cycles(300);
        MC_Stop& s = b.mc.blocks(3).stop;
        s.Deceleration = 20000; // 1 s of ramp
        s.Execute = true;
        b.cycles(2);
        ASSERT_EQ(b.mc.axis(3).state(), AxisState::stopping);
        // Execute falls before Done: still Stopping until Done (then Standstill, Note 6).
        s.Execute = false;
        b.cycles(1);
        EXPECT_FALSE(s.Done);
        EXPECT_EQ(b.mc.axis(3).state(), AxisState::stopping);
        // An aborting command is refused in Stopping; a buffered one waits for Done AND NOT Execute.
        MC_MoveRelative& r = b.mc.blocks(3).move_rel;
        r.Distance = -500, r.Velocity = 20000, r.Acceleration = 100000, r.Deceleration = 100000;
        r.Execute = true;
        r.call();
        EXPECT_EQ(r.ErrorID, err::axis_stopping);
        r.Execute = false;
        r.call();
        r.Mode = BufferMode::buffered;
        r.Execute = true;
        b.cycles(1);
        EXPECT_TRUE(r.Busy);
        EXPECT_FALSE(r.Active);
        const int n = b.until([&] { return s.Done; });
        EXPECT_GT(n, 900); // MC_Stop's own ramp: (20000 - 100) / 20000 = 0.995 s
        const std::int64_t stopped = b.mc.chip().command_position(3);
        b.until([&] { return r.Done; });
        EXPECT_EQ(b.mc.chip().command_position(3), stopped - 500);
        EXPECT_EQ(b.mc.axis(3).state(), AxisState::standstill);
        // With Execute held the buffered move is refused.
        s.Execute = true;
        b.cycles(2);
        MC_MoveRelative q;
        q.Axis = &b.mc.axis(3);
        q.Distance = 10, q.Velocity = 100, q.Acceleration = 1000, q.Deceleration = 1000;
        q.Mode = BufferMode::buffered;
        q.Execute = true;
        q.call();
        EXPECT_EQ(q.ErrorID, err::axis_stopping);
    });
}

TEST(PLCopenRules, ErrorIds4114And4253FromBlocksAndTokens) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveAbsolute& m = b.mc.blocks(0).move_abs;
        auto edge = [&](double v, double a, double d) {
            m.Execute = false;
            m.call();
            m.Position = 100, m.Velocity = v, m.Acceleration = a, m.Deceleration = d;
            m.Execute = true;
            m.call();
            return m.ErrorID;
        };
        EXPECT_EQ(edge(1000, 0, 1000), 4114);
        EXPECT_EQ(edge(1000, 1000, 0), 4114);
        EXPECT_EQ(edge(1000, -5, 1000), 4114);
        EXPECT_EQ(edge(10000001, 1000, 1000), 4253); // above the 10 Mpps ceiling
        EXPECT_EQ(edge(10000000, 1000, 1000), 0);    // the ceiling itself is allowed
        EXPECT_EQ(edge(0, 1000, 1000), 4113);
        m.Execute = false;
        b.cycles(1);
        EXPECT_EQ(b.mc.command("MA", "1,100,1000,0,1000").data, "4114");
        EXPECT_EQ(b.mc.command("MA", "1,100,20000000,1000,1000").data, "4253");
        EXPECT_EQ(b.mc.command("ML", "100,100,1000,1000,0").data, "4114");
        MC_Home& h = b.mc.blocks(2).home;
        h.Acceleration = 0;
        h.Execute = true;
        h.call();
        EXPECT_EQ(h.ErrorID, 4114);
        h.Execute = false;
        h.call();
        h.Acceleration = 40000, h.ApproachVelocity = 2e7;
        h.Execute = true;
        h.call();
        EXPECT_EQ(h.ErrorID, 4253);
    });
}

} // namespace
