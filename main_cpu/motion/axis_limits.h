// rcsim — an axis' limits as PLCopen Part 1 v2.0 §3.10/3.11 (MC_ReadParameter /
// MC_WriteParameter) numbers them: software limits, following-error monitoring and the
// application's velocity and rate limits (docs/motion.md "Limits").
//
// Plain data plus checks; McAxis owns one and consults it at the block (a refused command leaves
// the axis as it was) and every control cycle (a limit reached or a lag exceeded is an axis error).
#pragma once

#include <cstdint>

namespace rcsim::motion {

/// Part 1 v2.0 MC_ReadParameter table, the numbers this axis has (others: ErrorID 0x7006).
namespace par {
constexpr int commanded_position = 1, sw_limit_pos = 2, sw_limit_neg = 3, enable_limit_pos = 4;
constexpr int enable_limit_neg = 5, enable_pos_lag_monitoring = 6, max_position_lag = 7;
constexpr int max_velocity_system = 8, max_velocity_appl = 9, actual_velocity = 10;
constexpr int commanded_velocity = 11, max_acceleration_appl = 13, max_deceleration_appl = 15;
// Vendor numbers (Part 1: above 999 are the supplier's): the drive's CiA402 object, by its index.
constexpr int profile_deceleration = 0x6084, quick_stop_deceleration = 0x6085;
constexpr int quick_stop_option = 0x605A, disable_operation_option = 0x605C;
constexpr int fault_reaction_option = 0x605E;
} // namespace par

/// ErrorIDs of the limits (our own 0x7xxx range, docs/motion.md "Limits"). Block errors (the FB
/// reports them, the axis state is unchanged): a write to a read-only or an invalid value, a target
/// past an enabled software limit, a velocity or rate above the application's limit. Axis errors
/// (ErrorStop): a software limit reached while moving, the following error above MaxPositionLag.
/// GroupErrorStop: the error a group move (line, circle) ends with when one of its axes fails.
namespace err {
constexpr std::uint16_t parameter_read_only = 0x7010, parameter_value = 0x7011;
constexpr std::uint16_t sw_limit_positive = 0x7110, sw_limit_negative = 0x7111, following_error = 0x7112;
constexpr std::uint16_t velocity_above_limit = 0x7113, acceleration_above_limit = 0x7114;
constexpr std::uint16_t deceleration_above_limit = 0x7115;
constexpr std::uint16_t group_error_stop = 0x7116; // a group move ended by its partner's axis error (Part 4)
} // namespace err

struct AxisLimits {
    double sw_limit_pos = 0, sw_limit_neg = 0;       // pulses (command position)
    bool enable_limit_pos = false, enable_limit_neg = false;
    bool enable_pos_lag_monitoring = false;
    double max_position_lag = 0;                     // pulses, |CNT1 - CNT2|
    double max_velocity_appl = 0;                    // pulses/s; 0 = the system's (10 Mpps)
    double max_acceleration_appl = 0, max_deceleration_appl = 0; // pulses/s^2; 0 = no limit
};

/// The block's velocity and rates against MaxVelocityAppl / MaxAcceleration- / MaxDecelerationAppl
/// (0 = within them).
std::uint16_t check_dynamics(const AxisLimits& l, double vel, double acc, double dec);
/// A move's end point against the enabled software limits (0 = within them).
std::uint16_t check_target(const AxisLimits& l, std::int64_t target);

class McAxis;
/// A relative move of a standing axis: its end point against the limits. A moving axis' relative
/// end depends on where it stops; its start (or the cycle's monitor) checks it then.
std::uint16_t check_relative_target(McAxis& axis, std::int64_t distance);

} // namespace rcsim::motion
