// Issue 49 item 7: CiA402 quick stop (controlword 0x02, transition 11) by its option code 0x605A,
// disable operation (transition 5) by 0x605C, and the emergency path to them from MC_Stop.
// Expected values: CiA402's option codes and the stop distance v^2 / 2a of the ramp they name.
#include "tests/main_cpu/motion/motion_loop.h"

#include <cmath>

using namespace rcsim::motion;
using namespace rcsim::motion::test;
using S = Cia402State;

namespace {

constexpr double v0 = 10000, dt = 1e-4, slow_down = 50000, quick = 200000; // 0x6084, 0x6085

/// A drive in PV at v0 pulses/s without following lag, 0x6084 = slow_down, 0x6085 = quick.
Cia402Drive running_drive() {
    Cia402Drive::Config c;
    c.following_lag_s = 0;
    Cia402Drive d(c);
    d.update(0.002);
    EXPECT_TRUE(d.write_object(0x6084, slow_down));
    EXPECT_TRUE(d.write_object(0x6085, quick));
    d.set_mode(mode::pv);
    d.update(dt);
    for (std::uint16_t w : {0x06, 0x07, 0x0F}) d.set_controlword(w);
    d.profile_accel = 1000000;
    d.target_velocity = static_cast<std::int32_t>(v0);
    for (int i = 0; i < 200; ++i) d.update(dt);
    EXPECT_DOUBLE_EQ(d.actual_velocity(), v0);
    return d;
}

/// Updates until the motor stands; the distance travelled.
double travel_to_rest(Cia402Drive& d) {
    const double from = static_cast<double>(d.actual_position());
    for (int i = 0; i < 100000 && (i < 2 || d.actual_velocity() != 0); ++i) d.update(dt);
    return static_cast<double>(d.actual_position()) - from;
}

// 0x605A: 1 and 5 ramp at the slow-down ramp 0x6084, 2 and 6 at the quick stop ramp 0x6085, 0 at
// once; 1, 2 end in Switch on disabled (transition 12), 5, 6 stay in Quick stop active and 0x0F
// brings them back to Operation enabled (transition 16).
TEST(QuickStop, OptionCodeChoosesTheRampAndTheEndState) {
    struct Case { int option; double decel; S end; };
    for (const Case c : {Case{0, 0, S::switch_on_disabled}, Case{1, slow_down, S::switch_on_disabled},
                         Case{2, quick, S::switch_on_disabled}, Case{5, slow_down, S::quick_stop_active},
                         Case{6, quick, S::quick_stop_active}}) {
        SCOPED_TRACE(c.option);
        Cia402Drive d = running_drive();
        ASSERT_TRUE(d.write_object(0x605A, c.option));
        d.set_controlword(0x02);
        EXPECT_EQ(d.state(), S::quick_stop_active);
        EXPECT_EQ(d.last_transition(), 11);
        const double want = c.decel > 0 ? v0 * v0 / (2 * c.decel) : 0;
        EXPECT_NEAR(travel_to_rest(d), want, v0 * dt + 1); // one update step and the encoder's pulse
        EXPECT_EQ(d.state(), c.end);
        if (c.end == S::quick_stop_active) {
            d.set_controlword(0x0F);
            EXPECT_EQ(d.state(), S::operation_enabled);
            EXPECT_EQ(d.last_transition(), 16);
        }
    }
}

// 0x605C: servo off at speed with 1 ramps at 0x6084 in Operation enabled, then transition 5;
// with 0 it disables the drive function at once.
TEST(QuickStop, DisableOperationOptionRampsDownAtServoOff) {
    for (const int option : {0, 1}) {
        SCOPED_TRACE(option);
        Cia402Drive d = running_drive();
        ASSERT_TRUE(d.write_object(0x605C, option));
        d.set_servo_on_input(false);
        EXPECT_EQ(d.state(), option ? S::operation_enabled : S::switched_on);
        EXPECT_NEAR(travel_to_rest(d), option ? v0 * v0 / (2 * slow_down) : 0, v0 * dt + 1);
        EXPECT_EQ(d.state(), S::switched_on);
        EXPECT_EQ(d.last_transition(), 5);
    }
    EXPECT_FALSE(running_drive().write_object(0x605C, 2)); // CiA402: 0 or 1
}

// MC_Stop with Emergency sends the drives the quick stop command: with 0x605A = 6 written
// through MC_WriteParameter the drive stays in Quick stop active (MC_Power does not time out) until
// MC_Reset brings it back (transition 16) and the axis to Standstill.
TEST(QuickStop, EmergencyStopReachesTheDrivesQuickStop) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_WriteParameter w;
        w.Axis = &b.mc.axis(0), w.ParameterNumber = 0x605A, w.Value = 6, w.Execute = true;
        w.call();
        ASSERT_TRUE(w.Done);
        MC_MoveVelocity& v = b.mc.blocks(0).move_vel;
        v.Velocity = 20000, v.Acceleration = v.Deceleration = 200000;
        v.Execute = true;
        b.cycles(150);
        MC_Stop& s = b.mc.blocks(0).stop;
        s.Emergency = true, s.Execute = true;
        b.cycles(1);
        EXPECT_EQ(b.mc.drive(0).state(), S::quick_stop_active);
        EXPECT_EQ(b.mc.drive(0).last_transition(), 11);
        b.cycles(200);
        EXPECT_EQ(b.mc.drive(0).state(), S::quick_stop_active); // option 6 stays
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::error_stop);
        EXPECT_EQ(b.mc.axis(0).error_id(), err::emergency_stop);
        s.Execute = false;
        MC_Reset& r = b.mc.blocks(0).reset;
        r.Execute = true;
        b.until([&] { return r.Done || r.Error; }, 500);
        EXPECT_TRUE(r.Done);
        EXPECT_EQ(b.mc.drive(0).state(), S::operation_enabled);
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
    });
}

} // namespace

