// ST programs driving the motion layer through the PLCopen blocks (docs/st.md "Motion blocks"):
// the blocks move the CAMC-QI's axes, a runtime error puts every axis in ErrorStop, SP stops the
// moving axes. Each test is its own SystemC simulation (CTest runs each in its own process).
#include "main_cpu/motion/motion_controller.h"
#include "main_cpu/st/library.h"
#include "main_cpu/st/program.h"
#include "tests/support/sc_test.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace rcsim;
using namespace rcsim::motion;
using rcsim::st::StProgram;

namespace {

struct StMotionLoop : sc_core::sc_module {
    MotionController mc{"mc"};
    std::unique_ptr<StProgram> program;
    std::function<void(StMotionLoop&)> body;
    StMotionLoop(sc_core::sc_module_name n, const std::string& text) : sc_module(n) {
        std::vector<McAxis*> axes;
        std::vector<MC_Power*> power;
        for (unsigned a = 0; a < MotionController::axes; ++a) {
            axes.push_back(&mc.axis(a));
            power.push_back(&mc.power(a));
        }
        program = std::make_unique<StProgram>(text, "m.st", axes, power);
        EXPECT_EQ(program->start("M"), "");
        rcsim::test::spawn_checked([this] { body(*this); sc_core::sc_stop(); }, "run");
    }
    /// n control cycles of 1 ms: the motion layer's cycle, then the program's.
    void cycles(int n) {
        for (int i = 0; i < n; ++i) {
            mc.control_cycle(sc_core::sc_time_stamp());
            program->cycle(sc_core::sc_time_stamp());
            wait(sc_core::sc_time(1, sc_core::SC_MS));
        }
    }
    std::int64_t var(const char* v) const { return program->value(v).i; }
};

void run(const std::string& text, const std::function<void(StMotionLoop&)>& body) {
    StMotionLoop b("loop", text);
    b.body = body;
    sc_core::sc_start();
}

const char* mover = R"(
PROGRAM M
VAR power : MC_Power; move : MC_MoveAbsolute; go, done_seen : BOOL; zero : INT; crash : BOOL; x : INT; END_VAR
power(Axis := Axis0, Enable := TRUE);
move(Axis := Axis0, Execute := go AND power.Status, Position := 3000, Velocity := 20000,
     Acceleration := 200000, Deceleration := 200000);
IF move.Done THEN done_seen := TRUE; END_IF;
IF crash THEN x := x / zero; END_IF;
END_PROGRAM)";

TEST(StMotion, McPowerAndMcMoveAbsoluteMoveTheAxis) {
    run(mover, [](StMotionLoop& b) {
        b.cycles(10);
        EXPECT_EQ(b.var("power.Status"), 1); // the drive reached Operation enabled
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
        b.program->set_value("go", st::Value{1, 0});
        b.cycles(2);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::discrete_motion);
        EXPECT_EQ(b.var("move.Busy"), 1);
        // 3000 pulses at 20000 pulses/s, 0.1 s ramps: 0.1 + 0.05 s (trapezoid, 1000 pulses per
        // ramp, 1000 at full speed); well within 400 cycles.
        b.cycles(400);
        EXPECT_EQ(b.var("done_seen"), 1);
        EXPECT_EQ(b.mc.chip().command_position(0), 3000);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
    });
}

TEST(StMotion, ARuntimeErrorPutsEveryAxisInErrorStop) {
    run(mover, [](StMotionLoop& b) {
        b.cycles(10);
        b.program->set_value("go", st::Value{1, 0});
        b.cycles(20); // moving
        b.program->set_value("crash", st::Value{1, 0});
        b.cycles(1);
        EXPECT_FALSE(b.program->running());
        EXPECT_EQ(b.program->error(), "m.st:8:22: division by zero");
        for (unsigned a = 0; a < MotionController::axes; ++a) {
            EXPECT_EQ(b.mc.axis(a).state(), AxisState::error_stop) << "axis " << a;
            EXPECT_EQ(b.mc.axis(a).error_id(), st::program_error);
        }
        b.cycles(50);
        EXPECT_FALSE(b.mc.api().InMotion(0)); // the chip stopped the move
        EXPECT_LT(b.mc.chip().command_position(0), 3000);
    });
}

