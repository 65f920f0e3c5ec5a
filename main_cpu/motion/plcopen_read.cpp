// rcsim — PLCopen Part 1's Enable-type reads of an axis (MC_ReadStatus, MC_ReadActualPosition,
// MC_ReadAxisError, MC_ReadParameter) and MC_SetPosition. See plcopen.h.
#include "main_cpu/motion/plcopen.h"

namespace rcsim::motion {

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
    switch (ParameterNumber) {
    case 1: Value = static_cast<double>(Axis->api().CmdPos(ax)); return 0;
    case 8: Value = camc::CamcQi::max_pps; return 0;
    case 10: Value = Axis->drive().actual_velocity(); return 0;
    case 11: Value = Axis->api().CurrentSpeed(ax); return 0;
    default: return err::parameter_unsupported;
    }
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
