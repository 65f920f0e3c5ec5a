// PLCopen function blocks over the CAMC-QI and CiA402 drives: interface rules, state diagram,
// aborting and buffered moves, Stopping, ErrorStop and bad parameters.
#include "tests/main_cpu/motion/motion_loop.h"

using namespace rcsim::motion;
using namespace rcsim::motion::test;

namespace {

int outputs_set(const McExecuteFb& f) { return f.Done + f.Busy + f.CommandAborted + f.Error; }

TEST(PLCopen, PowerDrivesTheIndy7SequenceDisabledToStandstill) {
    run_motion([](MotionLoop& b) {
        b.cycles(3);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::disabled);
        MC_Power& p = b.mc.power(0);
        p.Enable = true;
        b.until([&] { return p.Status; });
        ASSERT_GE(p.history.size(), 3u);
        EXPECT_EQ(p.history[0], std::make_pair(std::uint16_t{0x06}, std::uint16_t{0x221}));
        EXPECT_EQ(p.history[1], std::make_pair(std::uint16_t{0x07}, std::uint16_t{0x233}));
        EXPECT_EQ(p.history[2].first, 0x0F);
        EXPECT_EQ(p.history[2].second & ~0x400, 0x237);
        EXPECT_TRUE(b.mc.chip().servo_on(0)); // SVON output
        b.cycles(1);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill); // Note 5
        p.Enable = false;
        b.cycles(1);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::disabled); // Note 2
        EXPECT_FALSE(p.Status);
    });
}

TEST(PLCopen, MoveAbsoluteOutputsFollowTheInterfaceRules) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveAbsolute& m = b.mc.blocks(0).move_abs;
        m.Position = 3000, m.Velocity = 20000, m.Acceleration = 200000, m.Deceleration = 200000;
        m.Execute = true;
        b.cycles(1);
        EXPECT_TRUE(m.Busy);
        EXPECT_TRUE(m.Active);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::discrete_motion);
        // Parameters are latched at the edge: changing them now has no effect.
        m.Position = 99999;
        int n = 0;
        while (!m.Done && n++ < 2000) {
            EXPECT_EQ(outputs_set(m), 1); // exclusivity while Execute
            b.cycles(1);
        }
        EXPECT_TRUE(m.Done);
        EXPECT_FALSE(m.Busy || m.Active || m.Error || m.CommandAborted);
        EXPECT_EQ(b.mc.chip().command_position(0), 3000);
        b.cycles(1);
        EXPECT_TRUE(m.Done); // stays while Execute is high
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
        m.Execute = false;
        b.cycles(1);
        EXPECT_FALSE(m.Done); // reset on the falling edge

        // Execute falling before completion: Done still shows for one cycle.
        m.Position = 0;
        m.Execute = true;
        b.cycles(1);
        m.Execute = false;
        b.until([&] { return m.Done; });
        EXPECT_TRUE(m.Done);
        b.cycles(1);
        EXPECT_FALSE(m.Done);
        EXPECT_EQ(b.mc.chip().command_position(0), 0);
    });
}

