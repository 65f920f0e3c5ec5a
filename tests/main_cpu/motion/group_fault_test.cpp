// Issue 49 item 6: a drive fault in a two-axis group (Part 4). The faulted axis follows its CiA402
// fault reaction (0x605E) into Fault and ErrorStop 0x7103; its partner stops on the path with it
// and the group's move reports the group's error (GroupErrorStop), not the other axis' ErrorID;
// the partner needs no reset of its own.
#include "tests/main_cpu/motion/motion_loop.h"

#include <cmath>
#include <utility>

using namespace rcsim::motion;
using namespace rcsim::motion::test;

namespace {

/// A line in cruise; the drive of axis `bad` faults; `good` is its partner.
void fault_in_line(unsigned bad) {
    const unsigned good = 1 - bad;
    run_motion([bad, good](MotionLoop& b) {
        b.power_on();
        MC_LineMove2& l = b.mc.line_move();
        const double X = 20000, Y = 10000;
        l.X = 20000, l.Y = 10000, l.Velocity = 20000, l.Acceleration = l.Deceleration = 200000;
        l.Execute = true;
        b.cycles(300); // in cruise, mid-path
        b.mc.drive(bad).inject_fault(0x7500);
        b.until([&] { return l.Error; }, 100);
        EXPECT_TRUE(l.Error);
        EXPECT_EQ(l.ErrorID, err::group_error_stop);
        b.until([&] { return !b.mc.chip().busy(0) && !b.mc.chip().busy(1); }, 1000);
        b.cycles(2);
        EXPECT_EQ(b.mc.axis(bad).state(), AxisState::error_stop);
        EXPECT_EQ(b.mc.axis(bad).error_id(), err::drive_fault);
        b.until([&] { return b.mc.drive(bad).state() == Cia402State::fault; }, 100); // its fault reaction
        EXPECT_EQ(b.mc.drive(bad).state(), Cia402State::fault);
        EXPECT_EQ(b.mc.axis(good).state(), AxisState::standstill);
        EXPECT_EQ(b.mc.axis(good).error_id(), 0);
        // On the path: the commanded point lies on the line from the start (0, 0) to (X, Y).
        const double x = static_cast<double>(b.mc.chip().command_position(0));
        const double y = static_cast<double>(b.mc.chip().command_position(1));
        // Where the path was at the fault: v^2/2a + v (0.3 s - v/a) = 5000 pulses of path, x = 5000 X /
        // |(X, Y)| = 4472, give or take the few cycles the fault takes to stop the chip.
        EXPECT_NEAR(x, 4472, 60);
        EXPECT_LE(std::abs(x * Y - y * X) / std::hypot(X, Y), 1.0);
        // The healthy partner moves again without a reset.
        MC_MoveRelative& m = b.mc.blocks(good).move_rel;
        m.Distance = 1000, m.Velocity = 10000, m.Acceleration = m.Deceleration = 100000;
        m.Execute = true;
        b.until([&] { return m.Done || m.Error; }, 1000);
        EXPECT_TRUE(m.Done);
    });
}

// Axis 0 is cycled first: it takes its error itself. Axis 1 faulted: axis 0 sees the chip's ALARM
// end status of the line first and hands the error to the partner whose drive failed.
TEST(GroupFault, FaultOfTheFirstAxisStopsThePartnerOnThePathWithGroupErrorStop) { fault_in_line(0); }
TEST(GroupFault, FaultOfTheSecondAxisStopsThePartnerOnThePathWithGroupErrorStop) { fault_in_line(1); }

// The same for an axis error of the limits: axis 1 monitored with MaxPositionLag 200 while its
// drive lags T = 50 ms behind a line at 20000 pulses/s of path (10000 pulses/s on Y: 500 pulses of
// lag): axis 1 in ErrorStop 0x7112, the line ends with 0x7116, axis 0 in Standstill without error.
TEST(GroupFault, FollowingErrorOfOneAxisEndsTheLineWithGroupErrorStop) {
    MotionConfig cfg;
    cfg.drive.following_lag_s = 0.05;
    run_motion([](MotionLoop& b) {
        b.power_on();
        for (const auto& [number, value] : {std::pair{7, 200.0}, std::pair{6, 1.0}}) {
            MC_WriteParameter w;
            w.Axis = &b.mc.axis(1), w.ParameterNumber = number, w.Value = value, w.Execute = true;
            w.call();
            ASSERT_TRUE(w.Done);
        }
        MC_LineMove2& l = b.mc.line_move();
        l.X = 20000, l.Y = 10000, l.Velocity = 20000, l.Acceleration = l.Deceleration = 200000;
        l.Execute = true;
        b.until([&] { return l.Error || l.Done; }, 3000);
        EXPECT_TRUE(l.Error);
        EXPECT_EQ(l.ErrorID, err::group_error_stop);
        b.cycles(2);
        EXPECT_EQ(b.mc.axis(1).state(), AxisState::error_stop);
        EXPECT_EQ(b.mc.axis(1).error_id(), err::following_error);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
        EXPECT_EQ(b.mc.axis(0).error_id(), 0);
    }, cfg);
}

} // namespace
