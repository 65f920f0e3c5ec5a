// Issue 29 "motion a machine builder can trust": aborted and stopped group moves, servo-on,
// MC_Reset, homing counters, and the blocks' shared state rules. Expected values come from
// PLCopen Part 1, the CiA402 profile and geometry (stop distance v^2 / 2a), not from the code.
#include "tests/main_cpu/motion/motion_loop.h"

#include <cmath>
#include <vector>

using namespace rcsim::motion;
using namespace rcsim::motion::test;

namespace {

// A line in cruise aborted through its Y axis ramps down at the line's own Deceleration: the path
// covers at most v^2 / (2 Deceleration) after the abort, and both axes reach StandStill.
TEST(Trust, AbortedLineStopsWithinItsDecelerationDistanceAndBothAxesStandStill) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_LineMove2& l = b.mc.line_move();
        const double v = 20000, dec = 200000;
        l.X = 20000, l.Y = 10000, l.Velocity = v, l.Acceleration = 200000, l.Deceleration = dec;
        l.Execute = true;
        b.cycles(200); // accelerated after v / a = 100 ms: in cruise
        MC_MoveAbsolute& m = b.mc.blocks(1).move_abs;
        m.Position = 0, m.Velocity = 10000, m.Acceleration = m.Deceleration = 100000;
        m.Execute = true;
        const double x0 = static_cast<double>(b.mc.chip().command_position(0));
        const double y0 = static_cast<double>(b.mc.chip().command_position(1));
        const sc_core::sc_time t0 = sc_core::sc_time_stamp();
        b.cycles(1);
        b.until([&] { return !b.mc.chip().busy(0); }, 1000);
        const double travelled = std::hypot(b.mc.chip().command_position(0) - x0, b.mc.chip().command_position(1) - y0);
        const double allowed = v * v / (2 * dec); // 1000 pulses of path
        EXPECT_GT(travelled, 0.5 * allowed);      // it ramps, it does not stop dead
        EXPECT_LE(travelled, allowed + 1.5);      // + the lattice's rounding of both axes
        EXPECT_LE((sc_core::sc_time_stamp() - t0).to_seconds(), v / dec + 0.003);
        EXPECT_TRUE(l.CommandAborted);
        b.cycles(2);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill); // the partner, no job of its own
        b.until([&] { return m.Done; }, 3000);
        EXPECT_TRUE(m.Done);
        EXPECT_EQ(b.mc.chip().command_position(1), 0);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::standstill);
    });
}

// MC_Stop through one axis of a circle: the partner leaves SynchronizedMotion when the chip's
// ramp ends, and a program waiting for StandStill on it goes on.
TEST(Trust, StoppedCircleLeavesThePartnerInStandStill) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_CircleCenterMove& c = b.mc.circle_move();
        c.CenterX = 5000, c.CenterY = 0, c.EndX = 10000, c.EndY = 0, c.Direction = dir_ccw;
        c.Velocity = 20000, c.Acceleration = c.Deceleration = 200000;
        c.Execute = true;
        b.cycles(150);
        MC_Stop& s = b.mc.blocks(1).stop;
        s.Execute = true;
        b.until([&] { return s.Done; }, 1000);
        ASSERT_TRUE(s.Done);
        EXPECT_TRUE(c.CommandAborted);
        b.cycles(1);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::stopping); // held while Execute
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
        s.Execute = false;
        b.cycles(1);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::standstill);
    });
}