TEST(PLCopen, AbortingMoveAbortsTheRunningOneBufferedWaits) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveRelative& a = b.mc.blocks(0).move_rel;
        MC_MoveAbsolute& c = b.mc.blocks(0).move_abs;
        a.Distance = 50000, a.Velocity = 20000, a.Acceleration = 100000, a.Deceleration = 100000;
        a.Execute = true;
        b.cycles(200);
        ASSERT_TRUE(a.Busy);
        // Aborting: the first block reports CommandAborted, never Done.
        c.Position = -1000, c.Velocity = 20000, c.Acceleration = 100000, c.Deceleration = 100000;
        c.Mode = BufferMode::aborting;
        c.Execute = true;
        b.cycles(1);
        EXPECT_TRUE(a.CommandAborted);
        EXPECT_FALSE(a.Done);
        EXPECT_TRUE(c.Active);
        b.until([&] { return c.Done; });
        EXPECT_EQ(b.mc.chip().command_position(0), -1000);
        a.Execute = c.Execute = false;
        b.cycles(1);

        // Buffered: the second waits (Busy, not Active) and starts after the first is Done,
        // relative to the set position at its start.
        a.Distance = 4000;
        a.Execute = true;
        b.cycles(1);
        MC_MoveRelative second;
        second.Axis = &b.mc.axis(0);
        second.Distance = 1000, second.Velocity = 20000, second.Acceleration = 100000, second.Deceleration = 100000;
        second.Mode = BufferMode::buffered;
        second.Execute = true;
        second.call();
        EXPECT_TRUE(second.Busy);
        EXPECT_FALSE(second.Active);
        while (!a.Done) {
            b.cycles(1);
            second.call();
            if (!a.Done) {
                EXPECT_FALSE(second.Active);
            }
        }
        EXPECT_EQ(b.mc.chip().command_position(0), 3000);
        for (int i = 0; i < 2000 && !second.Done; ++i) {
            b.cycles(1);
            second.call();
        }
        EXPECT_TRUE(second.Done);
        EXPECT_EQ(b.mc.chip().command_position(0), 4000);
    });
}

TEST(PLCopen, StopHoldsStoppingAndRejectsMotionWhileExecute) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveAbsolute& m = b.mc.blocks(1).move_abs;
        m.Position = 100000, m.Velocity = 20000, m.Acceleration = 100000, m.Deceleration = 100000;
        m.Execute = true;
        b.cycles(300);
        MC_Stop& s = b.mc.blocks(1).stop;
        s.Deceleration = 400000;
        s.Execute = true;
        b.cycles(2); // the move's block runs before the stop's in a cycle: it sees it next cycle
        EXPECT_TRUE(m.CommandAborted);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::stopping);
        MC_MoveRelative r;
        r.Axis = &b.mc.axis(1);
        r.Distance = 10, r.Velocity = 100, r.Acceleration = 1000, r.Deceleration = 1000;
        r.Execute = true;
        r.call();
        EXPECT_TRUE(r.Error);
        EXPECT_EQ(r.ErrorID, err::axis_stopping);
        // Done once stopped, but the axis stays in Stopping while Execute (the controller's token
        // program would drop Execute; here the test holds it).
        s.Execute = true;
        for (int i = 0; i < 200 && !s.Done; ++i) {
            b.mc.control_cycle(sc_core::sc_time_stamp());
            s.Execute = true;
            wait(sc_core::sc_time(1, sc_core::SC_MS));
        }
        EXPECT_FALSE(b.mc.chip().busy(1));
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::stopping);
        s.Execute = false;
        b.cycles(1);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::standstill); // Note 6
    });
}

TEST(PLCopen, HaltStopsToStandstillAndCanBeAborted) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveAbsolute& m = b.mc.blocks(2).move_abs;
        m.Position = 100000, m.Velocity = 20000, m.Acceleration = 100000, m.Deceleration = 100000;
        m.Execute = true;
        b.cycles(300);
        MC_Halt& h = b.mc.blocks(2).halt;
        h.Execute = true;
        b.cycles(2); // the move's block runs before the halt's in a cycle: it sees it next cycle
        EXPECT_TRUE(m.CommandAborted);
        EXPECT_EQ(b.mc.axis(2).state(), AxisState::discrete_motion);
        b.until([&] { return h.Done; });
        EXPECT_EQ(b.mc.axis(2).state(), AxisState::standstill);
        EXPECT_FALSE(b.mc.chip().busy(2));
    });
}

