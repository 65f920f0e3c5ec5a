// rcsim — an axis' limits. See axis_limits.h.
#include "main_cpu/motion/axis_limits.h"

#include "main_cpu/motion/plcopen.h"

#include <cmath>

namespace rcsim::motion {

std::uint16_t check_dynamics(const AxisLimits& l, double vel, double acc, double dec) {
    if (l.max_velocity_appl > 0 && vel > l.max_velocity_appl) return err::velocity_above_limit;
    if (l.max_acceleration_appl > 0 && acc > l.max_acceleration_appl) return err::acceleration_above_limit;
    if (l.max_deceleration_appl > 0 && dec > l.max_deceleration_appl) return err::deceleration_above_limit;
    return 0;
}

std::uint16_t check_target(const AxisLimits& l, std::int64_t target) {
    if (l.enable_limit_pos && static_cast<double>(target) > l.sw_limit_pos) return err::sw_limit_positive;
    if (l.enable_limit_neg && static_cast<double>(target) < l.sw_limit_neg) return err::sw_limit_negative;
    return 0;
}

std::uint16_t check_relative_target(McAxis& axis, std::int64_t distance) {
    const int ax = static_cast<int>(axis.index());
    if (axis.api().InMotion(ax)) return 0;
    return check_target(axis.limits(), axis.api().CmdPos(ax) + distance);
}

bool McAxis::blame_partner() {
    if (!active_ || active_->axes.size() < 2) return false;
    for (McAxis* a : active_->axes)
        if (a != this && a->drive_.alarm_output() && a->state_ != AxisState::error_stop) {
            a->enter_error(err::drive_fault);
            return true;
        }
    return false;
}

std::uint16_t McAxis::monitor_limits() {
    if (!powered_ || state_ == AxisState::disabled || state_ == AxisState::error_stop) return 0;
    const AxisLimits& l = limits_;
    if (!l.enable_limit_pos && !l.enable_limit_neg && !l.enable_pos_lag_monitoring) return 0; // no bus reads
    const int ax = static_cast<int>(index_);
    const double cmd = static_cast<double>(api_.CmdPos(ax));
    if (api_.InMotion(ax)) {
        // A move the block could not check (MC_MoveVelocity, a group's path) stops when its command
        // passes the limit, as the chip stops at a limit switch: at once, one control cycle late at most.
        const bool negative = api_.DriveStatus(ax) & camc::drvst::negative;
        if (l.enable_limit_pos && !negative && cmd > l.sw_limit_pos) return err::sw_limit_positive;
        if (l.enable_limit_neg && negative && cmd < l.sw_limit_neg) return err::sw_limit_negative;
    }
    if (l.enable_pos_lag_monitoring && std::abs(cmd - static_cast<double>(api_.ActPos(ax))) > l.max_position_lag)
        return err::following_error;
    return 0;
}

} // namespace rcsim::motion