// Servo off while moving: the drive's deviation counter is cleared with the power stage off, so
// switching it on again moves nothing (a pulse-train servo; a safety matter), and the command
// counter starts at the motor's position, so the next move ends where it is commanded.
TEST(Trust, ServoOnAfterServoOffWhileMovingDoesNotMoveTheMotor) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveRelative& m = b.mc.blocks(0).move_rel;
        m.Distance = 50000, m.Velocity = 20000, m.Acceleration = m.Deceleration = 200000;
        m.Execute = true;
        b.cycles(100);
        b.mc.command("SV", "0");
        b.cycles(20);
        const std::int64_t rest = b.mc.drive(0).actual_position();
        EXPECT_NE(b.mc.chip().pulse_count(0), rest); // the motor lagged the pulses at servo off
        b.mc.command("SV", "1");
        for (int i = 0; i < 30; ++i) {
            b.cycles(1);
            EXPECT_EQ(b.mc.drive(0).actual_position(), rest) << "cycle " << i;
        }
        ASSERT_EQ(b.mc.axis(0).state(), AxisState::standstill);
        EXPECT_EQ(b.mc.chip().command_position(0), b.mc.chip().encoder_position(0));
        MC_MoveAbsolute& a = b.mc.blocks(0).move_abs;
        a.Position = 1000, a.Velocity = 10000, a.Acceleration = a.Deceleration = 100000;
        a.Execute = true;
        b.until([&] { return a.Done; }, 3000);
        b.cycles(30); // the motor catches up with the set-point
        EXPECT_EQ(b.mc.chip().encoder_position(0), 1000);
    });
}

// A drive fault while moving (fault reaction, CiA402 transition 13), cleared and reset: enabling
// again moves nothing either.
TEST(Trust, ServoOnAfterADriveFaultAndResetDoesNotMoveTheMotor) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveRelative& m = b.mc.blocks(1).move_rel;
        m.Distance = -50000, m.Velocity = 20000, m.Acceleration = m.Deceleration = 200000;
        m.Execute = true;
        b.cycles(100);
        b.mc.drive(1).inject_fault(0x2310);
        b.cycles(20);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::error_stop);
        const std::int64_t rest = b.mc.drive(1).actual_position();
        b.mc.drive(1).clear_fault_cause();
        MC_Reset& r = b.mc.blocks(1).reset;
        r.Execute = true;
        for (int i = 0; i < 40; ++i) {
            b.cycles(1);
            EXPECT_EQ(b.mc.drive(1).actual_position(), rest) << "cycle " << i;
        }
        EXPECT_TRUE(r.Done);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::standstill);
        EXPECT_EQ(b.mc.drive(1).state(), Cia402State::operation_enabled);
    });
}

// MC_Reset on an axis without a drive fault must not touch the power stage (a vertical axis
// would drop its load): the drive stays in Operation enabled on every cycle, from StandStill and
// from an ErrorStop of a limit switch.
TEST(Trust, ResetWithoutADriveFaultKeepsThePowerStageOn) {
    MotionConfig cfg;
    cfg.switches[0].pelm = 3000;
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_Reset& r = b.mc.blocks(0).reset;
        auto reset_keeps_power = [&] {
            r.Execute = true;
            for (int i = 0; i < 10 && !r.Done; ++i) {
                b.cycles(1);
                EXPECT_EQ(b.mc.drive(0).state(), Cia402State::operation_enabled) << "cycle " << i;
            }
            EXPECT_TRUE(r.Done);
            r.Execute = false;
            b.cycles(1);
        };
        reset_keeps_power(); // from StandStill
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
        MC_MoveAbsolute& a = b.mc.blocks(0).move_abs;
        a.Position = 10000, a.Velocity = 10000, a.Acceleration = a.Deceleration = 100000;
        a.Execute = true;
        b.until([&] { return a.Error; }, 3000);
        ASSERT_EQ(a.ErrorID, err::limit_positive);
        ASSERT_EQ(b.mc.axis(0).state(), AxisState::error_stop);
        reset_keeps_power(); // from ErrorStop by PELM
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
    }, cfg);
}

// MC_Home presets the counters at one physical point: once the motor has caught up, actual =
// command = Position (the approach stops while the motor still lags by velocity x lag).
TEST(Trust, HomingLeavesActualEqualToCommandAtRest) {
    MotionConfig cfg;
    cfg.switches[0].home = -2500;
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_Home& h = b.mc.blocks(0).home;
        h.Position = 0, h.Direction = -1;
        h.Execute = true;
        b.until([&] { return h.Done; }, 5000);
        ASSERT_TRUE(h.Done);
        b.cycles(30);
        EXPECT_EQ(b.mc.chip().command_position(0), 0);
        EXPECT_EQ(b.mc.chip().encoder_position(0), 0);
    }, cfg);
}