TEST(StMotion, StopDeceleratesTheMovingAxesAndTheProgramNoLongerRuns) {
    run(mover, [](StMotionLoop& b) {
        b.cycles(10);
        b.program->set_value("go", st::Value{1, 0});
        b.cycles(60); // in the middle of the move
        ASSERT_TRUE(b.mc.api().InMotion(0));
        b.program->stop();
        b.cycles(300);
        EXPECT_FALSE(b.mc.api().InMotion(0));
        EXPECT_LT(b.mc.chip().command_position(0), 3000); // stopped short of the target
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
        EXPECT_EQ(b.var("done_seen"), 0); // no program cycle saw the end
    });
}

TEST(StMotion, AnUnboundAxisRefIsInvalidAxis) {
    run("PROGRAM M VAR ax : AXIS_REF; m : MC_MoveRelative; END_VAR\n"
        "m(Axis := ax, Execute := TRUE, Distance := 100, Velocity := 1000, Acceleration := 1000, Deceleration := 1000);\n"
        "END_PROGRAM",
        [](StMotionLoop& b) {
            b.cycles(2);
            EXPECT_EQ(b.var("m.Error"), 1);
            EXPECT_EQ(b.var("m.ErrorID"), err::invalid_axis);
            EXPECT_TRUE(b.program->running()); // a block error is the program's to handle
        });
}

// MC_LineMove over three axes (docs/st.md "Motion blocks"): X, Y, Z relative to where the axes
// are; the chip interpolates them as one group, so every axis is at the same fraction of its
// distance at every instant and all arrive together.
const char* line3 = R"(
PROGRAM M
VAR p0, p1, p2 : MC_Power; line : MC_LineMove; go, done_seen : BOOL; END_VAR
p0(Axis := Axis0, Enable := TRUE);
p1(Axis := Axis1, Enable := TRUE);
p2(Axis := Axis2, Enable := TRUE);
line(AxisX := Axis0, AxisY := Axis1, AxisZ := Axis2, Execute := go AND p0.Status AND p1.Status AND p2.Status,
     X := 3000, Y := -1500, Z := 1000, Velocity := 20000, Acceleration := 200000, Deceleration := 200000);
IF line.Done THEN done_seen := TRUE; END_IF;
END_PROGRAM)";

TEST(StMotion, McLineMoveOfThreeAxesReachesItsEndPointWithTheAxesTogether) {
    run(line3, [](StMotionLoop& b) {
        b.cycles(10);
        ASSERT_EQ(b.var("p2.Status"), 1);
        b.program->set_value("go", st::Value{1, 0});
        b.cycles(2);
        for (unsigned a = 0; a < 3; ++a) EXPECT_EQ(b.mc.axis(a).state(), AxisState::synchronized_motion) << a;
        EXPECT_EQ(b.mc.axis(3).state(), AxisState::disabled); // AxisU left unset: not in the group
        EXPECT_EQ(b.var("line.Busy"), 1);
        // Path length sqrt(3000^2 + 1500^2 + 1000^2) = 3500 pulses at 20000 pulses/s with 0.1 s
        // ramps: 0.275 s. Each cycle the Y and Z positions are the X position's fraction of
        // their distances, to within one pulse (the chip's interpolation steps whole pulses).
        double worst = 0;
        int moving_cycles = 0;
        for (int k = 0; k < 500 && !b.var("done_seen"); ++k) {
            b.cycles(1);
            const double x = double(b.mc.chip().command_position(0));
            const double y = double(b.mc.chip().command_position(1)), z = double(b.mc.chip().command_position(2));
            worst = std::max({worst, std::abs(y - x * -1500.0 / 3000.0), std::abs(z - x * 1000.0 / 3000.0)});
            moving_cycles += x > 0 && x < 3000;
        }
        EXPECT_EQ(b.var("done_seen"), 1);
        EXPECT_LE(worst, 1.0);
        EXPECT_GT(moving_cycles, 200); // it took the profile's time, not one jump
        EXPECT_EQ(b.mc.chip().command_position(0), 3000);
        EXPECT_EQ(b.mc.chip().command_position(1), -1500);
        EXPECT_EQ(b.mc.chip().command_position(2), 1000);
        EXPECT_EQ(b.mc.chip().command_position(3), 0);
        for (unsigned a = 0; a < 3; ++a) EXPECT_EQ(b.mc.axis(a).state(), AxisState::standstill) << a;
        // Four motion blocks called in each execution: the cost model's count.
        EXPECT_EQ(b.program->cycle(sc_core::sc_time_stamp()).motion_calls, 4u);
    });
}

