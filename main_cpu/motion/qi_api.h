// rcsim — the C motion library of the motion-controller paper (P2, docs/system.md §1) on the
// CAMC-QI (its Table 1: SignalSetHomeLevel, SignalSetLimit, SignalServoOn, SignalServoAlarmReset,
// MovePos, LineMove) plus the circle-centre move of its MC_CircleCenterMove, the stops and the
// status reads the function blocks need.
//
// Every call is a sequence of CAMC-QI register accesses (write DATA, write COMMAND) through a
// QiBus; return values are AXL codes (0 = success). Names follow the paper (AXL style).
#pragma once

#include "camc_qi/camc_qi.h"

#include <array>
#include <cstdint>

namespace rcsim::motion {

/// The main CPU's path to the chip: one register command per call.
class QiBus {
public:
    virtual ~QiBus() = default;
    virtual void write(unsigned axis, std::uint8_t code, std::uint32_t data) = 0;
    virtual std::uint32_t read(unsigned axis, std::uint8_t code) = 0;
};

/// AXL return codes (AXHS.h AXT_FUNC_RESULT) used here.
namespace axl {
constexpr int success = 0;
constexpr int invalid_axis = 4101;
constexpr int invalid_velocity = 4113;
constexpr int invalid_accel = 4114;
constexpr int in_motion = 4152;
constexpr int sensor_check = 4169;  // alarm / limit / ESTOP active before the move
constexpr int interpolation_value = 4184;
constexpr int position_out_of_bound = 4251; // beyond the chip's +-(2^30 - 1) pulses
constexpr int profile_invalid = 4252;
constexpr int velocity_out_of_bound = 4253;
} // namespace axl

/// AXL home search results (AXHS.h AXT_MOTION_HOME_RESULT) used here.
namespace home {
constexpr unsigned success = 0x01, searching = 0x02;
constexpr unsigned err_amp_fault = 0x13, err_neg_limit = 0x14, err_pos_limit = 0x15, err_not_detect = 0x16;
} // namespace home

/// AXL's homing method and speeds (AxmHomeSetMethod / AxmHomeSetVel, defaults from AXM.h): search
/// the home switch at vel_first, back off it at vel_second, approach it again at vel_third and
/// stop on its edge; with zphase, then leave it at vel_last and stop on the encoder Z pulse.
struct HomeMethod {
    int dir = -1;        // search direction: -1 negative, +1 positive
    bool zphase = false;
    double vel_first = 10000, vel_second = 10000, vel_third = 2000, vel_last = 100;
    double acc_first = 40000, acc_second = 40000;
};

constexpr unsigned level_low = 0, level_high = 1, level_unused = 2;
constexpr unsigned stop_emergency = 0, stop_slowdown = 1;
constexpr int dir_ccw = 0, dir_cw = 1; // AXL DIR_CCW / DIR_CW

class QiMotionApi {
public:
    explicit QiMotionApi(QiBus& bus) : bus_(bus) {}

    int SignalSetHomeLevel(int AxisNo, unsigned Level);
    int SignalSetLimit(int AxisNo, unsigned StopMode, unsigned PositiveLevel, unsigned NegativeLevel);
    int SignalServoOn(long AxisNo, unsigned OnOff);
    int SignalServoAlarmReset(int AxisNo, unsigned OnOff);
    /// Starts a move to the absolute position Pos (returns when the pulses start, as
    /// AxmMoveStartPos). Units: pulses, pulses/s, pulses/s^2. Positions, distances and centres are
    /// 32-bit integers all the way to the chip's registers (the paper's `float` would lose pulses
    /// above 2^24); the chip's range is +-(2^30 - 1) (4251 beyond).
    int MovePos(int AxisNo, std::int32_t Pos, double Vel, double Accel, double Decel);
    /// Linear interpolation of the axes of coordinate system Coord (SetCoord), Pos[] relative to
    /// the current positions (the paper's MC_LineMove), one per axis of Coord in axis order; Vel
    /// is the vector speed.
    int LineMove(int Coord, const std::int32_t* Pos, double Vel, double Accel, double Decel);
    /// Circular interpolation on the two axes of Coord; centre and end relative to the current
    /// position; Dir = dir_cw / dir_ccw; writes QiISNUM from the octant formula (eqs. 1-10).
    int CircleCenterMove(int Coord, std::int32_t CenX, std::int32_t CenY, std::int32_t EndX, std::int32_t EndY,
                         double Vel, double Accel, double Decel, int Dir);
    /// Continuous drive (AxmMoveVel): Vel signed.
    int MoveVel(int AxisNo, double Vel, double Accel, double Decel);
    /// The library's homing sequence (AXL runs it in a thread; here HomeGetResult advances it,
    /// polled once per control cycle). Each step is one chip signal search that stops at the
    /// exact time of its edge; a step starts when the previous one has ended.
    int HomeSetMethod(int AxisNo, const HomeMethod& m);
    int HomeSetStart(int AxisNo);
    unsigned HomeGetResult(int AxisNo);
    /// Slow-down stop; Decel > 0 replaces the programmed deceleration for this stop (pulses/s^2
    /// along the path for an interpolation: it is written to the master axis, whose RATE2 the
    /// chip uses whichever member the stop is written to).
    int SlowStop(int AxisNo, double Decel);
    int EmergencyStop(int AxisNo);
    int EmergencyStopAll();

