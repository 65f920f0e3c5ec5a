// rcsim — PLCopen Motion Control function blocks (Part 1 v2.0 single-axis state diagram and
// interface rules, docs/motion.md; Table 2 of the paper P2, docs/system.md §1) over the paper's
// C motion library (qi_api.h) and a CiA402 drive per axis.
//
// Every block is called once per control cycle (call()); motion blocks hand a Job to the axis,
// which starts it on the chip and reports Active/Done/Aborted/Error back. The interpolating
// blocks (MC_LineMove2, MC_CircleCenterMove) put both axes into SynchronizedMotion (a two-axis
// group in the sense of Part 4).
#pragma once

#include "main_cpu/motion/axis_limits.h"
#include "main_cpu/motion/cia402_drive.h"
#include "main_cpu/motion/qi_api.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace rcsim::motion {

enum class AxisState : std::uint8_t {
    disabled, standstill, homing, discrete_motion, continuous_motion, synchronized_motion, stopping, error_stop,
};
const char* to_string(AxisState s);

/// MC_BUFFER_MODE (Part 1 §2.4.2, numbered as PLC runtimes do): with the blending modes the
/// command waits for the running one as buffered, but the axis passes the junction without
/// stopping, at the lower (Low) of both Velocity inputs, the first's (Previous), the second's
/// (Next) or the higher (High) (docs/motion.md "Buffer modes"). Other values: ErrorID 0x7020.
enum class BufferMode : std::uint8_t {
    aborting = 0, buffered = 1, blending_low = 2, blending_previous = 3, blending_next = 4, blending_high = 5,
};
bool valid(BufferMode m);
bool blending(BufferMode m);
/// The speed at the junction of a move at v1 blended into one at v2 (0 = stop there).
double blend_velocity(BufferMode m, double v1, double v2);
/// MC_DIRECTION (Part 1 §2.4.3) for MC_MoveVelocity; mcShortestWay applies to rotary axes only.
enum class McDirection : std::int8_t { negative = -1, current = 0, positive = 1 };

/// ErrorID values (AXL codes where AXL has one, 0x7xxx our own).
namespace err {
constexpr std::uint16_t none = 0;
constexpr std::uint16_t invalid_axis = 4101, invalid_velocity = 4113, invalid_accel = 4114;
constexpr std::uint16_t sensor_check = 4169, interpolation_value = 4184, velocity_out_of_bound = 4253;
constexpr std::uint16_t position_out_of_bound = 4251; // beyond the chip's +-(2^30 - 1) pulses
constexpr std::uint16_t profile_invalid = 4252;       // e.g. a negative Jerk
constexpr std::uint16_t axis_disabled = 0x7001;  // motion command while Disabled
constexpr std::uint16_t axis_error_stop = 0x7002; // motion command while ErrorStop
constexpr std::uint16_t axis_stopping = 0x7003;  // motion command while MC_Stop.Execute
constexpr std::uint16_t wrong_state = 0x7004;    // e.g. MC_Home outside Standstill
constexpr std::uint16_t power_timeout = 0x7005;  // drive did not reach Operation enabled
constexpr std::uint16_t parameter_unsupported = 0x7006; // MC_ReadParameter: a number not listed in docs/motion.md
constexpr std::uint16_t invalid_buffer_mode = 0x7020; // BufferMode not one of MC_BUFFER_MODE's 0..5
constexpr std::uint16_t buffer_full = 0x7021;   // a command behind a blended one already on the chip
constexpr std::uint16_t limit_positive = 0x7101, limit_negative = 0x7102, drive_fault = 0x7103;
constexpr std::uint16_t emergency_stop = 0x7104, home_not_found = 0x7105;
} // namespace err

class McAxis;