TEST(StMotion, McLineMoveWithoutAxisYIsInvalidAxis) {
    // Axis0 powered, so that the block gets past its first axis to the missing second.
    run("PROGRAM M VAR p0 : MC_Power; l : MC_LineMove; END_VAR\np0(Axis := Axis0, Enable := TRUE);\n"
        "l(AxisX := Axis0, AxisZ := Axis2, Execute := p0.Status, X := 100, Z := 100, Velocity := 1000,\n"
        "  Acceleration := 1000, Deceleration := 1000);\nEND_PROGRAM",
        [](StMotionLoop& b) {
            b.cycles(12);
            ASSERT_EQ(b.var("p0.Status"), 1);
            EXPECT_EQ(b.var("l.Error"), 1);
            EXPECT_EQ(b.var("l.ErrorID"), err::invalid_axis);
        });
}

} // namespace

namespace {

// PLCopen Part 1 (MC_Stop, Table 4): while MC_Stop.Execute is held the axis stays in Stopping and
// every motion command is refused with 16#7003, also after Done. The same sequence through an ST
// program (axis 0) and through the token layer's own blocks, the scenario `fb:` path (axis 1),
// gets the same answer: the rules are the axis', whoever calls the blocks.
TEST(StMotion, StopHeldRefusesAMoveAtDoneInStAndThroughTheControllersBlocks) {
    const char* text = R"(
PROGRAM M
VAR power : MC_Power; mv : MC_MoveRelative; stop : MC_Stop; move : MC_MoveAbsolute; go, halt : BOOL; END_VAR
power(Axis := Axis0, Enable := TRUE);
mv(Axis := Axis0, Execute := go, Distance := 50000, Velocity := 20000, Acceleration := 200000, Deceleration := 200000);
stop(Axis := Axis0, Execute := halt, Deceleration := 200000);
move(Axis := Axis0, Execute := stop.Done, Position := 0, Velocity := 20000, Acceleration := 200000,
     Deceleration := 200000);
END_PROGRAM)";
    run(text, [](StMotionLoop& b) {
        b.mc.command("SV", "1");
        b.cycles(10);
        b.program->set_value("go", st::Value{1, 0});
        MotionController::Blocks& k = b.mc.blocks(1);
        k.move_rel.Distance = 50000, k.move_rel.Velocity = 20000;
        k.move_rel.Acceleration = k.move_rel.Deceleration = 200000;
        k.move_rel.Execute = true;
        b.cycles(100);
        b.program->set_value("halt", st::Value{1, 0});
        k.stop.Deceleration = 200000;
        k.stop.Execute = true;
        for (int i = 0; i < 400 && !k.stop.Done; ++i) b.cycles(1);
        ASSERT_TRUE(k.stop.Done);
        k.move_abs.Position = 0, k.move_abs.Velocity = 20000;
        k.move_abs.Acceleration = k.move_abs.Deceleration = 200000;
        k.move_abs.Execute = true; // at Done, MC_Stop.Execute still high
        b.cycles(3);
        EXPECT_EQ(b.var("stop.Done"), 1);
        EXPECT_EQ(b.var("move.Error"), 1);
        EXPECT_EQ(b.var("move.ErrorID"), 0x7003);
        EXPECT_TRUE(k.move_abs.Error);
        EXPECT_EQ(k.move_abs.ErrorID, 0x7003);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::stopping);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::stopping);
        // Execute low: both leave Stopping (Note 6).
        b.program->set_value("halt", st::Value{0, 0});
        k.stop.Execute = false;
        b.cycles(2);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::standstill);
    });
}

} // namespace