// An arc whose programmed end lies off the chip's track (a host rounding an angle) ends exactly
// on that end point: the chip's final correction step, so chained arcs do not drift.
TEST(Trust, ArcWithAnEndOffTheTrackEndsExactlyOnIt) {
    const double pi = std::acos(-1.0), R = 7071.3;
    rcsim::camc::Point s, e;
    for (int deg = 1; deg < 360; ++deg) { // the first rounded end the interpolator misses
        s = {std::llround(R), 0};
        e = {std::llround(R * std::cos(deg * pi / 180)), std::llround(R * std::sin(deg * pi / 180))};
        try {
            if (rcsim::camc::circle_walked_end(s, e, rcsim::camc::ArcDirection::ccw) != e) break;
        } catch (const rcsim::camc::InterpolationError&) {
        }
    }
    ASSERT_NE(rcsim::camc::circle_walked_end(s, e, rcsim::camc::ArcDirection::ccw), e);
    run_motion([s, e](MotionLoop& b) {
        b.power_on();
        MC_CircleCenterMove& c = b.mc.circle_move();
        // Twice the same arc, the second from where the first ended: no drift.
        for (int i = 1; i <= 2; ++i) {
            const std::int64_t x0 = b.mc.chip().command_position(0), y0 = b.mc.chip().command_position(1);
            c.CenterX = static_cast<std::int32_t>(-s.x), c.CenterY = static_cast<std::int32_t>(-s.y);
            c.EndX = static_cast<std::int32_t>(e.x - s.x), c.EndY = static_cast<std::int32_t>(e.y - s.y);
            c.Direction = dir_ccw, c.Velocity = 50000, c.Acceleration = c.Deceleration = 500000;
            c.Execute = true;
            b.until([&] { return c.Done || c.Error; }, 20000);
            ASSERT_TRUE(c.Done) << c.ErrorID;
            EXPECT_EQ(b.mc.chip().command_position(0), x0 + (e.x - s.x)) << "arc " << i;
            EXPECT_EQ(b.mc.chip().command_position(1), y0 + (e.y - s.y)) << "arc " << i;
            c.Execute = false;
            b.cycles(1);
        }
    });
}

// PLCopen's Velocity of an interpolated move is the path velocity: with the chip's constant
// vector speed mode the speed along a circle stays within 1 % of it in cruise, near the axes
// (one-axis steps) as at 45 degrees (two-axis steps), and the circle still closes exactly.
TEST(Trust, CirclePathSpeedStaysWithinOnePercentOfVelocityInCruise) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_CircleCenterMove& c = b.mc.circle_move();
        const double v = 20000, acc = 200000, R = 5000;
        c.CenterX = -5000, c.CenterY = 0, c.EndX = 0, c.EndY = 0, c.Direction = dir_ccw;
        c.Velocity = v, c.Acceleration = c.Deceleration = acc;
        c.Execute = true;
        std::vector<std::pair<double, double>> xy; // one sample per 1 ms cycle
        while (!c.Done && xy.size() < 5000) {
            b.cycles(1);
            xy.emplace_back(b.mc.chip().command_position(0), b.mc.chip().command_position(1));
        }
        ASSERT_TRUE(c.Done);
        const double ramp_ms = 1000 * v / acc;                   // 100 ms each way
        const double cruise_ms = 1000 * (2 * 3.14159265 * R / v) - ramp_ms; // the full length at v minus a ramp
        const int w = 25; // windows of 25 ms: 500 pulses of path, the chord 0.03 % short of the arc
        double lo = 1e9, hi = 0;
        for (int i = static_cast<int>(ramp_ms) + 5; i + w < static_cast<int>(cruise_ms) - 5; i += w) {
            const double chord = std::hypot(xy[i + w].first - xy[i].first, xy[i + w].second - xy[i].second);
            const double speed = chord / (w / 1000.0);
            lo = std::min(lo, speed), hi = std::max(hi, speed);
        }
        EXPECT_GE(lo, 0.99 * v);
        EXPECT_LE(hi, 1.01 * v);
        EXPECT_EQ(b.mc.chip().command_position(0), 0);
        EXPECT_EQ(b.mc.chip().command_position(1), 0);
    });
}