/// One motion command in the hands of an axis.
struct Job {
    enum class Status : std::uint8_t { queued, active, done, aborted, error };
    Status status = Status::queued;
    std::uint16_t error_id = 0;
    AxisState motion_state = AxisState::discrete_motion;
    std::vector<McAxis*> axes;                 // 1, or 2 for the interpolating blocks
    std::function<int()> start;                // issues the chip commands; returns an AXL code
    bool started = false;
    bool is_stop = false;                      // MC_Stop: holds the axis in Stopping
    bool is_home = false;
    bool is_continuous = false;                // MC_MoveVelocity: never Done; a buffered successor takes over at InVelocity
    double abort_decel = 0;                    // the ramp (pulses/s^2) that stops the drive it aborts; 0 = as programmed
    std::int64_t home_position = 0;
    // Blending: a positioning or path move (not a halt, velocity or homing), its Velocity and,
    // for one axis, its direction from where the move before it ends (0: unknown, no blend).
    bool blendable = false;
    double velocity = 0;
    std::function<int()> direction;
    BufferMode mode = BufferMode::aborting;
    // Aborting (issue #49 item 3): whether this single-axis move can take over the running drive
    // from its present speed (same way, room to stop); empty = never.
    std::function<bool()> can_take_over;
};

/// The axis whose chip registers hold a job's rates: the lowest-numbered (the chip's master).
int master_of(const Job& j);

class McAxis {
public:
    McAxis(unsigned index, QiMotionApi& api, Cia402Drive& drive) : index_(index), api_(api), drive_(drive) {}

    unsigned index() const { return index_; }
    AxisState state() const { return state_; }
    std::uint16_t error_id() const { return error_id_; }
    QiMotionApi& api() { return api_; }
    Cia402Drive& drive() { return drive_; }
    bool powered() const { return powered_; }

    /// Start of every control cycle: errors from the chip/drive, job completion, buffered starts.
    void cycle();
    /// Hands a job over (the caller has checked the state). Aborting: the running job is
    /// aborted (the chip decelerates with SSTOP before the new one starts); buffered: queued.
    void submit(const std::shared_ptr<Job>& job, BufferMode mode);
    /// Why a new motion command would be refused now (0 = accepted).
    std::uint16_t motion_refusal() const { return motion_refusal(BufferMode::aborting); }
    /// In Stopping a buffered command is taken once MC_Stop.Execute is low (it starts at
    /// Done AND NOT Execute, Part 1 Table 4); an aborting one never (the stop is not abortable).
    std::uint16_t motion_refusal(BufferMode mode) const;
    void set_power(bool status);
    void release_stop();                        // MC_Stop.Execute fell
    void hold_stop() { stop_held_ = true; }     // MC_Stop.Execute is high
    void drop_stop_hold() { stop_held_ = false; } // MC_Stop.Execute fell before Done
    void reset_error();                         // MC_Reset: ErrorStop -> Standstill/Disabled
    void enter_error(std::uint16_t id);
    /// The axes that share this axis' chip ({this} unless set): an emergency stop stops them all.
    void set_group(std::vector<McAxis*> group) { group_ = std::move(group); }
    /// Emergency stop (the ES token, MC_Stop with Emergency): the chip's ESTOP stops every axis at
    /// once, and every axis of the group, moving or not, latches ErrorStop (ErrorID 0x7104; an axis
    /// already in ErrorStop keeps its ErrorID) until MC_Reset.
    void emergency_stop_all();
    /// MC_Power.Enable as last seen (MC_Reset decides between Notes 3 and 4 with it).
    void set_power_enable(bool e) { power_enable_ = e; }
    bool power_enable() const { return power_enable_; }
    /// The limits MC_WriteParameter sets (axis_limits.h).
    AxisLimits& limits() { return limits_; }
    const AxisLimits& limits() const { return limits_; }

private:
    unsigned index_;
    QiMotionApi& api_;
    Cia402Drive& drive_;
    AxisState state_ = AxisState::disabled;
    std::uint16_t error_id_ = 0;
    bool powered_ = false, stop_held_ = false, power_enable_ = false;
    std::shared_ptr<Job> active_, queued_;
    std::vector<McAxis*> group_;
    AxisLimits limits_;

