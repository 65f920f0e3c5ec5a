// CiA402 drive model: the full transition table, statusword values, fault reset edge, modes,
// CSP enable without a jump, quick stop options, fault reaction.
#include "main_cpu/motion/cia402_drive.h"
#include "tests/support/sc_test.h"

#include <cmath>

using namespace rcsim::motion;
using S = Cia402State;

namespace {

Cia402Drive booted(Cia402Drive::Config c = {}) {
    Cia402Drive d(c);
    d.update(0.002); // transition 1 after the self test
    return d;
}

void go(Cia402Drive& d, S target) {
    // Walks the normal path to `target`.
    if (target == S::switch_on_disabled) return;
    d.set_controlword(0x06);
    if (target == S::ready_to_switch_on) return;
    d.set_controlword(0x07);
    if (target == S::switched_on) return;
    d.set_controlword(0x0F);
    if (target == S::operation_enabled) return;
    d.set_controlword(0x02); // quick stop
}

struct Row {
    S from;
    std::uint16_t cw;
    S to;
    int transition;
};

TEST(Cia402, TransitionTable) {
    const Row rows[] = {
        {S::switch_on_disabled, 0x06, S::ready_to_switch_on, 2},
        {S::ready_to_switch_on, 0x07, S::switched_on, 3},
        {S::switched_on, 0x0F, S::operation_enabled, 4},
        {S::operation_enabled, 0x07, S::switched_on, 5},
        {S::switched_on, 0x06, S::ready_to_switch_on, 6},
        {S::ready_to_switch_on, 0x00, S::switch_on_disabled, 7},
        {S::ready_to_switch_on, 0x02, S::switch_on_disabled, 7},
        {S::operation_enabled, 0x06, S::ready_to_switch_on, 8},
        {S::operation_enabled, 0x00, S::switch_on_disabled, 9},
        {S::switched_on, 0x00, S::switch_on_disabled, 10},
        {S::switched_on, 0x02, S::switch_on_disabled, 10},
        {S::operation_enabled, 0x02, S::quick_stop_active, 11},
        {S::quick_stop_active, 0x00, S::switch_on_disabled, 12},
        {S::ready_to_switch_on, 0x0F, S::operation_enabled, 4}, // 3+4 in one command
        // Invalid commands keep the state.
        {S::switch_on_disabled, 0x07, S::switch_on_disabled, 1},
        {S::switch_on_disabled, 0x0F, S::switch_on_disabled, 1},
        {S::ready_to_switch_on, 0x06, S::ready_to_switch_on, 2},
    };
    for (const Row& r : rows) {
        Cia402Drive d = booted();
        go(d, r.from);
        ASSERT_EQ(d.state(), r.from) << to_string(r.from);
        d.set_controlword(r.cw);
        EXPECT_EQ(d.state(), r.to) << to_string(r.from) << " cw 0x" << std::hex << r.cw;
        EXPECT_EQ(d.last_transition(), r.transition) << to_string(r.from) << " cw 0x" << std::hex << r.cw;
    }
}

TEST(Cia402, PowerOnSelfTestAndIndy7Statuswords) {
    Cia402Drive d({0.002, 2, 2, 1e6, 0.003});
    EXPECT_EQ(d.state(), S::not_ready_to_switch_on);
    EXPECT_EQ(d.last_transition(), 0);
    EXPECT_EQ(d.statusword() & 0x4F, 0x00);
    d.update(0.001);
    EXPECT_EQ(d.state(), S::not_ready_to_switch_on);
    d.update(0.002);
    EXPECT_EQ(d.state(), S::switch_on_disabled);
    EXPECT_EQ(d.last_transition(), 1);
    EXPECT_EQ(d.statusword() & 0x4F, 0x40);
    // P3's Neuromeka Indy7 sequence (docs/system.md §8).
    d.set_controlword(0x06);
    EXPECT_EQ(d.statusword(), 0x221);
    d.set_controlword(0x07);
    EXPECT_EQ(d.statusword(), 0x233);
    d.set_controlword(0x0F);
    EXPECT_EQ(d.statusword() & ~0x0400, 0x237); // bit 10 target reached may be set
    d.set_controlword(0x02);
    EXPECT_EQ(d.statusword() & 0x6F, 0x07); // quick stop active decodes by mask 0x6F
}

TEST(Cia402, FaultReactionFaultAndResetNeedsAnEdge) {
    Cia402Drive d = booted();
    go(d, S::operation_enabled);
    d.inject_fault(0x7580);
    EXPECT_EQ(d.state(), S::fault_reaction_active);
    EXPECT_EQ(d.last_transition(), 13);
    EXPECT_EQ(d.statusword() & 0x4F, 0x0F);
    EXPECT_TRUE(d.alarm_output());
    d.update(0.001);
    EXPECT_EQ(d.state(), S::fault);
    EXPECT_EQ(d.last_transition(), 14);
    EXPECT_EQ(d.statusword() & 0x4F, 0x08);
    EXPECT_EQ(d.error_code(), 0x7580);
    // The cause is still there: a reset edge does nothing.
    d.set_controlword(0x80);
    EXPECT_EQ(d.state(), S::fault);
    d.clear_fault_cause();
    // Controlword held at 0x80 (ICube #76): no edge, no reset.
    d.set_controlword(0x80);
    EXPECT_EQ(d.state(), S::fault);
    d.set_controlword(0x00);
    d.set_controlword(0x80);
    EXPECT_EQ(d.state(), S::switch_on_disabled);
    EXPECT_EQ(d.last_transition(), 15);
    EXPECT_EQ(d.error_code(), 0);
    // The ALMRST input's rising edge resets as well.
    d.inject_fault(1);
    d.update(0.001);
    d.clear_fault_cause();
    d.set_alarm_reset_input(true);
    EXPECT_EQ(d.state(), S::switch_on_disabled);
}

TEST(Cia402, QuickStopOptionsAndTransition16) {
    Cia402Drive::Config c;
    c.quick_stop_option = 2; // ramp, then Switch on disabled (transition 12)
    Cia402Drive d = booted(c);
    d.set_mode(mode::csv);
    go(d, S::operation_enabled);
    d.target_velocity = 10000;
    d.update(0.01);
    d.set_controlword(0x02);
    EXPECT_EQ(d.state(), S::quick_stop_active);
    d.update(0.005); // 10000 pulses/s at 1e6 /s^2: 10 ms
    EXPECT_EQ(d.state(), S::quick_stop_active);
    d.update(0.006);
    EXPECT_EQ(d.state(), S::switch_on_disabled);
    EXPECT_EQ(d.last_transition(), 12);

    c.quick_stop_option = 6; // ramp, stay in Quick stop active; 0x0F returns (transition 16)
    Cia402Drive e = booted(c);
    go(e, S::operation_enabled);
    e.set_controlword(0x02);
    e.update(0.1);
    EXPECT_EQ(e.state(), S::quick_stop_active);
    e.set_controlword(0x0F);
    EXPECT_EQ(e.state(), S::operation_enabled);
    EXPECT_EQ(e.last_transition(), 16);
}

TEST(Cia402, CspEnableCopiesActualPositionToTargetNoJump) {
    Cia402Drive d = booted(Cia402Drive::Config{0, 2, 2, 1e6, 0.001});
    d.set_mode(mode::pulse_train);
    go(d, S::operation_enabled);
    d.set_pulse_input(5000);
    d.update(0.001);
    EXPECT_EQ(d.actual_position(), 5000);
    d.set_controlword(0x07); // disable operation, switch to CSP with a stale target of 0
    d.set_mode(mode::csp);
    d.target_position = 0;
    d.update(0.001);
    EXPECT_EQ(d.mode_display(), mode::csp);
    d.set_controlword(0x0F);
    EXPECT_EQ(d.target_position, 5000);
    d.update(0.001);
    EXPECT_EQ(d.actual_position(), 5000); // no jump to 0
    d.target_position = 5100;
    d.update(0.001);
    EXPECT_EQ(d.actual_position(), 5100);
}

TEST(Cia402, ModesFollowTheirTargetObjects) {
    // PP: a set-point edge starts a move; bit 12 acknowledges, bit 10 on arrival.
    Cia402Drive d = booted(Cia402Drive::Config{0, 2, 2, 1e6, 0.001});
    d.set_mode(mode::pp);
    d.update(0.001);
    go(d, S::operation_enabled);
    d.target_position = 1000;
    d.profile_velocity = 10000;
    d.set_controlword(0x1F);
    EXPECT_TRUE(d.statusword() & sw::set_point_ack);
    EXPECT_FALSE(d.statusword() & sw::target_reached);
    d.set_controlword(0x0F);
    EXPECT_FALSE(d.statusword() & sw::set_point_ack);
    for (int i = 0; i < 300; ++i) d.update(0.001);
    EXPECT_EQ(d.actual_position(), 1000);
    EXPECT_TRUE(d.statusword() & sw::target_reached);
    // PV: speed ramps to 0x60FF; CSV integrates; PT/CST set the torque.
    d.set_mode(mode::pv);
    d.target_velocity = 2000;
    for (int i = 0; i < 100; ++i) d.update(0.001);
    EXPECT_NEAR(d.actual_velocity(), 2000, 1e-6);
    EXPECT_TRUE(d.statusword() & sw::target_reached);
    d.set_mode(mode::cst);
    d.target_torque = 300;
    d.update(0.001);
    EXPECT_EQ(d.actual_torque(), 300);
    d.set_mode(mode::pt);
    d.target_torque = 500;
    d.update(0.1); // slope 1000 per mille/s
    EXPECT_EQ(d.actual_torque(), 400);
    EXPECT_THROW(d.set_mode(7), std::invalid_argument);
}

TEST(Cia402, PulseModeFollowsWithConfigurableLag) {
    Cia402Drive d = booted(Cia402Drive::Config{0.002, 2, 2, 1e6, 0.001});
    go(d, S::operation_enabled);
    // A ramp of 10 pulses per ms through the sampled first-order lag: the steady following error
    // is v*dt*(1/(1-exp(-dt/tau)) - 1) = 15.4 pulses (v*tau = 20 in continuous time).
    std::int64_t cmd = 0;
    for (int i = 0; i < 100; ++i) {
        cmd += 10;
        d.set_pulse_input(cmd);
        d.update(0.001);
    }
    EXPECT_NEAR(static_cast<double>(cmd - d.actual_position()), 10 * (1 / (1 - std::exp(-0.5)) - 1), 1.0);
    for (int i = 0; i < 50; ++i) d.update(0.001);
    EXPECT_EQ(d.actual_position(), cmd); // settles exactly
    // SVON low disables operation (transition 5).
    d.set_servo_on_input(false);
    EXPECT_EQ(d.state(), S::switched_on);
    EXPECT_EQ(d.last_transition(), 5);
    d.set_controlword(0x0F);
    EXPECT_EQ(d.state(), S::switched_on); // refused without SVON
}

} // namespace