namespace {

// Servo off at speed with 0x605C = 1, and MC_Power.Enable back on during the ramp: the axis stays
// unpowered until the drive has stopped and is enabled again (it follows no pulse while ramping),
// and the next move then travels what it is commanded.
TEST(QuickStop, PowerBackOnDuringTheDisableRampWaitsForIt) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_WriteParameter w;
        w.Axis = &b.mc.axis(0), w.ParameterNumber = 0x605C, w.Value = 1, w.Execute = true;
        w.call();
        ASSERT_TRUE(w.Done);
        w.Execute = false, w.call();
        w.ParameterNumber = 0x6084, w.Value = 20000, w.Execute = true; // 20000 / 20000: a 1 s ramp
        w.call();
        ASSERT_TRUE(w.Done);
        MC_MoveVelocity& v = b.mc.blocks(0).move_vel;
        v.Velocity = 20000, v.Acceleration = v.Deceleration = 200000;
        v.Execute = true;
        b.cycles(150);
        v.Execute = false;
        ASSERT_EQ(b.mc.command("SV", "0").bch, 0x00); // the controller's MC_Power.Enable falls
        b.cycles(1);
        EXPECT_TRUE(b.mc.drive(0).disabling());
        ASSERT_EQ(b.mc.command("SV", "1").bch, 0x00);
        for (int i = 0; i < 100; ++i) { // a tenth of the ramp: not powered yet
            b.cycles(1);
            EXPECT_FALSE(b.mc.axis(0).powered());
        }
        b.until([&] { return b.mc.axis(0).powered(); }, 2000);
        EXPECT_FALSE(b.mc.drive(0).disabling());
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
        MC_MoveRelative& m = b.mc.blocks(0).move_rel;
        const std::int64_t from = b.mc.drive(0).actual_position();
        m.Distance = 1000, m.Velocity = 10000, m.Acceleration = m.Deceleration = 100000;
        m.Execute = true;
        b.until([&] { return m.Done || m.Error; }, 1000);
        b.cycles(50);
        EXPECT_EQ(b.mc.drive(0).actual_position() - from, 1000);
    });
}

} // namespace