    /// Each cycle: a software limit passed while moving toward it, or the following error above
    /// MaxPositionLag (0 = none; axis_limits.cpp).
    std::uint16_t monitor_limits();
    /// The chip's ALARM end status without this drive's alarm, in a group move: a partner's drive
    /// failed. That partner takes the error (and stops this axis with it, Part 4); true if found.
    bool blame_partner();
    void finish_job(Job::Status st, std::uint16_t id = 0);
    void leave_stopping(); // Done AND NOT Execute: a buffered command, or Standstill
    void start(const std::shared_ptr<Job>& j);
    void settle_state();
    /// Blending: starts the buffered job on the chip behind the running one (queued there), if
    /// both can blend at a junction speed above 0; false leaves it buffered.
    bool try_blend(const std::shared_ptr<Job>& next);
    /// Aborting: replaces the running single-axis move by `job` on the chip at once, from the
    /// present velocity (no stop); false when it cannot, and the old way (ramp down) applies.
    bool try_take_over(const std::shared_ptr<Job>& job);
};

// ---------------------------------------------------------------------------------------------

/// Execute-type block: Done/Busy/Active/CommandAborted/Error/ErrorID by the Part 1 rules.
class McExecuteFb {
public:
    virtual ~McExecuteFb() = default;
    bool Execute = false;
    bool Done = false, Busy = false, Active = false, CommandAborted = false, Error = false;
    std::uint16_t ErrorID = 0;

    void call();

protected:
    /// On the rising edge of Execute: validate, build and submit a job (or return an ErrorID).
    virtual std::uint16_t begin() = 0;
    /// Each call while the job runs.
    virtual void running() {}
    /// At the end of every call (MC_Stop holds Stopping while Execute).
    virtual void after() {}
    std::shared_ptr<Job> job_;

private:
    bool prev_ = false;
};

class MC_Power {
public:
    McAxis* Axis = nullptr;
    bool Enable = false;
    bool Status = false, Valid = false, Error = false;
    std::uint16_t ErrorID = 0;
    int timeout_cycles = 100;
    /// (controlword written, statusword seen) per call, for P3's 0x06/0x07/0x0F sequence.
    std::vector<std::pair<std::uint16_t, std::uint16_t>> history;
    void call();

private:
    int waited_ = 0;
};

class MC_Reset : public McExecuteFb {
public:
    McAxis* Axis = nullptr;

protected:
    std::uint16_t begin() override;
    void running() override;
    int phase_ = 0;
    bool faulted_ = false; // the drive was in Fault at the edge: a fault reset is due
};

class MC_Stop : public McExecuteFb {
public:
    McAxis* Axis = nullptr;
    double Deceleration = 0; // 0 = the axis' programmed decel
    /// Vendor extension: an emergency stop instead of a ramp (the ES token): every axis of the
    /// chip stops at once and latches ErrorStop until MC_Reset; never refused; Done at once.
    bool Emergency = false;

protected:
    std::uint16_t begin() override;
    void running() override;
    void after() override;

private:
    bool issued_ = false; // this instance's stop holds the axis in Stopping
};

/// Part 1 §3.7: a controlled stop in DiscreteMotion, abortable by any motion command. The running
/// drive decelerates at the Halt's own Deceleration (0: the rate programmed for the aborted move),
/// so it travels v^2 / (2 Deceleration) while halting; Done at standstill.
class MC_Halt : public McExecuteFb {
public:
    McAxis* Axis = nullptr;
    double Deceleration = 0;
    BufferMode Mode = BufferMode::aborting;

protected:
    std::uint16_t begin() override;
};

