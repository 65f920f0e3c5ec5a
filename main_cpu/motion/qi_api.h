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
constexpr int velocity_out_of_bound = 4253;
} // namespace axl

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
    /// Starts a trapezoid move to the absolute position Pos (returns when the pulses start, as
    /// AxmMoveStartPos). Units: pulses, pulses/s, pulses/s^2.
    int MovePos(int AxisNo, float Pos, float dVel, float Accel, float Decel);
    /// Linear interpolation of the axes of coordinate system Coord (SetCoord), Pos[] relative to
    /// the current positions (the paper's MC_LineMove); Vel is the vector speed.
    int LineMove(int Coord, const float* Pos, float Vel, float Accel, float Decel);
    /// Circular interpolation on the two axes of Coord; centre and end relative to the current
    /// position; Dir = dir_cw / dir_ccw; writes QiISNUM from the octant formula (eqs. 1-10).
    int CircleCenterMove(int Coord, float CenX, float CenY, float EndX, float EndY, float Vel, float Accel,
                         float Decel, int Dir);
    /// Continuous drive (AxmMoveVel): Vel signed.
    int MoveVel(int AxisNo, float Vel, float Accel, float Decel);
    int HomeSearch(int AxisNo, int Dir, float Vel, float Accel);
    int SlowStop(int AxisNo, float Decel);
    int EmergencyStop(int AxisNo);
    int EmergencyStopAll();

    int SetCoord(int Coord, std::uint32_t axis_mask);
    void SetStartSpeed(int AxisNo, float Vel) { start_speed_[AxisNo & 3] = Vel; }
    bool InMotion(int AxisNo);
    std::uint32_t DriveStatus(int AxisNo); // STAT2 (AxmStatusReadMotion)
    std::uint32_t EndStatus(int AxisNo);
    void ClearEndStatus(int AxisNo);
    std::int64_t CmdPos(int AxisNo);
    std::int64_t ActPos(int AxisNo);
    void SetPos(int AxisNo, std::int64_t pos); // CNT1 and CNT2 (after homing)

    static constexpr int coords = 4;

private:
    QiBus& bus_;
    std::array<std::uint32_t, coords> coord_{0x3, 0x3, 0xC, 0xF};
    std::array<float, 4> start_speed_{100, 100, 100, 100};
    std::array<std::uint32_t, 4> ucfg1_{camc::ucfg::reset_value, camc::ucfg::reset_value,
                                        camc::ucfg::reset_value, camc::ucfg::reset_value};

    static bool axis_ok(long a) { return a >= 0 && a < 4; }
    int speeds(int axis, float vel, float acc, float dec, std::uint32_t profile_mode);
    void uio(int axis, unsigned bit, bool on);
};

} // namespace rcsim::motion