namespace {

// The read blocks and MC_SetPosition from ST (docs/st.md "Motion blocks"): the position read
// back after MC_SetPosition, the status BOOLs, and a parameter the axis does not have.
TEST(StMotion, ReadBlocksAndSetPosition) {
    const char* text = R"(
PROGRAM M
VAR power : MC_Power; sp : MC_SetPosition; rp : MC_ReadActualPosition; rs : MC_ReadStatus;
    par : MC_ReadParameter; bad : MC_ReadParameter; go : BOOL; END_VAR
power(Axis := Axis0, Enable := TRUE);
sp(Axis := Axis0, Execute := go AND power.Status, Position := 1234);
rp(Axis := Axis0, Enable := TRUE);
rs(Axis := Axis0, Enable := TRUE);
par(Axis := Axis0, Enable := TRUE, ParameterNumber := 8);
bad(Axis := Axis0, Enable := TRUE, ParameterNumber := 16);
END_PROGRAM)";
    run(text, [](StMotionLoop& b) {
        b.cycles(10);
        EXPECT_EQ(b.var("rs.Standstill"), 1);
        EXPECT_EQ(b.var("rs.Valid"), 1);
        b.program->set_value("go", st::Value{1, 0});
        b.cycles(3);
        EXPECT_EQ(b.var("sp.Done"), 1);
        EXPECT_EQ(b.program->value("rp.Position").r, 1234.0);
        EXPECT_EQ(b.program->value("par.Value").r, 10e6);
        EXPECT_EQ(b.var("bad.Error"), 1);
        EXPECT_EQ(b.var("bad.ErrorID"), 0x7006);
        EXPECT_EQ(b.mc.chip().command_position(0), 1234);
    });
}


// MC_Jog (PLCopen Part 1): the axis runs while a jog input is held, at Velocity, and stops when
// it falls with the Deceleration's ramp: v^2 / (2 d) = 20000^2 / (2 * 400000) = 500 pulses.
TEST(StMotion, JogRunsWhileHeldAndHaltsWithItsDeceleration) {
    const char* text = R"(
PROGRAM M
VAR power : MC_Power; jog : MC_Jog; rv : MC_ReadActualVelocity; fwd, bwd : BOOL; END_VAR
power(Axis := Axis0, Enable := TRUE);
jog(Axis := Axis0, JogForward := fwd, JogBackward := bwd, Velocity := 20000, Acceleration := 200000,
    Deceleration := 400000);
rv(Axis := Axis0, Enable := TRUE);
END_PROGRAM)";
    run(text, [](StMotionLoop& b) {
        b.cycles(10);
        b.program->set_value("fwd", st::Value{1, 0});
        b.cycles(300); // 0.1 s ramp, then constant speed
        EXPECT_EQ(b.var("jog.Busy"), 1);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::continuous_motion);
        EXPECT_EQ(b.var("rv.Valid"), 1);
        EXPECT_NEAR(b.program->value("rv.Velocity").r, 20000, 200); // the drive follows the set speed
        const auto p0 = b.mc.chip().command_position(0);
        b.program->set_value("fwd", st::Value{0, 0});
        b.cycles(200);
        EXPECT_EQ(b.var("jog.Done"), 1);
        EXPECT_EQ(b.var("jog.Busy"), 0);
        EXPECT_EQ(b.var("jog.CommandAborted"), 0);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
        // The halt is issued in the cycle the input falls, from full speed: 500 pulses (+-1 of
        // the chip's pulse quantisation).
        EXPECT_NEAR(static_cast<double>(b.mc.chip().command_position(0) - p0), 500, 1);
        b.program->set_value("bwd", st::Value{1, 0});
        b.cycles(300);
        EXPECT_NEAR(b.program->value("rv.Velocity").r, -20000, 200);
        const auto p1 = b.mc.chip().command_position(0);
        b.program->set_value("fwd", st::Value{1, 0}); // both held: the jog stops
        b.cycles(200);
        EXPECT_EQ(b.var("jog.Done"), 1);
        EXPECT_LT(b.mc.chip().command_position(0), p1);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
    });
}