/// Part 1 §3.3 homing by the CAMC-QI library's sequence (docs/motion.md "Homing"): search the
/// home switch at Velocity in Direction, back off it, approach it slowly and stop on its edge,
/// optionally move on to the encoder Z pulse; there the position becomes Position. Speed inputs
/// after Velocity are vendor extensions (AXL AxmHomeSetVel, its defaults).
class MC_Home : public McExecuteFb {
public:
    McAxis* Axis = nullptr;
    std::int32_t Position = 0; // set at the home point, pulses
    int Direction = -1;        // -1 negative, +1 positive
    double Velocity = 10000, Acceleration = 40000; // AXL home defaults
    double BackOffVelocity = 10000, ApproachVelocity = 2000, ZVelocity = 100;
    bool ZPhase = false;
    BufferMode Mode = BufferMode::aborting;

protected:
    std::uint16_t begin() override;
};

// Positions, distances and centres are whole pulses, 32-bit as the chip's counters (a decision:
// PLCopen's LREAL would invite fractions the chip cannot drive); the chip's range is
// +-(2^30 - 1) (ErrorID 4251 beyond). Velocities and rates are LREAL as in Part 1.

class MC_MoveAbsolute : public McExecuteFb {
public:
    McAxis* Axis = nullptr;
    std::int32_t Position = 0;
    double Velocity = 0, Acceleration = 0, Deceleration = 0;
    double Jerk = 0; // pulses/s^3: an S-curve with this jerk; 0 = trapezoid
    BufferMode Mode = BufferMode::aborting;

protected:
    std::uint16_t begin() override;
};

class MC_MoveRelative : public McExecuteFb {
public:
    McAxis* Axis = nullptr;
    std::int32_t Distance = 0;
    double Velocity = 0, Acceleration = 0, Deceleration = 0;
    double Jerk = 0; // pulses/s^3: an S-curve with this jerk; 0 = trapezoid
    BufferMode Mode = BufferMode::aborting;

protected:
    std::uint16_t begin() override;
};

/// Part 1 §3.9: an endless drive at Velocity (ContinuousMotion); InVelocity while the commanded
/// speed equals Velocity; ends only by CommandAborted (another motion block, MC_Halt, MC_Stop)
/// or Error. Velocity > 0 (its sign, if negative, reverses Direction); an aborting command the same
/// way takes over from the present speed, one that reverses first ramps this one down
/// (docs/motion.md "Buffer modes").
class MC_MoveVelocity : public McExecuteFb {
public:
    McAxis* Axis = nullptr;
    double Velocity = 0, Acceleration = 0, Deceleration = 0;
    double Jerk = 0; // pulses/s^3, 0 = trapezoid
    McDirection Direction = McDirection::positive;
    BufferMode Mode = BufferMode::aborting;
    bool InVelocity = false;

protected:
    std::uint16_t begin() override;
    void running() override;
    void after() override;
};

class MC_LineMove2 : public McExecuteFb {
public:
    McAxis *AxisX = nullptr, *AxisY = nullptr;
    std::int32_t X = 0, Y = 0; // relative to the current position (the paper's MC_LineMove)
    double Velocity = 0, Acceleration = 0, Deceleration = 0;
    BufferMode Mode = BufferMode::aborting;

protected:
    std::uint16_t begin() override;
};

/// Linear interpolation of 2-4 axes of one chip (a Part 4 group: all in SynchronizedMotion);
/// Distances relative to the current positions, one per entry of Axes (in any order).
class MC_LineMove : public McExecuteFb {
public:
    std::vector<McAxis*> Axes;
    std::vector<std::int32_t> Distances;
    double Velocity = 0, Acceleration = 0, Deceleration = 0; // path (vector) speed and rates
    BufferMode Mode = BufferMode::aborting;

protected:
    std::uint16_t begin() override;
};

class MC_CircleCenterMove : public McExecuteFb {
public:
    McAxis *AxisX = nullptr, *AxisY = nullptr;
    std::int32_t CenterX = 0, CenterY = 0, EndX = 0, EndY = 0; // relative to the current position
    int Direction = dir_ccw;
    double Velocity = 0, Acceleration = 0, Deceleration = 0;
    BufferMode Mode = BufferMode::aborting;

protected:
    std::uint16_t begin() override;
};

