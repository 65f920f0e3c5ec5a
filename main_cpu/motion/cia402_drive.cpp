// rcsim — CiA 402 servo drive model. See cia402_drive.h.
#include "main_cpu/motion/cia402_drive.h"

#include <cmath>
#include <stdexcept>

namespace rcsim::motion {

const char* to_string(Cia402State s) {
    switch (s) {
    case Cia402State::not_ready_to_switch_on: return "NOT_READY_TO_SWITCH_ON";
    case Cia402State::switch_on_disabled: return "SWITCH_ON_DISABLED";
    case Cia402State::ready_to_switch_on: return "READY_TO_SWITCH_ON";
    case Cia402State::switched_on: return "SWITCHED_ON";
    case Cia402State::operation_enabled: return "OPERATION_ENABLED";
    case Cia402State::quick_stop_active: return "QUICK_STOP_ACTIVE";
    case Cia402State::fault_reaction_active: return "FAULT_REACTION_ACTIVE";
    case Cia402State::fault: return "FAULT";
    }
    return "?";
}

Cia402Drive::Cia402Drive(const Config& c) : cfg_(c), init_left_(c.init_time_s) {
    last_transition_ = 0; // transition 0: power on -> Not ready to switch on
}

std::uint16_t Cia402Drive::statusword() const {
    // Bit patterns of the decoding table (mask 0x4F/0x6F); bit 9 remote is always set, bit 5
    // (quick stop, active low) is set except in Quick stop active, Not ready and the fault states,
    // bit 4 (voltage enabled) with the power stage on. Gives P3's 0x221/0x233/0x237.
    std::uint16_t s = sw::remote;
    switch (state_) {
    case Cia402State::not_ready_to_switch_on: break;
    case Cia402State::switch_on_disabled: s |= sw::switch_on_disabled | sw::quick_stop; break;
    case Cia402State::ready_to_switch_on: s |= sw::ready | sw::quick_stop; break;
    case Cia402State::switched_on: s |= sw::ready | sw::switched_on | sw::quick_stop | sw::voltage_enabled; break;
    case Cia402State::operation_enabled:
        s |= sw::ready | sw::switched_on | sw::operation_enabled | sw::quick_stop | sw::voltage_enabled;
        break;
    case Cia402State::quick_stop_active:
        s |= sw::ready | sw::switched_on | sw::operation_enabled | sw::voltage_enabled;
        break;
    case Cia402State::fault_reaction_active:
        s |= sw::ready | sw::switched_on | sw::operation_enabled | sw::fault | sw::voltage_enabled;
        break;
    case Cia402State::fault: s |= sw::fault; break;
    }
    if (state_ == Cia402State::operation_enabled) {
        if (target_reached_) s |= sw::target_reached;
        if (mode_display_ == mode::pp && set_point_ack_) s |= sw::set_point_ack;
    }
    return s;
}

void Cia402Drive::enter(Cia402State s, int transition) {
    const bool was_enabled = state_ == Cia402State::operation_enabled;
    if (s != Cia402State::operation_enabled) disabling_ = false;
    state_ = s;
    last_transition_ = transition;
    if (s == Cia402State::operation_enabled && !was_enabled) {
        // Enabling: hold where the motor is. CSP/PP targets start at the actual position, or the
        // first cycle would jump to a stale 0x607A (SOEM #415).
        ref_ = motor_ = static_cast<double>(actual_);
        cmd_vel_ = 0;
        if (mode_display_ == mode::csp || mode_display_ == mode::pp)
            target_position = static_cast<std::int32_t>(actual_);
        pp_active_ = false;
        target_reached_ = true;
        // Pulse train: the deviation counter was cleared with the power stage off, so the pulses
        // counted meanwhile (a stop ramp, a move the drive did not follow) move nothing now.
        pulse_zero_ = static_cast<std::int64_t>(actual_) - pulse_in_;
    }
}

void Cia402Drive::set_controlword(std::uint16_t v) {
    const bool reset_edge = (v & cw::fault_reset) && !(cw_ & cw::fault_reset);
    const bool new_sp_edge = (v & cw::new_set_point) && !(cw_ & cw::new_set_point);
    cw_ = v;
    // Commands by their masks (docs/motion.md "Sources"); bit 7 is in every mask, so a
    // controlword holding a fault reset is no other command.
    const bool shutdown = (v & 0x87) == 0x06;
    const bool switch_on = (v & 0x8F) == 0x07;
    const bool enable_op = (v & 0x8F) == 0x0F;
    const bool disable_voltage = (v & 0x82) == 0x00;
    const bool quick_stop = (v & 0x86) == 0x02;
    using S = Cia402State;
    switch (state_) {
    case S::switch_on_disabled:
        if (shutdown) enter(S::ready_to_switch_on, 2);
        break;
    case S::ready_to_switch_on:
        if (switch_on) enter(S::switched_on, 3);
        else if (enable_op) { // 3+4 in one command (ETG.6010)
            enter(S::switched_on, 3);
            if (svon_) enter(S::operation_enabled, 4);
        } else if (disable_voltage || quick_stop) enter(S::switch_on_disabled, 7);
        break;
    case S::switched_on:
        if (enable_op && svon_) enter(S::operation_enabled, 4);
        else if (shutdown) enter(S::ready_to_switch_on, 6);
        else if (disable_voltage || quick_stop) enter(S::switch_on_disabled, 10);
        break;
    case S::operation_enabled:
        if (disabling_) { // a disable operation ramp: only disable voltage and quick stop cut it short
            if (disable_voltage) enter(S::switch_on_disabled, 9);
            else if (quick_stop) enter(S::quick_stop_active, 11);
        } else if (switch_on) disable_operation();
        else if (shutdown) enter(S::ready_to_switch_on, 8);
        else if (disable_voltage) enter(S::switch_on_disabled, 9);
        else if (quick_stop) enter(S::quick_stop_active, 11);
        else if (new_sp_edge && mode_display_ == mode::pp) start_pp();
        break;
    case S::quick_stop_active:
        if (disable_voltage) enter(S::switch_on_disabled, 12);
        else if (enable_op && cfg_.quick_stop_option >= 5 && cfg_.quick_stop_option <= 8)
            enter(S::operation_enabled, 16);
        break;
    case S::fault:
        if (reset_edge) fault_reset_edge();
        break;
    default: break; // Not ready and Fault reaction active only change automatically
    }
    if (!(v & cw::new_set_point)) set_point_ack_ = false; // PP handshake: ack follows bit 4 down
}

void Cia402Drive::fault_reset_edge() {
    if (state_ == Cia402State::fault && !fault_cause_) {
        error_code_ = 0;
        enter(Cia402State::switch_on_disabled, 15);
    }
}

void Cia402Drive::set_mode(std::int8_t m) {
    switch (m) {
    case mode::pulse_train: case mode::pp: case mode::pv: case mode::pt:
    case mode::csp: case mode::csv: case mode::cst: mode_ = m; break;
    default: throw std::invalid_argument("CiA402: mode of operation " + std::to_string(int{m}) + " is not supported");
    }
}

void Cia402Drive::set_servo_on_input(bool on) {
    svon_ = on;
    if (!on && state_ == Cia402State::operation_enabled && !disabling_) disable_operation();
}

void Cia402Drive::disable_operation() {
    if (cfg_.disable_operation_option == 1 && cmd_vel_ != 0) disabling_ = true;
    else enter(Cia402State::switched_on, 5);
}

bool Cia402Drive::write_object(std::uint16_t index, double value) {
    const auto in = [value](double lo, double hi) { return value >= lo && value <= hi && value == std::floor(value); };
    switch (index) {
    case 0x605A: if (!in(0, 8)) return false; cfg_.quick_stop_option = static_cast<std::int16_t>(value); return true;
    case 0x605C: if (!in(0, 1)) return false; cfg_.disable_operation_option = static_cast<std::int16_t>(value); return true;
    case 0x605E: if (!in(0, 4)) return false; cfg_.fault_reaction_option = static_cast<std::int16_t>(value); return true;
    case 0x6084: if (!in(1, 4294967295.0)) return false; profile_decel = static_cast<std::uint32_t>(value); return true;
    case 0x6085: if (!in(1, 4294967295.0)) return false; cfg_.quick_stop_decel = value; return true;
    default: return false;
    }
}

bool Cia402Drive::read_object(std::uint16_t index, double& value) const {
    switch (index) {
    case 0x605A: value = cfg_.quick_stop_option; return true;
    case 0x605C: value = cfg_.disable_operation_option; return true;
    case 0x605E: value = cfg_.fault_reaction_option; return true;
    case 0x6084: value = profile_decel; return true;
    case 0x6085: value = cfg_.quick_stop_decel; return true;
    default: return false;
    }
}

void Cia402Drive::set_alarm_reset_input(bool on) {
    if (on && !almrst_) fault_reset_edge();
    almrst_ = on;
}

void Cia402Drive::inject_fault(std::uint16_t code) {
    fault_cause_ = true;
    error_code_ = code;
    if (state_ != Cia402State::fault && state_ != Cia402State::fault_reaction_active)
        enter(Cia402State::fault_reaction_active, 13);
}

void Cia402Drive::start_pp() {
    const double from = ref_;
    const double to = (cw_ & cw::relative) ? from + target_position : static_cast<double>(target_position);
    camc::ProfileParams p;
    p.start_speed = 0;
    p.object_speed = profile_velocity;
    p.accel = profile_accel;
    p.decel = profile_decel;
    pp_profile_ = camc::SpeedProfile::preset(p, std::abs(to - from));
    pp_from_ = from;
    pp_dir_ = to < from ? -1 : 1;
    pp_dist_ = std::abs(to - from);
    pp_t_ = 0;
    pp_active_ = true;
    set_point_ack_ = true;
    target_reached_ = false;
}

void Cia402Drive::step_reference(double dt) {
    const double before = ref_;
    switch (mode_display_) {
    case mode::pulse_train: ref_ = static_cast<double>(pulse_in_ + pulse_zero_); break;
    case mode::csp: ref_ = target_position; break;
    case mode::pp:
        if (pp_active_) {
            pp_t_ += dt;
            const bool done = pp_t_ >= pp_profile_.end_time();
            ref_ = pp_from_ + pp_dir_ * (done ? pp_dist_ : pp_profile_.position(pp_t_));
            if (done) {
                pp_active_ = false;
                target_reached_ = true;
            }
        }
        break;
    case mode::pv: {
        // Ramp the commanded speed toward 0x60FF at 0x6083/0x6084; bit 10 = speed reached.
        const double want = target_velocity;
        const double rate = std::abs(want) > std::abs(cmd_vel_) ? profile_accel : profile_decel;
        const double dv = want - cmd_vel_;
        cmd_vel_ += std::abs(dv) <= rate * dt ? dv : (dv > 0 ? rate * dt : -rate * dt);
        ref_ += cmd_vel_ * dt;
        target_reached_ = cmd_vel_ == want;
        break;
    }
    case mode::csv: ref_ += target_velocity * dt; break;
    case mode::pt: {
        const double dq = target_torque - torque_, step = torque_slope * dt;
        torque_ = static_cast<std::int16_t>(std::lround(std::abs(dq) <= step ? target_torque
                                                                             : torque_ + (dq > 0 ? step : -step)));
        target_reached_ = torque_ == target_torque;
        break;
    }
    case mode::cst: torque_ = target_torque; break;
    default: break;
    }
    if (dt > 0 && mode_display_ != mode::pv) cmd_vel_ = (ref_ - before) / dt;
}

void Cia402Drive::stop_ramp(int opt, double dt) {
    // Option 0 disables the drive function: the motor coasts, which stops it at once here (no load
    // inertia is modelled); 1 and 5 ramp at the slow-down ramp, every other one at the quick stop ramp.
    const double rate = opt == 0 ? INFINITY : (opt == 1 || opt == 5) ? double(profile_decel) : cfg_.quick_stop_decel;
    const double dv = std::min(std::abs(cmd_vel_), rate * dt);
    cmd_vel_ -= cmd_vel_ > 0 ? dv : -dv;
}

void Cia402Drive::update(double dt) {
    using S = Cia402State;
    if (state_ == S::not_ready_to_switch_on) {
        init_left_ -= dt;
        if (init_left_ <= 0) enter(S::switch_on_disabled, 1);
    }
    mode_display_ = mode_; // the mode switch completes within one drive cycle
    const double prev_motor = motor_;
    if (state_ == S::operation_enabled && disabling_) {
        // 0x605C = 1: the reference ramps down on its own (the pulse input is no longer followed),
        // the position loop stays closed; transition 5 at rest, then any command given meanwhile.
        stop_ramp(1, dt);
        ref_ += cmd_vel_ * dt;
        if (cmd_vel_ == 0) {
            disabling_ = false;
            enter(S::switched_on, 5);
            set_controlword(cw_);
        }
    } else if (state_ == S::operation_enabled) {
        step_reference(dt);
    } else if (state_ == S::quick_stop_active || state_ == S::fault_reaction_active) {
        // The option code's ramp from the speed the motor had.
        stop_ramp(state_ == S::quick_stop_active ? cfg_.quick_stop_option : cfg_.fault_reaction_option, dt);
        ref_ = motor_ + cmd_vel_ * dt;
        if (cmd_vel_ == 0) {
            ref_ = motor_;
            if (state_ == S::fault_reaction_active) enter(S::fault, 14);
            else if (cfg_.quick_stop_option <= 4) enter(S::switch_on_disabled, 12);
        }
    } else {
        ref_ = motor_; // power stage off or brake on: the reference holds the motor
        cmd_vel_ = 0;
    }
    // Position loop: first-order lag toward the reference.
    if (cfg_.following_lag_s <= 0 || state_ != S::operation_enabled)
        motor_ = ref_;
    else
        motor_ += (ref_ - motor_) * (1 - std::exp(-dt / cfg_.following_lag_s));
    if (std::abs(ref_ - motor_) < 0.5) motor_ = ref_; // within the encoder's resolution
    vel_ = dt > 0 ? (motor_ - prev_motor) / dt : 0;
    actual_ = std::llround(motor_);
}

} // namespace rcsim::motion
