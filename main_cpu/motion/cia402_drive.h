// rcsim — CiA 402 servo drive model (IEC 61800-7-201 device profile, docs/motion.md "CiA402
// drive" and "Sources", and the CiA402 article P3 of docs/system.md §1: controlword 0x6040, statusword
// 0x6041, eight states, transitions 0-16, modes 0x6060/0x6061).
//
// Plain C++ (no SystemC): the controller writes the controlword and objects and calls update()
// once per drive cycle with the elapsed time; everything is deterministic.
//
// Position reference per mode: -1 (manufacturer "pulse train", our default for the CAMC-QI
// plotter) follows the pulse input; 8 CSP follows 0x607A; 1 PP runs a trapezoid to 0x607A on a
// new set-point; 3 PV / 9 CSV integrate a velocity; 4 PT / 10 CST set the torque (no load model:
// the position holds). The motor follows the reference through a first-order lag (time constant
// = the configurable following lag), so the following error is about speed * lag. In pulse-train
// mode the drive's deviation counter is cleared while the power stage is off (as a pulse-train
// servo amplifier clears it at servo off): enabling never moves the motor.
#pragma once

#include "camc_qi/profile.h"

#include <cstdint>
#include <string>

namespace rcsim::motion {

enum class Cia402State : std::uint8_t {
    not_ready_to_switch_on, switch_on_disabled, ready_to_switch_on, switched_on,
    operation_enabled, quick_stop_active, fault_reaction_active, fault,
};
const char* to_string(Cia402State s);

namespace cw { // controlword bits and commands
constexpr std::uint16_t switch_on = 1u << 0, enable_voltage = 1u << 1, quick_stop = 1u << 2;
constexpr std::uint16_t enable_operation = 1u << 3, new_set_point = 1u << 4, relative = 1u << 6;
constexpr std::uint16_t fault_reset = 1u << 7, halt = 1u << 8;
constexpr std::uint16_t shutdown = 0x06, switch_on_cmd = 0x07, enable_operation_cmd = 0x0F;
constexpr std::uint16_t disable_voltage = 0x00, quick_stop_cmd = 0x02;
} // namespace cw

namespace sw { // statusword bits
constexpr std::uint16_t ready = 1u << 0, switched_on = 1u << 1, operation_enabled = 1u << 2;
constexpr std::uint16_t fault = 1u << 3, voltage_enabled = 1u << 4, quick_stop = 1u << 5;
constexpr std::uint16_t switch_on_disabled = 1u << 6, warning = 1u << 7, remote = 1u << 9;
constexpr std::uint16_t target_reached = 1u << 10, set_point_ack = 1u << 12;
} // namespace sw

namespace mode {
constexpr std::int8_t pulse_train = -1, pp = 1, pv = 3, pt = 4, csp = 8, csv = 9, cst = 10;
} // namespace mode

class Cia402Drive {
public:
    struct Config {
        double following_lag_s = 0.002;   // first-order time constant of the position loop
        // Option codes: 0 disables the drive function (no load inertia is modelled: the motor stops
        // at once); 1 (and 5) ramp at the slow-down ramp 0x6084, 2 (and 6) at the quick stop ramp
        // 0x6085; 3, 4, 7, 8 (current / voltage limit) at 0x6085 too (no torque model). 0x605A 1-4 go
        // on to Switch on disabled, 5-8 stay in Quick stop active.
        std::int16_t quick_stop_option = 2;   // 0x605A, 0..8
        std::int16_t fault_reaction_option = 2; // 0x605E, 0..4
        double quick_stop_decel = 1e6;    // 0x6085, pulses/s^2
        double init_time_s = 0.001;       // transition 1 (self test) takes this long
        // 0x605C: 0 disable the drive function at once (the default here: a pulse-train amplifier frees
        // the motor at servo off), 1 ramp at 0x6084 first, then transition 5 (CiA402's default).
        std::int16_t disable_operation_option = 0;
    };

    explicit Cia402Drive(const Config& c);
    Cia402Drive() : Cia402Drive(Config{}) {}