/// Enable-type block (Part 1 §2.4.2): while Enable, Busy and, when the value could be read,
/// Valid with the outputs refreshed every call; otherwise Error with ErrorID. All reset when
/// Enable falls.
class McEnableFb {
public:
    virtual ~McEnableFb() = default;
    McAxis* Axis = nullptr;
    bool Enable = false;
    bool Valid = false, Busy = false, Error = false;
    std::uint16_t ErrorID = 0;
    void call();

protected:
    /// Reads the values into the outputs (Axis is set); returns an ErrorID or 0.
    virtual std::uint16_t read() = 0;
    /// Clears the value outputs (Enable low, or an error).
    virtual void clear() = 0;
};

/// Part 1 §3.11: the axis' state of the state diagram, one BOOL each.
class MC_ReadStatus : public McEnableFb {
public:
    bool ErrorStop = false, Disabled = false, Stopping = false, Homing = false, Standstill = false;
    bool DiscreteMotion = false, ContinuousMotion = false, SynchronizedMotion = false;

protected:
    std::uint16_t read() override;
    void clear() override;
};

/// Part 1 §3.13: the actual position, pulses (the CAMC-QI's encoder counter CNT2).
class MC_ReadActualPosition : public McEnableFb {
public:
    double Position = 0;

protected:
    std::uint16_t read() override;
    void clear() override { Position = 0; }
};

/// Part 1 §3.12: the axis error (the ErrorID that put it in ErrorStop, 0 without).
class MC_ReadAxisError : public McEnableFb {
public:
    std::uint16_t AxisErrorID = 0;

protected:
    std::uint16_t read() override;
    void clear() override { AxisErrorID = 0; }
};

/// Part 1 §3.10 with the parameter numbers of its table that this axis has (axis_limits.h `par`):
/// 1 CommandedPosition (CNT1), 2-7 and 9, 13, 15 the limits (AxisLimits), 8 MaxVelocitySystem (the
/// chip's 10 Mpps), 10 ActualVelocity (the drive's 0x606C), 11 CommandedVelocity (the chip's current
/// drive speed, pulses/s; of the path for an interpolation's master); vendor numbers 0x605A,
/// 0x605C, 0x605E, 0x6084, 0x6085: the drive's object. Others: Error 0x7006.
class MC_ReadParameter : public McEnableFb {
public:
    std::int32_t ParameterNumber = 0;
    double Value = 0;

protected:
    std::uint16_t read() override;
    void clear() override { Value = 0; }
};

/// Part 1 §3.11: writes a parameter MC_ReadParameter reads, Done at once. Read-only numbers (1, 8,
/// 10, 11) answer 0x7010, a value outside the parameter's range 0x7011 (BOOLs take 0 or 1), other
/// numbers 0x7006; never refused by the axis state (a limit may be set while the axis moves).
class MC_WriteParameter : public McExecuteFb {
public:
    McAxis* Axis = nullptr;
    std::int32_t ParameterNumber = 0;
    double Value = 0;

protected:
    std::uint16_t begin() override;
};

/// Part 1 §3.8: shifts the axis' coordinate system without motion: the command and the actual
/// position by the same amount, so that the command position becomes Position (Relative: moves
/// by Position). Refused while the axis moves (0x7004) or in ErrorStop/Disabled as motion is;
/// Done at once.
class MC_SetPosition : public McExecuteFb {
public:
    McAxis* Axis = nullptr;
    std::int32_t Position = 0;
    bool Relative = false;

protected:
    std::uint16_t begin() override;
};

/// Whether a move `rest` pulses on from the present position can take over the axis' running
/// drive: the same way, and the drive's present speed can stop within it at `dec`.
bool room_to_take_over(QiMotionApi& api, int axis, std::int64_t rest, double dec);

/// Shared parameter checks (0 = ok).
std::uint16_t check_motion(const McAxis* axis, double vel, double acc, double dec,
                           BufferMode mode = BufferMode::aborting);

} // namespace rcsim::motion