// PLCopen Part 1 reads (Enable-type, §2.4.2) and MC_SetPosition (§3.8): values from the axis,
// Error with an ErrorID where the axis cannot answer, everything reset when Enable falls.
TEST(Trust, ReadBlocksAndSetPositionFollowPartOne) {
    MotionConfig cfg;
    cfg.switches[1].pelm = 2000;
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_ReadStatus st;
        MC_ReadActualPosition pos;
        MC_ReadAxisError ae;
        MC_ReadParameter par;
        st.Axis = pos.Axis = ae.Axis = par.Axis = &b.mc.axis(0);
        st.Enable = pos.Enable = ae.Enable = par.Enable = true;
        st.call();
        EXPECT_TRUE(st.Valid && st.Busy && st.Standstill && !st.DiscreteMotion && !st.Error);
        MC_MoveAbsolute& m = b.mc.blocks(0).move_abs;
        m.Position = 3000, m.Velocity = 20000, m.Acceleration = m.Deceleration = 200000;
        m.Execute = true;
        b.cycles(20);
        st.call();
        EXPECT_TRUE(st.DiscreteMotion && !st.Standstill);
        par.ParameterNumber = 11; // CommandedVelocity: the cruise at 20000 (reached after 0.1 s)
        b.cycles(100);
        par.call();
        EXPECT_TRUE(par.Valid);
        EXPECT_DOUBLE_EQ(par.Value, 20000);
        b.until([&] { return m.Done; }, 2000);
        b.cycles(30);
        pos.call();
        EXPECT_DOUBLE_EQ(pos.Position, 3000);
        par.ParameterNumber = 1; // CommandedPosition
        par.call();
        EXPECT_DOUBLE_EQ(par.Value, 3000);
        par.ParameterNumber = 8; // MaxVelocitySystem: the chip's 10 Mpps
        par.call();
        EXPECT_DOUBLE_EQ(par.Value, 10e6);
        par.ParameterNumber = 16; // MaxJerkSystem: this axis has none
        par.call();
        EXPECT_TRUE(par.Error && !par.Valid);
        EXPECT_EQ(par.ErrorID, err::parameter_unsupported);
        par.Enable = false;
        par.call();
        EXPECT_FALSE(par.Error || par.Valid || par.Busy);
        EXPECT_EQ(par.ErrorID, 0);
        // No axis: Error 4101.
        MC_ReadStatus none;
        none.Enable = true;
        none.call();
        EXPECT_TRUE(none.Error);
        EXPECT_EQ(none.ErrorID, err::invalid_axis);

        // MC_SetPosition: both counters shift, nothing moves.
        const std::int64_t pulses = b.mc.chip().pulse_count(0);
        MC_SetPosition& sp = b.mc.blocks(0).set_pos;
        sp.Position = -500;
        sp.Execute = true;
        b.cycles(1);
        EXPECT_TRUE(sp.Done);
        EXPECT_EQ(b.mc.chip().command_position(0), -500);
        EXPECT_EQ(b.mc.chip().encoder_position(0), -500);
        EXPECT_EQ(b.mc.chip().pulse_count(0), pulses);
        sp.Execute = false;
        b.cycles(1);
        sp.Position = 100, sp.Relative = true;
        sp.Execute = true;
        b.cycles(1);
        EXPECT_EQ(b.mc.chip().command_position(0), -400);
        sp.Execute = false;
        b.cycles(1);
        // Refused while the axis moves (0x7004).
        m.Execute = false;
        b.cycles(1);
        m.Position = 20000;
        m.Execute = true;
        b.cycles(5);
        sp.Relative = false;
        sp.Execute = true;
        b.cycles(1);
        EXPECT_TRUE(sp.Error);
        EXPECT_EQ(sp.ErrorID, err::wrong_state);

        // The axis error of an ErrorStop by PELM (axis 1).
        MC_MoveAbsolute& m1 = b.mc.blocks(1).move_abs;
        m1.Position = 5000, m1.Velocity = 20000, m1.Acceleration = m1.Deceleration = 200000;
        m1.Execute = true;
        b.until([&] { return m1.Error; }, 2000);
        ae.Axis = &b.mc.axis(1);
        ae.call();
        EXPECT_TRUE(ae.Valid);
        EXPECT_EQ(ae.AxisErrorID, err::limit_positive);
    }, cfg);
}

} // namespace