// Issue #49 item 1, Part 1 §3.7: the running drive halts at MC_Halt's own Deceleration, not at the
// aborted move's. At 20000 pulses/s a Deceleration of 50000 pulses/s^2 travels
// v^2 / (2 dec) = 20000^2 / 100000 = 4000 pulses; the move's own 200000 would give 1000.
TEST(PLCopen, HaltRampsAtItsOwnDeceleration) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveAbsolute& m = b.mc.blocks(2).move_abs;
        m.Position = 1000000, m.Velocity = 20000, m.Acceleration = 200000, m.Deceleration = 200000;
        m.Execute = true;
        b.cycles(300); // at speed after 0.1 s
        MC_Halt& h = b.mc.blocks(2).halt;
        h.Deceleration = 50000;
        h.Execute = true;
        b.cycles(1); // the halt's block sees Execute rise in this cycle and stops the drive then
        const std::int64_t from = b.mc.chip().command_position(2);
        ASSERT_GE(b.until([&] { return h.Done; }), 0);
        const double travel = double(b.mc.chip().command_position(2) - from);
        EXPECT_NEAR(travel, 20000.0 * 20000.0 / (2 * 50000.0), 40) << "4000 pulses +- 1 %";
        EXPECT_EQ(b.mc.axis(2).state(), AxisState::standstill);
    });
}

// A negative Deceleration is refused (Part 1: rates are positive), the axis keeps moving.
TEST(PLCopen, HaltRefusesANegativeDeceleration) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveVelocity& v = b.mc.blocks(2).move_vel;
        v.Velocity = 10000, v.Acceleration = 100000, v.Deceleration = 100000;
        v.Execute = true;
        b.cycles(50);
        MC_Halt& h = b.mc.blocks(2).halt;
        h.Deceleration = -1;
        h.Execute = true;
        b.cycles(2);
        EXPECT_TRUE(h.Error);
        EXPECT_EQ(h.ErrorID, err::invalid_accel);
        EXPECT_EQ(b.mc.axis(2).state(), AxisState::continuous_motion);
    });
}

TEST(PLCopen, LimitSwitchDriveFaultAndBadParametersGiveErrors) {
    MotionConfig cfg;
    cfg.switches[0].pelm = 20000; // the plotter's + limit at 20000 pulses
    run_motion([](MotionLoop& b) {
        b.power_on();
        // Bad parameters: FB Error with ErrorID, the axis stays in Standstill.
        MC_MoveAbsolute& m = b.mc.blocks(0).move_abs;
        m.Position = 30000, m.Velocity = 0, m.Acceleration = 1, m.Deceleration = 1;
        m.Execute = true;
        b.cycles(1);
        EXPECT_TRUE(m.Error);
        EXPECT_EQ(m.ErrorID, err::invalid_velocity);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
        m.Execute = false;
        b.cycles(1);
        MC_MoveAbsolute none;
        none.Execute = true;
        none.Velocity = 1, none.Acceleration = 1, none.Deceleration = 1;
        none.call();
        EXPECT_EQ(none.ErrorID, err::invalid_axis);
        EXPECT_EQ(b.mc.command("MA", "7,100,100,100,100").bch, 0x02); // unknown axis

        // Moving into PELM: ErrorStop, the running block ends with Error.
        m.Velocity = 20000, m.Acceleration = 100000, m.Deceleration = 100000;
        m.Execute = true;
        b.until([&] { return m.Error; }, 5000);
        EXPECT_EQ(m.ErrorID, err::limit_positive);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::error_stop);
        EXPECT_EQ(b.mc.state(), "ERRORSTOP");
        // Move while in ErrorStop.
        MC_MoveRelative back;
        back.Axis = &b.mc.axis(0);
        back.Distance = -5000, back.Velocity = 20000, back.Acceleration = 100000, back.Deceleration = 100000;
        back.Execute = true;
        back.call();
        EXPECT_EQ(back.ErrorID, err::axis_error_stop);
        EXPECT_EQ(b.mc.command("MR", "0,-5000,20000,100000,100000").bch, 0x05);
        // MC_Reset: ErrorStop -> Standstill (power on, Note 4); then the way back is free.
        EXPECT_EQ(b.mc.command("RS", "1").bch, 0x00);
        b.until([&] { return b.mc.axis(0).state() == AxisState::standstill; }, 100);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
        EXPECT_EQ(b.mc.command("MR", "0,-5000,20000,100000,100000").bch, 0x00);
        b.until([&] { return b.mc.axis(0).state() == AxisState::standstill; });
        EXPECT_LT(b.mc.chip().command_position(0), 20000);

        // Drive fault -> CiA402 Fault -> CAMC-QI alarm -> ErrorStop; reset needs the cause gone.
        b.mc.drive(1).inject_fault(0x7500);
        b.cycles(3);
        EXPECT_TRUE(b.mc.chip().pin(1, rcsim::camc::Pin::alarm));
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::error_stop);
        EXPECT_EQ(b.mc.axis(1).error_id(), err::drive_fault);
        MC_Reset& r = b.mc.blocks(1).reset;
        r.Execute = true;
        b.cycles(3);
        EXPECT_TRUE(r.Error);
        r.Execute = false;
        b.cycles(1);
        b.mc.drive(1).clear_fault_cause();
        r.Execute = true;
        b.until([&] { return r.Done; }, 50);
        EXPECT_TRUE(r.Done);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::standstill);
        EXPECT_EQ(b.mc.drive(1).state(), Cia402State::operation_enabled);
    }, cfg);
}