    // --- objects ---
    void set_controlword(std::uint16_t v);                 // 0x6040: evaluated at once
    std::uint16_t controlword() const { return cw_; }
    std::uint16_t statusword() const;                      // 0x6041
    Cia402State state() const { return state_; }
    /// The transition number (0-16) of the last state change; -1 before any.
    int last_transition() const { return last_transition_; }
    /// Operation enabled, but ramping down to disable it (0x605C = 1): the pulses are not followed.
    bool disabling() const { return disabling_; }
    /// 0x6060; the display 0x6061 follows on the next update() (switching takes one cycle).
    /// Throws std::invalid_argument for a mode the drive does not support.
    void set_mode(std::int8_t m);
    std::int8_t mode_display() const { return mode_display_; }   // 0x6061
    std::int32_t target_position = 0;                      // 0x607A
    std::int32_t target_velocity = 0;                      // 0x60FF
    std::int16_t target_torque = 0;                        // 0x6071, per mille
    std::uint32_t profile_velocity = 10000, profile_accel = 100000, profile_decel = 100000; // 0x6081/3/4
    std::uint32_t torque_slope = 1000;                     // 0x6087, per mille per second
    std::int64_t actual_position() const { return actual_; }   // 0x6064
    double actual_velocity() const { return vel_; }            // 0x606C
    std::int16_t actual_torque() const { return torque_; }     // 0x6077
    std::uint16_t error_code() const { return error_code_; }   // 0x603F
    /// SDO access to the option codes and ramps: 0x605A, 0x605C, 0x605E, 0x6084, 0x6085 (the
    /// PLC's MC_WriteParameter / MC_ReadParameter with the index as vendor number). write_object
    /// returns false for another index or a value outside the object's range; read_object false
    /// for another index.
    bool write_object(std::uint16_t index, double value);
    bool read_object(std::uint16_t index, double& value) const;

    // --- hardware side ---
    void set_pulse_input(std::int64_t pulses) { pulse_in_ = pulses; }
    /// SVON (CAMC-QI UIO0): without it the power stage cannot be enabled (transition 4 refused,
    /// and dropping it in Operation enabled disables operation, transition 5).
    void set_servo_on_input(bool on);
    /// ALMRST (CAMC-QI UIO1): a rising edge acts as a fault reset.
    void set_alarm_reset_input(bool on);
    /// ALM output to the CAMC-QI alarm input: asserted in Fault reaction active and Fault.
    bool alarm_output() const {
        return state_ == Cia402State::fault || state_ == Cia402State::fault_reaction_active;
    }
    /// An internal fault (e.g. overcurrent): transition 13; the cause stays until cleared.
    void inject_fault(std::uint16_t code);
    void clear_fault_cause() { fault_cause_ = false; }

    /// Advances the drive by dt seconds: automatic transitions, the reference, the motor.
    void update(double dt);

private:
    Config cfg_;
    Cia402State state_ = Cia402State::not_ready_to_switch_on;
    int last_transition_ = -1;
    std::uint16_t cw_ = 0, error_code_ = 0;
    std::int8_t mode_ = mode::pulse_train, mode_display_ = mode::pulse_train;
    bool svon_ = true, almrst_ = false, fault_cause_ = false;
    bool disabling_ = false; // Operation enabled, ramping down before transition 5 (0x605C = 1)
    double init_left_;
    std::int64_t pulse_in_ = 0, actual_ = 0;
    std::int64_t pulse_zero_ = 0; // pulse count of the motor's position when operation was enabled
    double ref_ = 0, motor_ = 0, vel_ = 0, cmd_vel_ = 0;
    std::int16_t torque_ = 0;
    // Profile position move in progress.
    bool pp_active_ = false, set_point_ack_ = false, target_reached_ = true;
    camc::SpeedProfile pp_profile_;
    double pp_t_ = 0, pp_from_ = 0, pp_dir_ = 1, pp_dist_ = 0;

    void enter(Cia402State s, int transition);
    void fault_reset_edge();
    void start_pp();
    void step_reference(double dt);
    /// Transition 5 by 0x605C: at once, or after a ramp at 0x6084 (disabling_).
    void disable_operation();
    /// The ramp of Quick stop active / Fault reaction active / disabling at option \p opt.
    void stop_ramp(int opt, double dt);
};

} // namespace rcsim::motion