    /// AxmMotSetProfileMode: 0 symmetric trapezoid, 1 asymmetric trapezoid (the default here), 3
    /// symmetric S, 4 asymmetric S; 2 (quasi-S) is not modelled (4252).
    int SetProfileMode(int AxisNo, unsigned Mode);
    /// AxmMotSetAccelJerk: the share of a ramp spent in jerk sections, 0..100 % (SW1; a symmetric
    /// S uses it for both ramps). An asymmetric S decelerates with SW2 = 0 unless a Jerk is set.
    int SetAccelJerk(int AxisNo, double Percent);
    /// A jerk limit in pulses/s^3 for the next move only (the PLCopen blocks' Jerk input): an
    /// asymmetric S whose shares give that jerk on a ramp STD -> Vel, to the chip's whole percent
    /// (below rate^2/dv the rate is lowered so that a pure S has that jerk); 0 = the profile
    /// mode and shares above. A move that peaks below Vel ramps with the same shares, so its
    /// jerk is higher.
    int SetJerk(int AxisNo, double Jerk);

    /// Blending (PLCopen BufferMode 2-5; camc_qi/README.md "Blending"): the next MovePos,
    /// LineMove or CircleCenterMove on this axis (the master of a group) is queued behind the
    /// drive the same axes run now, which then ends at Vel (pulses/s along the path) instead of
    /// stopping, and the new move starts there at Vel. For the next move only; without a running
    /// drive the move starts as usual. MovePos then measures from the running move's target.
    int SetBlend(int AxisNo, double Vel);
    /// Take-over (PLCopen Aborting, camc_qi/README.md "Blending"): the next MovePos or MoveVel on
    /// this axis replaces the drive it runs now at once, from its current speed and the same way
    /// (the caller checks the direction and that the new target leaves room to stop).
    void SetTakeOver(int AxisNo, bool on = true) { take_over_[AxisNo & 3] = on; }
    bool BlendPending(int AxisNo) const { return blend_[AxisNo & 3] > 0; }
    /// A blended move waits behind the running drive (the chip's queue is not empty).
    bool BlendQueued(int AxisNo);
    /// Where the last MovePos of the axis ends (its blended successor starts there).
    std::int64_t TargetPos(int AxisNo) const { return target_[AxisNo & 3]; }

    int SetCoord(int Coord, std::uint32_t axis_mask);
    void SetStartSpeed(int AxisNo, double Vel) { start_speed_[AxisNo & 3] = Vel; }
    bool InMotion(int AxisNo);
    std::uint32_t DriveStatus(int AxisNo); // STAT2 (AxmStatusReadMotion)
    std::uint32_t EndStatus(int AxisNo);
    void ClearEndStatus(int AxisNo);
    std::int64_t CmdPos(int AxisNo);
    std::int64_t ActPos(int AxisNo);
    /// CURSPD: the speed of the drive the axis is in, pulses/s (0 at rest).
    double CurrentSpeed(int AxisNo);
    /// Shifts CNT1 to pos and CNT2 by the same amount (PLCopen MC_SetPosition: both by the same
    /// value, no motion): a following error in progress is kept, so when the motor has caught
    /// up, actual = command again.
    void SetPos(int AxisNo, std::int64_t pos);
    /// Presets CNT1 alone (no pulses: AxmStatusSetCmdPos).
    void SetCmdPos(int AxisNo, std::int64_t pos);

    static constexpr int coords = 4;

private:
    QiBus& bus_;
    std::array<std::uint32_t, coords> coord_{0x3, 0x3, 0xC, 0xF};
    std::array<double, 4> start_speed_{100, 100, 100, 100};
    std::array<std::uint32_t, 4> ucfg1_{camc::ucfg::reset_value, camc::ucfg::reset_value,
                                        camc::ucfg::reset_value, camc::ucfg::reset_value};

    struct Homing {
        HomeMethod method;
        int step = -1; // -1 idle; 0 search, 1 back off, 2 approach, 3 Z phase
        unsigned result = home::success;
    };
    std::array<Homing, 4> homing_{};
    std::array<unsigned, 4> profile_{1, 1, 1, 1};
    std::array<double, 4> accel_jerk_{}, jerk_{}, blend_{};
    std::array<std::int64_t, 4> target_{};
    std::array<bool, 4> take_over_{};
    // The axis holding the rates of the drive an axis was last started in (itself, or the master
    // of its interpolation), and that drive's chip steps per pulse of path (for SlowStop's Decel).
    std::array<int, 4> master_{0, 1, 2, 3};
    std::array<double, 4> step_scale_{1, 1, 1, 1};

    static bool axis_ok(long a) { return a >= 0 && a < 4; }
    int home_step(int axis);
    int speeds(int axis, double vel, double acc, double dec, std::uint32_t profile_mode);
    /// Takes the SetBlend speed of `master` if `busy`: 0 = no blend (a busy axis is refused).
    double take_blend(int master, bool busy);
    /// JSPD/JEXIT of a blended start: the junction speed in the new drive's and the running one's steps.
    void blend_speeds(int master, double vel, double new_scale);
    void uio(int axis, unsigned bit, bool on);
    void set_master(std::uint32_t mask, int master, double scale);
};

} // namespace rcsim::motion