TEST(PLCopen, ErrorStopAbortsBufferedCommandsWithError) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveRelative& a = b.mc.blocks(3).move_rel;
        a.Distance = 80000, a.Velocity = 20000, a.Acceleration = 100000, a.Deceleration = 100000;
        a.Execute = true;
        b.cycles(10);
        MC_MoveAbsolute& q = b.mc.blocks(3).move_abs;
        q.Position = 0, q.Velocity = 20000, q.Acceleration = 100000, q.Deceleration = 100000;
        q.Mode = BufferMode::buffered;
        q.Execute = true;
        b.cycles(1);
        EXPECT_TRUE(q.Busy);
        b.mc.command("ES", "");
        b.cycles(2);
        EXPECT_TRUE(a.Error);
        EXPECT_TRUE(q.Error);
        EXPECT_EQ(q.ErrorID, err::emergency_stop);
        EXPECT_EQ(b.mc.axis(3).state(), AxisState::error_stop);
    });
}

TEST(PLCopen, LineMove2AndCircleCenterMoveUseBothAxes) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_LineMove2& l = b.mc.line_move();
        l.X = 8000, l.Y = -4800, l.Velocity = 20000, l.Acceleration = 200000, l.Deceleration = 200000;
        l.Execute = true;
        b.cycles(1);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::synchronized_motion);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::synchronized_motion);
        b.until([&] { return l.Done; });
        EXPECT_EQ(b.mc.chip().command_position(0), 8000);
        EXPECT_EQ(b.mc.chip().command_position(1), -4800);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::standstill);
        // A circle whose end is not on the circle: FB error, nothing moves.
        MC_CircleCenterMove& c = b.mc.circle_move();
        c.CenterX = -1000, c.CenterY = 0, c.EndX = 500, c.EndY = 500, c.Velocity = 10000;
        c.Acceleration = c.Deceleration = 100000;
        c.Execute = true;
        b.cycles(1);
        EXPECT_TRUE(c.Error);
        EXPECT_EQ(c.ErrorID, err::interpolation_value);
        c.Execute = false;
        b.cycles(1);
        // Half circle, CW, radius 1000.
        c.EndX = -2000, c.EndY = 0, c.Direction = dir_cw;
        c.Execute = true;
        b.until([&] { return c.Done; });
        EXPECT_EQ(b.mc.chip().command_position(0), 8000 - 2000);
        EXPECT_EQ(b.mc.chip().command_position(1), -4800);
    });
}

} // namespace