// Another block taking the axis over ends the jog with CommandAborted (Part 1 §2.4.1), and the
// jog does not restart while its input stays TRUE.
TEST(StMotion, AJogTakenOverIsCommandAborted) {
    const char* text = R"(
PROGRAM M
VAR power : MC_Power; jog : MC_Jog; move : MC_MoveAbsolute; fwd, go : BOOL; END_VAR
power(Axis := Axis0, Enable := TRUE);
jog(Axis := Axis0, JogForward := fwd, Velocity := 5000, Acceleration := 100000, Deceleration := 100000);
move(Axis := Axis0, Execute := go, Position := 0, Velocity := 5000, Acceleration := 100000,
     Deceleration := 100000);
END_PROGRAM)";
    run(text, [](StMotionLoop& b) {
        b.cycles(10);
        b.program->set_value("fwd", st::Value{1, 0});
        b.cycles(100);
        b.program->set_value("go", st::Value{1, 0});
        b.cycles(3);
        EXPECT_EQ(b.var("jog.CommandAborted"), 1);
        EXPECT_EQ(b.var("jog.Busy"), 0);
        b.cycles(500);
        EXPECT_EQ(b.var("move.Done"), 1); // back at 0: the jog did not take the axis again
        EXPECT_EQ(b.mc.chip().command_position(0), 0);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
    });
}

// A jog on an axis that is not powered is refused with the motion block's ErrorID (0x7001).
TEST(StMotion, JogOnADisabledAxisIsAnError) {
    const char* text = R"(
PROGRAM M
VAR jog : MC_Jog; fwd : BOOL; END_VAR
jog(Axis := Axis1, JogForward := fwd, Velocity := 1000, Acceleration := 10000, Deceleration := 10000);
END_PROGRAM)";
    run(text, [](StMotionLoop& b) {
        b.program->set_value("fwd", st::Value{1, 0});
        b.cycles(3);
        EXPECT_EQ(b.var("jog.Error"), 1);
        EXPECT_EQ(b.var("jog.ErrorID"), 0x7001);
        EXPECT_EQ(b.var("jog.Busy"), 0);
    });
}

// MC_MoveSuperimposed: in Standstill it acts as MC_MoveRelative (Part 1), VelocityDiff the
// velocity; on a moving axis it is refused (st::superimposed_in_motion) and the motion goes on.
TEST(StMotion, MoveSuperimposedMovesFromStandstillAndIsRefusedInMotion) {
    const char* text = R"(
PROGRAM M
VAR power : MC_Power; sup : MC_MoveSuperimposed; mv : MC_MoveVelocity; go, run : BOOL; END_VAR
power(Axis := Axis0, Enable := TRUE);
sup(Axis := Axis0, Execute := go, Distance := 2000, VelocityDiff := 20000, Acceleration := 200000,
    Deceleration := 200000);
mv(Axis := Axis0, Execute := run, Velocity := 5000, Acceleration := 100000, Deceleration := 100000);
END_PROGRAM)";
    run(text, [](StMotionLoop& b) {
        b.cycles(10);
        b.program->set_value("go", st::Value{1, 0});
        b.cycles(300);
        EXPECT_EQ(b.var("sup.Done"), 1);
        EXPECT_EQ(b.mc.chip().command_position(0), 2000);
        EXPECT_EQ(b.program->value("sup.CoveredDistance").r, 2000.0);
        b.program->set_value("go", st::Value{0, 0});
        b.program->set_value("run", st::Value{1, 0});
        b.cycles(100);
        b.program->set_value("go", st::Value{1, 0});
        b.cycles(2);
        EXPECT_EQ(b.var("sup.Error"), 1);
        EXPECT_EQ(b.var("sup.ErrorID"), st::superimposed_in_motion);
        EXPECT_EQ(b.var("mv.CommandAborted"), 0);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::continuous_motion);
    });
}

} // namespace


namespace {

// MC_WriteParameter from ST (issue #49 item 5): SWLimitPos 5000 enabled (Part 1 numbers 2 and 4)
// refuses a move to 6000 with 16#7110 and reads back through MC_ReadParameter 2.
TEST(StMotion, WriteParameterSetsASoftwareLimit) {
    const char* text = R"(
PROGRAM M
VAR power : MC_Power; lim : MC_WriteParameter; en : MC_WriteParameter; par : MC_ReadParameter;
    mv : MC_MoveAbsolute; END_VAR
power(Axis := Axis0, Enable := TRUE);
lim(Axis := Axis0, Execute := TRUE, ParameterNumber := 2, Value := 5000.0);
en(Axis := Axis0, Execute := lim.Done, ParameterNumber := 4, Value := 1.0);
par(Axis := Axis0, Enable := TRUE, ParameterNumber := 2);
mv(Axis := Axis0, Execute := en.Done AND power.Status, Position := 6000, Velocity := 10000.0,
   Acceleration := 100000.0, Deceleration := 100000.0);
END_PROGRAM)";
    run(text, [](StMotionLoop& b) {
        b.cycles(10);
        EXPECT_EQ(b.var("lim.Done"), 1);
        EXPECT_EQ(b.program->value("par.Value").r, 5000.0);
        EXPECT_EQ(b.var("mv.Error"), 1);
        EXPECT_EQ(b.var("mv.ErrorID"), 0x7110);
        EXPECT_EQ(b.mc.chip().pulse_count(0), 0);
    });
}

