// rcsim — an axis state's name and PLCopen Part 1's Enable-type reads of an axis (MC_ReadStatus,
// MC_ReadActualPosition, MC_ReadAxisError, MC_ReadParameter), MC_WriteParameter and MC_SetPosition.
// See plcopen.h.
#include "main_cpu/motion/plcopen.h"

#include <cmath>

namespace rcsim::motion {

const char* to_string(AxisState s) {
    switch (s) {
    case AxisState::disabled: return "DISABLED";
    case AxisState::standstill: return "STANDSTILL";
    case AxisState::homing: return "HOMING";
    case AxisState::discrete_motion: return "DISCRETE_MOTION";
    case AxisState::continuous_motion: return "CONTINUOUS_MOTION";
    case AxisState::synchronized_motion: return "SYNCHRONIZED_MOTION";
    case AxisState::stopping: return "STOPPING";
    case AxisState::error_stop: return "ERRORSTOP";
    }
    return "?";
}

void McEnableFb::call() {
    Busy = Enable;
    if (!Enable) {
        Valid = Error = false;
        ErrorID = 0;
        clear();
        return;
    }
    const std::uint16_t e = Axis ? read() : err::invalid_axis;
    Valid = e == 0;
    Error = e != 0;
    ErrorID = e;
    if (e) clear();
}

std::uint16_t MC_ReadStatus::read() {
    const AxisState s = Axis->state();
    ErrorStop = s == AxisState::error_stop;
    Disabled = s == AxisState::disabled;
    Stopping = s == AxisState::stopping;
    Homing = s == AxisState::homing;
    Standstill = s == AxisState::standstill;
    DiscreteMotion = s == AxisState::discrete_motion;
    ContinuousMotion = s == AxisState::continuous_motion;
    SynchronizedMotion = s == AxisState::synchronized_motion;
    return 0;
}

void MC_ReadStatus::clear() {
    ErrorStop = Disabled = Stopping = Homing = Standstill = false;
    DiscreteMotion = ContinuousMotion = SynchronizedMotion = false;
}

std::uint16_t MC_ReadActualPosition::read() {
    Position = static_cast<double>(Axis->api().ActPos(static_cast<int>(Axis->index())));
    return 0;
}

std::uint16_t MC_ReadAxisError::read() {
    AxisErrorID = Axis->error_id();
    return 0;
}

std::uint16_t MC_ReadParameter::read() {
    const int ax = static_cast<int>(Axis->index());
    const AxisLimits& l = Axis->limits();
    switch (ParameterNumber) {
    case par::commanded_position: Value = static_cast<double>(Axis->api().CmdPos(ax)); return 0;
    case par::sw_limit_pos: Value = l.sw_limit_pos; return 0;
    case par::sw_limit_neg: Value = l.sw_limit_neg; return 0;
    case par::enable_limit_pos: Value = l.enable_limit_pos; return 0;
    case par::enable_limit_neg: Value = l.enable_limit_neg; return 0;
    case par::enable_pos_lag_monitoring: Value = l.enable_pos_lag_monitoring; return 0;
    case par::max_position_lag: Value = l.max_position_lag; return 0;
    case par::max_velocity_system: Value = camc::CamcQi::max_pps; return 0;
    case par::max_velocity_appl: Value = l.max_velocity_appl > 0 ? l.max_velocity_appl : camc::CamcQi::max_pps; return 0;
    case par::actual_velocity: Value = Axis->drive().actual_velocity(); return 0;
    case par::commanded_velocity: Value = Axis->api().CurrentSpeed(ax); return 0;
    case par::max_acceleration_appl: Value = l.max_acceleration_appl; return 0;
    case par::max_deceleration_appl: Value = l.max_deceleration_appl; return 0;
    default:
        if (ParameterNumber >= 0 && ParameterNumber <= 0xFFFF &&
            Axis->drive().read_object(static_cast<std::uint16_t>(ParameterNumber), Value))
            return 0;
        return err::parameter_unsupported;
    }
}

std::uint16_t MC_WriteParameter::begin() {
    if (!Axis) return err::invalid_axis;
    AxisLimits& l = Axis->limits();
    const double v = Value;
    const bool is_bool = v == 0 || v == 1;
    const bool in_range = std::isfinite(v) && std::abs(v) <= camc::max_coordinate;
    const bool positive = std::isfinite(v) && v > 0;
    switch (ParameterNumber) {
    case par::commanded_position: case par::max_velocity_system: case par::actual_velocity:
    case par::commanded_velocity: return err::parameter_read_only;
    case par::sw_limit_pos: if (!in_range) return err::parameter_value; l.sw_limit_pos = v; break;
    case par::sw_limit_neg: if (!in_range) return err::parameter_value; l.sw_limit_neg = v; break;
    case par::enable_limit_pos: if (!is_bool) return err::parameter_value; l.enable_limit_pos = v != 0; break;
    case par::enable_limit_neg: if (!is_bool) return err::parameter_value; l.enable_limit_neg = v != 0; break;
    case par::enable_pos_lag_monitoring:
        if (!is_bool) return err::parameter_value;
        l.enable_pos_lag_monitoring = v != 0;
        break;
    case par::max_position_lag: if (!positive) return err::parameter_value; l.max_position_lag = v; break;
    case par::max_velocity_appl:
        if (!positive || v > camc::CamcQi::max_pps) return err::parameter_value;
        l.max_velocity_appl = v;
        break;
    case par::max_acceleration_appl: if (!positive) return err::parameter_value; l.max_acceleration_appl = v; break;
    case par::max_deceleration_appl: if (!positive) return err::parameter_value; l.max_deceleration_appl = v; break;
    default: {
        double old = 0;
        if (ParameterNumber < 0 || ParameterNumber > 0xFFFF ||
            !Axis->drive().read_object(static_cast<std::uint16_t>(ParameterNumber), old))
            return err::parameter_unsupported;
        if (!Axis->drive().write_object(static_cast<std::uint16_t>(ParameterNumber), v)) return err::parameter_value;
    }
    }
    job_ = std::make_shared<Job>();
    job_->status = Job::Status::done; // the block's own job: written at once
    return 0;
}

std::uint16_t MC_SetPosition::begin() {
    if (!Axis) return err::invalid_axis;
    const AxisState s = Axis->state();
    if (s == AxisState::error_stop) return err::axis_error_stop;
    if (s == AxisState::disabled) return err::axis_disabled;
    const int ax = static_cast<int>(Axis->index());
    if (s != AxisState::standstill || Axis->api().InMotion(ax)) return err::wrong_state;
    const std::int64_t target = Relative ? Axis->api().CmdPos(ax) + Position : std::int64_t{Position};
    if (target < -camc::max_coordinate || target > camc::max_coordinate) return err::position_out_of_bound;
    Axis->api().SetPos(ax, target);
    job_ = std::make_shared<Job>();
    job_->status = Job::Status::done; // the block's own job: the counters are set at once
    return 0;
}

} // namespace rcsim::motion