namespace {

TEST(PLCopen, MoveVelocityRunsInContinuousMotionWithInVelocityAndNoDone) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveVelocity& v = b.mc.blocks(0).move_vel;
        v.Velocity = 20000, v.Acceleration = 100000, v.Deceleration = 100000;
        v.Execute = true;
        b.cycles(1);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::continuous_motion);
        EXPECT_TRUE(v.Busy);
        EXPECT_TRUE(v.Active);
        EXPECT_FALSE(v.InVelocity);
        // The ramp STD 100 -> 20000 pps at 100000 pps/s takes 0.199 s: InVelocity from cycle 200 on.
        const int n = b.until([&] { return v.InVelocity; }, 1000);
        EXPECT_GE(n, 198);
        EXPECT_LE(n, 201);
        EXPECT_EQ(b.mc.chip().current_speed(0), 20000);
        const std::int64_t p0 = b.mc.chip().command_position(0);
        b.cycles(100); // 0.1 s at 20000 pps
        EXPECT_EQ(b.mc.chip().command_position(0) - p0, 2000);
        EXPECT_FALSE(v.Done);
        EXPECT_TRUE(v.Busy && v.Active && v.InVelocity);
        // Execute falling does not stop it (Part 1 §2.4.1).
        v.Execute = false;
        b.cycles(10);
        EXPECT_TRUE(v.Busy && v.InVelocity);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::continuous_motion);
        // MC_Halt aborts it: CommandAborted, InVelocity reset; Standstill when the Halt is Done.
        MC_Halt& h = b.mc.blocks(0).halt;
        h.Execute = true;
        b.cycles(2);
        EXPECT_TRUE(v.CommandAborted);
        EXPECT_FALSE(v.InVelocity || v.Busy || v.Active);
        b.until([&] { return h.Done; });
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
        EXPECT_FALSE(b.mc.chip().busy(0));
        b.cycles(1);
        EXPECT_FALSE(v.CommandAborted); // Execute is low: visible for one call only
    });
}

TEST(PLCopen, MoveVelocityDirectionsAndBufferedSuccessorAtInVelocity) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveVelocity& v = b.mc.blocks(1).move_vel;
        v.Velocity = 5000, v.Acceleration = 50000, v.Deceleration = 50000;
        v.Direction = McDirection::negative;
        v.Execute = true;
        b.until([&] { return v.InVelocity; }, 1000);
        EXPECT_LT(b.mc.chip().command_position(1), 0);
        EXPECT_TRUE(b.mc.chip().drive_status(1) & rcsim::camc::drvst::negative);
        // A second block with mcCurrentDirection keeps the negative direction; a negative
        // Velocity with Direction negative drives positive.
        MC_MoveVelocity cur;
        cur.Axis = &b.mc.axis(1);
        cur.Velocity = 8000, cur.Acceleration = 50000, cur.Deceleration = 50000;
        cur.Direction = McDirection::current;
        cur.Execute = true;
        cur.call();
        EXPECT_TRUE(cur.Busy);
        for (int i = 0; i < 1000 && !cur.InVelocity; ++i) {
            b.cycles(1);
            cur.call();
        }
        EXPECT_TRUE(v.CommandAborted); // Execute is still high: it stays visible
        EXPECT_FALSE(v.Busy);
        EXPECT_EQ(b.mc.chip().current_speed(1), 8000);
        EXPECT_TRUE(b.mc.chip().drive_status(1) & rcsim::camc::drvst::negative);

        // Buffered MC_MoveAbsolute after a MoveVelocity: it waits until InVelocity, then the
        // velocity block is CommandAborted and the move goes to its target.
        MC_MoveVelocity& w = b.mc.blocks(2).move_vel;
        w.Velocity = 10000, w.Acceleration = 20000, w.Deceleration = 20000;
        w.Execute = true;
        b.cycles(1);
        MC_MoveAbsolute& m = b.mc.blocks(2).move_abs;
        m.Position = 0, m.Velocity = 10000, m.Acceleration = 100000, m.Deceleration = 100000;
        m.Mode = BufferMode::buffered;
        m.Execute = true;
        b.cycles(1);
        EXPECT_TRUE(m.Busy);
        EXPECT_FALSE(m.Active);
        // Ramp 100 -> 10000 at 20000 pps/s: 0.495 s.
        const int n = b.until([&] { return w.CommandAborted; }, 2000);
        EXPECT_GE(n, 490);
        EXPECT_LE(n, 498);
        EXPECT_TRUE(m.Active);
        b.until([&] { return m.Done; });
        EXPECT_EQ(b.mc.chip().command_position(2), 0);
        EXPECT_EQ(b.mc.axis(2).state(), AxisState::standstill);
    });
}