// MC_BUFFER_MODE's names in ST (issue #49 item 2): two tangent half circles (an S of radius 2000 at
// 10000 pulses/s) with BufferMode := mcBlendingLow keep the path speed at 10000 through the
// junction; the same program with mcBuffered stops there; 7 and 259 are refused with 0x7020.
const char* s_curve = R"(
PROGRAM M
VAR p0, p1 : MC_Power; c1, c2 : MC_CircleCenterMove; bad : MC_MoveRelative; go : BOOL;
    mode : INT := mcBlendingLow; badmode : INT := 7; names_ok : BOOL; END_VAR
p0(Axis := Axis0, Enable := TRUE);
p1(Axis := Axis1, Enable := TRUE);
c1(AxisX := Axis0, AxisY := Axis1, Execute := go, CenterX := 2000, CenterY := 0, EndX := 4000, EndY := 0,
   Direction := 0, Velocity := 10000, Acceleration := 100000, Deceleration := 100000);
c2(AxisX := Axis0, AxisY := Axis1, Execute := go AND c1.Busy, CenterX := 2000, CenterY := 0, EndX := 4000,
   EndY := 0, Direction := 1, Velocity := 10000, Acceleration := 100000, Deceleration := 100000,
   BufferMode := mode);
bad(Axis := Axis2, Execute := go, Distance := 100, Velocity := 1000, Acceleration := 1000,
    Deceleration := 1000, BufferMode := badmode);
names_ok := mcAborting = 0 AND mcBuffered = 1 AND mcBlendingLow = 2 AND mcBlendingPrevious = 3
            AND mcBlendingNext = 4 AND mcBlendingHigh = 5;
END_PROGRAM)";

/// Runs the S once; returns the lowest path speed from 0.1 s after the start to the second arc's
/// final ramp (its last 0.1 s), and the refused move's ErrorID.
double s_curve_min_speed(StMotionLoop& b, std::int64_t& bad_error) {
    b.program->set_value("go", st::Value{1, 0});
    b.cycles(100);
    double min_speed = 1e9;
    for (int i = 0; i < 5000 && !b.var("c2.Done"); ++i) {
        b.cycles(1);
        if (!b.mc.chip().busy(0) || ((b.mc.chip().drive_status(0) & camc::drvst::down) && b.var("c2.Active")))
            continue; // the second arc's own final ramp, and the end
        min_speed = std::min(min_speed, b.mc.chip().current_speed(0));
    }
    EXPECT_EQ(b.var("c2.Done"), 1);
    bad_error = b.var("bad.ErrorID");
    b.program->set_value("go", st::Value{0, 0});
    b.cycles(2);
    return min_speed;
}

TEST(StMotion, BufferModeNamesBlendTwoTangentHalfCircles) {
    run(s_curve, [](StMotionLoop& b) {
        b.cycles(10);
        EXPECT_EQ(b.var("names_ok"), 1);
        std::int64_t bad = 0;
        EXPECT_GT(s_curve_min_speed(b, bad), 9900) << "mcBlendingLow: no stop at the junction";
        EXPECT_EQ(b.mc.chip().command_position(0), 8000);
        EXPECT_EQ(b.mc.chip().command_position(1), 0);
        EXPECT_EQ(bad, 0x7020) << "BufferMode 7";
        b.program->set_value("mode", st::Value{1, 0}); // mcBuffered
        b.program->set_value("badmode", st::Value{259, 0}); // not 3 by wrapping
        EXPECT_LT(s_curve_min_speed(b, bad), 200) << "mcBuffered stops between the arcs";
        EXPECT_EQ(b.mc.chip().command_position(0), 16000);
        EXPECT_EQ(bad, 0x7020) << "BufferMode 259";
        EXPECT_EQ(b.mc.chip().command_position(2), 0) << "the refused moves never ran";
    });
}

} // namespace