TEST(PLCopen, MoveVelocityParameterErrorsAndTheMvToken) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_MoveVelocity& v = b.mc.blocks(3).move_vel;
        auto edge = [&](double vel, double acc, double dec) {
            v.Execute = false;
            v.call();
            v.Velocity = vel, v.Acceleration = acc, v.Deceleration = dec;
            v.Execute = true;
            v.call();
            return v.Error ? v.ErrorID : std::uint16_t{0};
        };
        EXPECT_EQ(edge(0, 1000, 1000), err::invalid_velocity);
        EXPECT_EQ(edge(1000, 0, 1000), err::invalid_accel);
        EXPECT_EQ(edge(1000, 1000, -1), err::invalid_accel);
        EXPECT_EQ(edge(2e7, 1000, 1000), err::velocity_out_of_bound);
        EXPECT_EQ(b.mc.axis(3).state(), AxisState::standstill);
        v.Execute = false;
        b.cycles(1);
        EXPECT_EQ(b.mc.command("MV", "3,-3000,30000,30000").bch, 0x00);
        b.cycles(200);
        EXPECT_EQ(b.mc.axis(3).state(), AxisState::continuous_motion);
        EXPECT_EQ(b.mc.chip().current_speed(3), 3000);
        EXPECT_LT(b.mc.chip().command_position(3), -300);
        EXPECT_EQ(b.mc.command("MV", "3,0,30000,30000").bch, 0x02);
        EXPECT_EQ(b.mc.command("MV", "3,0,30000,30000").data, std::to_string(err::invalid_velocity));
        EXPECT_EQ(b.mc.command("MV", "3,100,30000").bch, 0x02);
    });
}

} // namespace

namespace {

// S-curves (docs/motion.md "Profiles"): the jerk share p of a ramp of dv at rate a with jerk J
// is p = 2a^2 / (J dv + a^2); the chip holds p in whole percent (SW1/SW2), its first jerk
// section lasts tj = p T / 2 with T = dv / (a (1 - p/2)), and in it v = STD + (a / tj) t^2 / 2.
TEST(PLCopen, JerkInputGivesTheChipsSCurve) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        using namespace rcsim::camc;
        MC_MoveAbsolute& m = b.mc.blocks(0).move_abs;
        m.Position = 30000, m.Velocity = 20000, m.Acceleration = 200000, m.Deceleration = 200000;
        m.Jerk = 4e6;
        m.Execute = true;
        b.cycles(1); // the drive starts at the first control cycle
        const double a = 200000, dv = 20000 - 100, J = 4e6;
        const double p = std::round(100 * 2 * a * a / (J * dv + a * a)) / 100; // 0.67
        EXPECT_EQ(b.mc.chip().read_register(0, qi::SW1), 67u);
        EXPECT_EQ(b.mc.chip().read_register(0, qi::SW2), 67u);
        EXPECT_EQ(b.mc.chip().read_register(0, qi::DCFG) & dcfg::profile_mask, 3u); // asymmetric S
        const double T = dv / (a * (1 - p / 2)), tj = p * T / 2, je = a / tj;
        EXPECT_NEAR(je, J, 0.02 * J); // the percent rounding
        EXPECT_NEAR(b.mc.chip().current_speed(0), 100 + je * 1e-6 / 2, 1e-6); // t = 1 ms into it
        b.until([&] { return m.Done; });
        EXPECT_EQ(b.mc.chip().command_position(0), 30000);
        m.Execute = false;
        b.cycles(1);
        // Too low a jerk for the rate: a pure S (100 %) at the lowered rate sqrt(J dv).
        m.Position = 0, m.Jerk = 1e6;
        m.Execute = true;
        b.cycles(1);
        EXPECT_EQ(b.mc.chip().read_register(0, qi::SW1), 100u);
        EXPECT_EQ(b.mc.chip().read_register(0, qi::RATE1), static_cast<std::uint32_t>(std::lround(std::sqrt(1e6 * dv))));
        b.until([&] { return m.Done; });
        EXPECT_EQ(b.mc.chip().command_position(0), 0);
        m.Execute = false;
        b.cycles(1);
        // Jerk 0 is a trapezoid again (the jerk is for one move), a negative one an error.
        m.Position = 100, m.Jerk = 0;
        m.Execute = true;
        b.cycles(1);
        EXPECT_EQ(b.mc.chip().read_register(0, qi::DCFG) & dcfg::profile_mask, 1u);
        b.until([&] { return m.Done; });
        m.Execute = false;
        b.cycles(1);
        m.Jerk = -1;
        m.Execute = true;
        m.call();
        EXPECT_EQ(m.ErrorID, err::profile_invalid);
        // MC_MoveVelocity with Jerk ramps as an S too.
        MC_MoveVelocity& v = b.mc.blocks(1).move_vel;
        v.Velocity = 20000, v.Acceleration = 200000, v.Deceleration = 200000, v.Jerk = 4e6;
        v.Execute = true;
        b.cycles(1);
        EXPECT_EQ(b.mc.chip().read_register(1, qi::DCFG) & dcfg::profile_mask, 3u);
        EXPECT_EQ(b.mc.chip().read_register(1, qi::SW1), 67u);
    });
}

TEST(QiApi, ProfileModesOfAxl) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        using namespace rcsim::camc;
        QiMotionApi& api = b.mc.api();
        EXPECT_EQ(api.SetProfileMode(2, 2), axl::profile_invalid); // quasi-S: not modelled
        EXPECT_EQ(api.SetProfileMode(2, 5), axl::profile_invalid);
        EXPECT_EQ(api.SetAccelJerk(2, 101), axl::profile_invalid);
        ASSERT_EQ(api.SetProfileMode(2, 3), axl::success); // symmetric S
        ASSERT_EQ(api.SetAccelJerk(2, 50), axl::success);
        ASSERT_EQ(api.MovePos(2, 5000, 10000, 100000, 100000), axl::success);
        EXPECT_EQ(b.mc.chip().read_register(2, qi::DCFG) & dcfg::profile_mask, 2u);
        EXPECT_EQ(b.mc.chip().read_register(2, qi::SW1), 50u);
        // In the first jerk section of a 50 % ramp: tj = 0.25 T, T = 9900 / (100000 * 0.75).
        const double tj = 0.25 * 9900 / 75000.0;
        wait(sc_core::sc_time(1, sc_core::SC_MS));
        EXPECT_NEAR(b.mc.chip().current_speed(2), 100 + 100000 / tj * 1e-6 / 2, 1e-6);
        ASSERT_EQ(api.SetProfileMode(3, 0), axl::success); // symmetric trapezoid: RATE1 both ways
        ASSERT_EQ(api.MovePos(3, 5000, 10000, 100000, 50000), axl::success);
        EXPECT_EQ(b.mc.chip().read_register(3, qi::DCFG) & dcfg::profile_mask, 0u);
        b.until([&] { return !b.mc.chip().busy(2) && !b.mc.chip().busy(3); });
        EXPECT_EQ(b.mc.chip().command_position(2), 5000);
        EXPECT_EQ(b.mc.chip().command_position(3), 5000);
    });
}

} // namespace
