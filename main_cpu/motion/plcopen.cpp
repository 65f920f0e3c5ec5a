// rcsim — PLCopen motion function blocks. See plcopen.h.
#include "main_cpu/motion/plcopen.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace rcsim::motion {

using camc::endst::alarm;
using camc::endst::estop_cmd;
using camc::endst::estop_signal;
using camc::endst::home_ok;
using camc::endst::nelm;
using camc::endst::pelm;

// ---------------------------------------------------------------------------------------------
// Axis

std::uint16_t McAxis::motion_refusal(BufferMode mode) const {
    switch (state_) {
    case AxisState::error_stop: return err::axis_error_stop;
    case AxisState::disabled: return err::axis_disabled;
    case AxisState::homing: return err::wrong_state;
    case AxisState::stopping: return (stop_held_ || mode == BufferMode::aborting) ? err::axis_stopping : 0;
    default: return 0;
    }
}

void McAxis::enter_error(std::uint16_t id) {
    error_id_ = id;
    state_ = AxisState::error_stop;
    stop_held_ = false;
    if (api_.InMotion(static_cast<int>(index_))) api_.EmergencyStop(static_cast<int>(index_));
    // Every command in the axis' hands ends with Error (Part 1 §2.2: buffered ones too).
    for (auto* slot : {&active_, &queued_})
        if (auto j = *slot) {
            j->status = Job::Status::error;
            j->error_id = j->axes.size() > 1 ? err::group_error_stop : id; // Part 4: the group's error
            for (McAxis* a : j->axes)
                if (a != this) {
                    if (a->active_ == j) a->active_.reset();
                    if (a->queued_ == j) a->queued_.reset();
                    if (a->state_ == AxisState::synchronized_motion) {
                        if (a->api_.InMotion(static_cast<int>(a->index_))) a->api_.EmergencyStop(static_cast<int>(a->index_));
                        a->api_.ClearEndStatus(static_cast<int>(a->index_)); // the stop's cause is not the partner's
                        a->settle_state();
                    }
                }
            slot->reset();
        }
}

void McAxis::emergency_stop_all() {
    api_.EmergencyStopAll();
    if (group_.empty()) group_ = {this};
    for (McAxis* a : group_) {
        if (a->state_ != AxisState::error_stop) a->enter_error(err::emergency_stop);
        // The drives' own quick stop (controlword 0x02, transition 11): each ramps down by its
        // 0x605A option code, as the chip's pulses have stopped at once.
        if (a->drive_.state() == Cia402State::operation_enabled) a->drive_.set_controlword(cw::quick_stop_cmd);
    }
}

void McAxis::settle_state() {
    if (state_ == AxisState::error_stop || state_ == AxisState::disabled) return;
    if (state_ == AxisState::stopping && stop_held_) return;
    state_ = powered_ ? AxisState::standstill : AxisState::disabled;
}

void McAxis::start(const std::shared_ptr<Job>& j) {
    j->status = Job::Status::active;
    j->started = true;
    for (McAxis* a : j->axes) a->state_ = j->motion_state;
    const int r = j->start();
    if (r == axl::success) return;
    if (r == axl::sensor_check) {
        // A limit, the alarm or ESTOP refused the start: an axis error (Part 1 Note 1).
        const std::uint32_t es = api_.EndStatus(static_cast<int>(index_));
        enter_error((es & pelm) ? err::limit_positive : (es & nelm) ? err::limit_negative
                    : (es & alarm) ? err::drive_fault : err::emergency_stop);
        return;
    }
    finish_job(Job::Status::error, static_cast<std::uint16_t>(r)); // a parameter error: FB error only
}

void McAxis::finish_job(Job::Status st, std::uint16_t id) {
    auto j = active_;
    if (!j) return;
    j->status = st;
    j->error_id = id;
    for (McAxis* a : j->axes) {
        if (a->active_ != j) continue;
        a->active_.reset();
        if (a->queued_) {
            a->active_ = std::move(a->queued_);
            a->active_->status = Job::Status::active;
        } else {
            a->settle_state();
        }
    }
}

void McAxis::cycle() {
    const int ax = static_cast<int>(index_);
    if (state_ != AxisState::error_stop) {
        std::uint16_t e = 0;
        if (drive_.alarm_output()) {
            e = err::drive_fault;
        } else {
            const std::uint32_t es = api_.EndStatus(ax);
            if (es & pelm) e = err::limit_positive;
            else if (es & nelm) e = err::limit_negative;
            else if (es & alarm) e = err::drive_fault;
            else if (es & (estop_signal | estop_cmd)) e = err::emergency_stop;
        }
        if (!e) e = monitor_limits(); // software limits, following error (axis_limits.cpp)
        if (e == err::drive_fault && !drive_.alarm_output() && blame_partner()) return;
        if (e) {
            enter_error(e);
            return;
        }
    }
    if (!active_) {
        // A group move aborted or stopped through its partner axis leaves this axis without a
        // job, still driven by the chip's ramp down: it is at rest when the chip is.
        const bool moving_state = state_ == AxisState::discrete_motion || state_ == AxisState::continuous_motion ||
                                  state_ == AxisState::synchronized_motion;
        if (!moving_state || api_.InMotion(ax)) return;
        if (!queued_) {
            settle_state();
            return;
        }
        active_ = std::move(queued_); // a command buffered behind the group move starts now
        active_->status = Job::Status::active;
        state_ = active_->motion_state;
    }
    if (active_->status != Job::Status::active && active_->status != Job::Status::queued) {
        active_.reset(); // finished through the partner axis of a group job
        if (queued_) active_ = std::move(queued_);
        else settle_state();
        if (!active_) return;
    }
    Job& j = *active_;
    bool any_busy = false;
    for (McAxis* a : j.axes) any_busy |= a->api_.InMotion(static_cast<int>(a->index_));
    if (!j.started) {
        if (!any_busy) start(active_);
        return;
    }
    if (queued_ && queued_->started && queued_->status == Job::Status::queued) {
        // Blending: the chip passed the junction and runs the successor (its queue is empty):
        // this move is Done and the successor Active, without a stop.
        if (!any_busy || !api_.BlendQueued(master_of(j))) finish_job(Job::Status::done);
        return;
    }
    if (j.is_continuous) {
        // MC_MoveVelocity releases a buffered successor at InVelocity (Part 1 Table 4): it is
        // aborted then, and the successor starts once the chip has ramped the drive down.
        const bool in_velocity = any_busy && (api_.DriveStatus(ax) & camc::drvst::constant);
        if (queued_ && in_velocity) {
            j.status = Job::Status::aborted;
            api_.SlowStop(ax, 0);
            active_ = std::move(queued_);
            active_->status = Job::Status::active;
            state_ = active_->motion_state;
            return;
        }
        if (!any_busy) finish_job(Job::Status::aborted); // ended by someone else's stop
        return;
    }
    if (j.is_home) {
        // The library's homing sequence advances here, one step per drive end.
        const unsigned r = api_.HomeGetResult(ax);
        if (r == home::searching) return;
        if (r == home::success) {
            api_.SetPos(ax, j.home_position);
            api_.ClearEndStatus(ax);
            finish_job(Job::Status::done);
        } else {
            enter_error(r == home::err_pos_limit   ? err::limit_positive
                        : r == home::err_neg_limit ? err::limit_negative
                        : r == home::err_amp_fault ? err::drive_fault
                                                   : err::home_not_found);
        }
        return;
    }
    if (any_busy) return;
    if (j.is_stop) {
        j.status = Job::Status::done; // Done, but the axis stays in Stopping while Execute
        active_.reset();
        if (!stop_held_) leave_stopping();
        return;
    }
    finish_job(Job::Status::done);
}

void McAxis::submit(const std::shared_ptr<Job>& job, BufferMode mode) {
    job->mode = mode;
    if (mode == BufferMode::aborting && try_take_over(job)) return;
    if (mode != BufferMode::aborting)
        for (McAxis* a : job->axes)
            if (a->active_ && a->queued_ && a->queued_->started) { // already on the chip: not replaceable
                job->status = Job::Status::error;
                job->error_id = err::buffer_full;
                return;
            }
    for (McAxis* a : job->axes) {
        if (mode == BufferMode::aborting || !a->active_) {
            for (auto* slot : {&a->active_, &a->queued_})
                if (*slot && *slot != job) {
                    (*slot)->status = Job::Status::aborted;
                    for (McAxis* b : (*slot)->axes)
                        if (b != a && b->active_ == *slot) b->active_.reset();
                    slot->reset();
                }
            // The CAMC-QI cannot retarget a running drive: decelerate (at MC_Halt's own rate for a
            // halt), then start the new job.
            if (a->api_.InMotion(static_cast<int>(a->index_)) && !job->is_stop)
                a->api_.SlowStop(static_cast<int>(a->index_), job->abort_decel);
            a->active_ = job;
            a->state_ = job->motion_state; // the state changes when the command is issued
        } else {
            if (a->queued_ && a->queued_ != job) a->queued_->status = Job::Status::aborted;
            a->queued_ = job;
        }
    }
    bool active_everywhere = true, any_busy = false;
    for (McAxis* a : job->axes) {
        active_everywhere &= a->active_ == job;
        any_busy |= a->api_.InMotion(static_cast<int>(a->index_));
    }
    if (active_everywhere) job->status = Job::Status::active;
    if (active_everywhere && (!any_busy || job->is_stop)) start(job);
    if (!active_everywhere && blending(mode)) try_blend(job);
}

void McAxis::set_power(bool status) {
    if (powered_ == status) return;
    powered_ = status;
    if (!status) {
        for (auto* slot : {&active_, &queued_})
            if (*slot) {
                (*slot)->status = Job::Status::aborted;
                slot->reset();
            }
        if (api_.InMotion(static_cast<int>(index_))) api_.EmergencyStop(static_cast<int>(index_));
        stop_held_ = false;
        if (state_ != AxisState::error_stop) state_ = AxisState::disabled; // Note 2
    } else if (state_ == AxisState::disabled) {
        state_ = AxisState::standstill; // Note 5
    }
}

void McAxis::release_stop() {
    stop_held_ = false;
    if (state_ == AxisState::stopping && !active_) leave_stopping(); // Note 6
}

void McAxis::leave_stopping() {
    if (queued_) { // the buffered command released by Done AND NOT Execute
        active_ = std::move(queued_);
        active_->status = Job::Status::active;
        state_ = active_->motion_state; // it starts at the next cycle, the chip being idle
        return;
    }
    settle_state();
}

void McAxis::reset_error() {
    if (state_ != AxisState::error_stop) return;
    api_.ClearEndStatus(static_cast<int>(index_));
    error_id_ = 0;
    state_ = powered_ ? AxisState::standstill : AxisState::disabled; // Notes 3, 4
}

// ---------------------------------------------------------------------------------------------
// Block interface

void McExecuteFb::call() {
    // Done/Error/CommandAborted reset when Execute is low, after being visible for one call.
    if (!Execute && (Done || Error || CommandAborted)) {
        Done = Error = CommandAborted = false;
        ErrorID = 0;
    }
    const bool rising = Execute && !prev_;
    prev_ = Execute;
    if (rising) {
        Done = Busy = Active = CommandAborted = Error = false;
        ErrorID = 0;
        job_.reset(); // a new edge before completion: no Done for the previous job
        if (const std::uint16_t e = begin()) {
            Error = true;
            ErrorID = e;
            job_.reset();
        }
    }
    if (job_) {
        running();
        switch (job_->status) {
        case Job::Status::queued: Busy = true; Active = false; break;
        case Job::Status::active: Busy = true; Active = true; break;
        case Job::Status::done: Done = true; Busy = Active = false; job_.reset(); break;
        case Job::Status::aborted: CommandAborted = true; Busy = Active = false; job_.reset(); break;
        case Job::Status::error:
            Error = true;
            ErrorID = job_->error_id;
            Busy = Active = false;
            job_.reset();
            break;
        }
    }
    after();
}

std::uint16_t check_motion(const McAxis* axis, double vel, double acc, double dec, BufferMode mode) {
    if (!axis) return err::invalid_axis;
    if (!valid(mode)) return err::invalid_buffer_mode;
    if (const std::uint16_t r = axis->motion_refusal(mode)) return r;
    if (!(vel > 0)) return err::invalid_velocity;
    if (vel > camc::CamcQi::max_pps) return err::velocity_out_of_bound;
    if (!(acc > 0) || !(dec > 0)) return err::invalid_accel;
    return check_dynamics(axis->limits(), vel, acc, dec);
}

namespace {
std::shared_ptr<Job> make_job(std::vector<McAxis*> axes, AxisState st, std::function<int()> start) {
    auto j = std::make_shared<Job>();
    j->axes = std::move(axes);
    j->motion_state = st;
    j->start = std::move(start);
    return j;
}
} // namespace

void MC_Power::call() {
    if (!Axis) {
        Error = Enable;
        ErrorID = Enable ? err::invalid_axis : 0;
        return;
    }
    Cia402Drive& d = Axis->drive();
    QiMotionApi& api = Axis->api();
    const int ax = static_cast<int>(Axis->index());
    Axis->set_power_enable(Enable);
    if (!Enable) {
        if (Status || Valid) {
            api.SignalServoOn(ax, 0);
            d.set_servo_on_input(false);
            d.set_controlword(cw::shutdown);
        }
        Status = Valid = Error = false;
        ErrorID = 0;
        waited_ = 0;
        Axis->set_power(false);
        return;
    }
    api.SignalServoOn(ax, 1);
    d.set_servo_on_input(true);
    std::uint16_t write = 0;
    switch (d.state()) {
    case Cia402State::switch_on_disabled: write = cw::shutdown; break;
    case Cia402State::ready_to_switch_on: write = cw::switch_on_cmd; break;
    case Cia402State::switched_on: write = cw::enable_operation_cmd; break;
    default: break;
    }
    if (write) {
        d.set_controlword(write);
        history.emplace_back(write, d.statusword());
    }
    const bool was = Status;
    Status = d.state() == Cia402State::operation_enabled && !write && !d.disabling();
    // The drive enabled where its motor is (its deviation counter cleared): the command counter
    // starts there too, or the next move would carry the old difference to its end point.
    if (Status && !was && !api.InMotion(ax)) api.SetCmdPos(ax, api.ActPos(ax));
    // A drive in Quick stop active (0x605A 5-8) waits there for MC_Reset: not a timeout.
    const bool held = d.alarm_output() || d.state() == Cia402State::quick_stop_active;
    if (!Status && !held && ++waited_ > timeout_cycles && !Error) {
        Error = true;
        ErrorID = err::power_timeout;
    }
    if (Status) waited_ = 0;
    Valid = !Error;
    Axis->set_power(Status);
}

std::uint16_t MC_Reset::begin() {
    if (!Axis) return err::invalid_axis;
    phase_ = 0;
    job_ = std::make_shared<Job>();
    job_->status = Job::Status::active; // the block's own job: never handed to the axis
    return 0;
}

void MC_Reset::running() {
    if (job_->status != Job::Status::active) return;
    Cia402Drive& d = Axis->drive();
    QiMotionApi& api = Axis->api();
    const int ax = static_cast<int>(Axis->index());
    switch (phase_) {
    case 0:
        // Only a drive in Fault gets a fault reset (ALMRST, controlword bit 7 rising with the
        // enable bits kept): an axis in StandStill, or in ErrorStop by a limit switch, keeps its
        // power stage on (CiA402: bit 7 acts in Fault only; 0x80 alone would disable voltage).
        if (d.state() == Cia402State::quick_stop_active) {
            // A quick stop that stays (0x605A 5-8): back to Operation enabled (transition 16)
            // once the ramp has stopped the motor.
            if (d.actual_velocity() != 0) return;
            d.set_controlword(cw::enable_operation_cmd);
        }
        faulted_ = d.alarm_output();
        if (faulted_) {
            api.SignalServoAlarmReset(ax, 1);
            d.set_alarm_reset_input(true);
            d.set_controlword(static_cast<std::uint16_t>(d.controlword() & ~cw::fault_reset));
            d.set_controlword(static_cast<std::uint16_t>(d.controlword() | cw::fault_reset));
        }
        api.ClearEndStatus(ax);
        phase_ = 1;
        break;
    case 1:
        if (faulted_) {
            api.SignalServoAlarmReset(ax, 0);
            d.set_alarm_reset_input(false);
            d.set_controlword(static_cast<std::uint16_t>(d.controlword() & ~cw::fault_reset));
        }
        if (d.alarm_output()) { // the cause is still there
            job_->status = Job::Status::error;
            job_->error_id = err::drive_fault;
            return;
        }
        phase_ = 2;
        break;
    default:
        // Note 4: with MC_Power.Enable the axis returns to Standstill once MC_Power has the drive
        // in Operation enabled again; Note 3: without it, to Disabled at once.
        if (Axis->power_enable() && d.state() != Cia402State::operation_enabled) return;
        Axis->set_power(Axis->power_enable() && d.state() == Cia402State::operation_enabled);
        Axis->reset_error();
        job_->status = Job::Status::done;
    }
}

std::uint16_t MC_Stop::begin() {
    if (!Axis) return err::invalid_axis;
    if (Emergency) { // never refused: the axes stop whatever their state
        Axis->emergency_stop_all();
        job_ = std::make_shared<Job>();
        job_->status = Job::Status::done; // the block's own job: the chip stopped at once
        return 0;
    }
    if (Axis->state() == AxisState::error_stop) return err::axis_error_stop;
    if (Axis->state() == AxisState::disabled) return err::axis_disabled;
    const int ax = static_cast<int>(Axis->index());
    const double dec = Deceleration;
    job_ = make_job({Axis}, AxisState::stopping, [&api = Axis->api(), ax, dec] { return api.SlowStop(ax, dec); });
    job_->is_stop = true;
    issued_ = true;
    Axis->submit(job_, BufferMode::aborting);
    return 0;
}

void MC_Stop::running() {}

void MC_Stop::after() {
    // Only the instance that stopped the axis holds and releases Stopping: another MC_Stop of the
    // same axis idling with Execute low (a program's own next to the token layer's) must not
    // release it (the rule is the axis', whichever program calls the blocks).
    if (!Axis || !issued_) return;
    if (Execute && Axis->state() == AxisState::stopping) Axis->hold_stop();
    if (!Execute) {
        if (job_)
            Axis->drop_stop_hold(); // Stopping until Done, then Standstill (or a buffered command)
        else
            Axis->release_stop();
        issued_ = false;
    }
}

std::uint16_t MC_Halt::begin() {
    if (!Axis) return err::invalid_axis;
    if (!valid(Mode)) return err::invalid_buffer_mode;
    if (const std::uint16_t r = Axis->motion_refusal()) return r;
    if (!(Deceleration >= 0) || !std::isfinite(Deceleration)) return err::invalid_accel;
    const int ax = static_cast<int>(Axis->index());
    const double dec = Deceleration;
    job_ = make_job({Axis}, AxisState::discrete_motion, [&api = Axis->api(), ax, dec] { return api.SlowStop(ax, dec); });
    job_->is_stop = false;
    job_->abort_decel = dec; // the aborted move ramps down at the Halt's rate, not its own
    // Halt decelerates the running drive; it must not be preceded by another SSTOP.
    job_->started = false;
    Axis->submit(job_, Mode);
    return 0;
}

std::uint16_t MC_Home::begin() {
    if (!Axis) return err::invalid_axis;
    if (!valid(Mode)) return err::invalid_buffer_mode;
    if (Axis->state() != AxisState::standstill) return Axis->motion_refusal() ? Axis->motion_refusal() : err::wrong_state;
    if (Position < -camc::max_coordinate || Position > camc::max_coordinate) return err::position_out_of_bound;
    HomeMethod m;
    m.dir = Direction < 0 ? -1 : 1;
    m.zphase = ZPhase;
    m.vel_first = Velocity, m.vel_second = BackOffVelocity, m.vel_third = ApproachVelocity, m.vel_last = ZVelocity;
    m.acc_first = m.acc_second = Acceleration;
    const int ax = static_cast<int>(Axis->index());
    QiMotionApi& api = Axis->api();
    if (const int r = api.HomeSetMethod(ax, m)) return static_cast<std::uint16_t>(r); // 4113 / 4114 / 4253
    job_ = make_job({Axis}, AxisState::homing, [&api, ax] { return api.HomeSetStart(ax); });
    job_->is_home = true;
    job_->home_position = Position;
    Axis->submit(job_, Mode);
    return 0;
}

std::uint16_t MC_MoveAbsolute::begin() {
    if (const std::uint16_t e = check_motion(Axis, Velocity, Acceleration, Deceleration, Mode)) return e;
    const int ax = static_cast<int>(Axis->index());
    if (Position < -camc::max_coordinate || Position > camc::max_coordinate) return err::position_out_of_bound;
    if (const std::uint16_t e = check_target(Axis->limits(), Position)) return e;
    if (!(Jerk >= 0)) return err::profile_invalid;
    const std::int32_t p = Position;
    const double v = Velocity, a = Acceleration, d = Deceleration, j = Jerk;
    job_ = make_job({Axis}, AxisState::discrete_motion, [&api = Axis->api(), ax, p, v, a, d, j] {
        api.SetJerk(ax, j);
        return api.MovePos(ax, p, v, a, d);
    });
    job_->blendable = true;
    job_->velocity = v;
    job_->direction = [&api = Axis->api(), ax, p] {
        const std::int64_t d = p - api.TargetPos(ax);
        return d > 0 ? 1 : d < 0 ? -1 : 0;
    };
    job_->can_take_over = [&api = Axis->api(), ax, p, d] { return room_to_take_over(api, ax, p - api.CmdPos(ax), d); };
    Axis->submit(job_, Mode);
    return 0;
}

std::uint16_t MC_MoveRelative::begin() {
    if (const std::uint16_t e = check_motion(Axis, Velocity, Acceleration, Deceleration, Mode)) return e;
    const int ax = static_cast<int>(Axis->index());
    if (!(Jerk >= 0)) return err::profile_invalid;
    const std::int64_t dist = Distance;
    const double v = Velocity, a = Acceleration, d = Deceleration, j = Jerk;
    // Relative to the set position when the move actually starts (after a buffered predecessor);
    // a target beyond the chip's range fails then with 4251.
    if (const std::uint16_t e = check_relative_target(*Axis, dist)) return e;
    job_ = make_job({Axis}, AxisState::discrete_motion, [&api = Axis->api(), &lim = Axis->limits(), ax, dist, v, a, d, j] {
        api.SetJerk(ax, j);
        // Blended: from where the running move ends.
        const std::int64_t target = (api.InMotion(ax) && api.BlendPending(ax) ? api.TargetPos(ax) : api.CmdPos(ax)) + dist;
        if (target < -camc::max_coordinate || target > camc::max_coordinate) return axl::position_out_of_bound;
        if (const std::uint16_t e = check_target(lim, target)) return int{e}; // FB error, the axis stays
        return api.MovePos(ax, static_cast<std::int32_t>(target), v, a, d);
    });
    job_->blendable = true;
    job_->velocity = v;
    job_->direction = [dist] { return dist > 0 ? 1 : dist < 0 ? -1 : 0; };
    job_->can_take_over = [&api = Axis->api(), ax, dist, d] { return room_to_take_over(api, ax, dist, d); };
    Axis->submit(job_, Mode);
    return 0;
}

std::uint16_t MC_MoveVelocity::begin() {
    if (const std::uint16_t e = check_motion(Axis, std::abs(Velocity), Acceleration, Deceleration, Mode)) return e;
    const int ax = static_cast<int>(Axis->index());
    int dir = static_cast<int>(Direction);
    if (dir == 0) // mcCurrentDirection: the way the axis moves now (positive when standing)
        dir = (Axis->api().InMotion(ax) && (Axis->api().DriveStatus(ax) & camc::drvst::negative)) ? -1 : 1;
    if (Velocity < 0) dir = -dir;
    if (!(Jerk >= 0)) return err::profile_invalid;
    const double v = dir * std::abs(Velocity), a = Acceleration, d = Deceleration, j = Jerk;
    job_ = make_job({Axis}, AxisState::continuous_motion, [&api = Axis->api(), ax, v, a, d, j] {
        api.SetJerk(ax, j);
        return api.MoveVel(ax, v, a, d);
    });
    job_->is_continuous = true;
    job_->can_take_over = [&api = Axis->api(), ax, v] {
        return (v < 0 ? -1 : 1) == ((api.DriveStatus(ax) & camc::drvst::negative) ? -1 : 1);
    };
    Axis->submit(job_, Mode);
    return 0;
}

void MC_MoveVelocity::running() {
    const int ax = static_cast<int>(Axis->index());
    // The setpoint, not the actual speed (Part 1 §2.4.1): the chip's drive in its constant phase.
    InVelocity = job_->status == Job::Status::active && job_->started &&
                 (Axis->api().DriveStatus(ax) & (camc::drvst::busy | camc::drvst::constant)) ==
                     (camc::drvst::busy | camc::drvst::constant);
}

void MC_MoveVelocity::after() {
    if (!job_) InVelocity = false; // CommandAborted and Error reset InVelocity
}

namespace {
std::uint16_t check_pair(McAxis* x, McAxis* y, double v, double a, double d, BufferMode mode) {
    if (!x || !y || x == y) return err::invalid_axis;
    if (const std::uint16_t e = check_motion(x, v, a, d, mode)) return e;
    return check_motion(y, v, a, d, mode);
}
} // namespace

std::uint16_t MC_LineMove2::begin() {
    if (const std::uint16_t e = check_pair(AxisX, AxisY, Velocity, Acceleration, Deceleration, Mode)) return e;
    if (const std::uint16_t e = check_relative_target(*AxisX, X)) return e;
    if (const std::uint16_t e = check_relative_target(*AxisY, Y)) return e;
    QiMotionApi& api = AxisX->api();
    const int coord = 0;
    const std::uint32_t mask = (1u << AxisX->index()) | (1u << AxisY->index());
    const bool swapped = AxisX->index() > AxisY->index(); // the chip orders axes by number
    const std::int32_t x = X, y = Y;
    const double v = Velocity, a = Acceleration, d = Deceleration;
    job_ = make_job({AxisX, AxisY}, AxisState::synchronized_motion, [&api, coord, mask, swapped, x, y, v, a, d] {
        api.SetCoord(coord, mask);
        const std::int32_t pos[2] = {swapped ? y : x, swapped ? x : y};
        return api.LineMove(coord, pos, v, a, d);
    });
    job_->blendable = true;
    job_->velocity = v;
    AxisX->submit(job_, Mode);
    return 0;
}

std::uint16_t MC_LineMove::begin() {
    const std::size_t n = Axes.size();
    if (n < 2 || n > 4 || Distances.size() != n) return err::invalid_axis;
    std::uint32_t mask = 0;
    std::array<std::int32_t, 4> by_index{};
    for (std::size_t i = 0; i < n; ++i) {
        McAxis* a = Axes[i];
        if (!a || (mask & (1u << a->index())) || &a->api() != &Axes[0]->api()) return err::invalid_axis;
        if (const std::uint16_t e = check_motion(a, Velocity, Acceleration, Deceleration, Mode)) return e;
        if (const std::uint16_t e = check_relative_target(*a, Distances[i])) return e;
        mask |= 1u << a->index();
        by_index[a->index()] = Distances[i];
    }
    // The chip takes the end point axis by axis in ascending axis order.
    std::array<std::int32_t, 4> pos{};
    unsigned k = 0;
    for (unsigned a = 0; a < 4; ++a)
        if (mask & (1u << a)) pos[k++] = by_index[a];
    QiMotionApi& api = Axes[0]->api();
    const double v = Velocity, acc = Acceleration, dec = Deceleration;
    job_ = make_job(Axes, AxisState::synchronized_motion, [&api, mask, pos, v, acc, dec] {
        api.SetCoord(3, mask);
        return api.LineMove(3, pos.data(), v, acc, dec);
    });
    job_->blendable = true;
    job_->velocity = v;
    Axes[0]->submit(job_, Mode);
    return 0;
}

std::uint16_t MC_CircleCenterMove::begin() {
    if (const std::uint16_t e = check_pair(AxisX, AxisY, Velocity, Acceleration, Deceleration, Mode)) return e;
    if (Direction != dir_cw && Direction != dir_ccw) return err::interpolation_value;
    if (AxisX->index() > AxisY->index()) return err::invalid_axis; // X must be the lower-numbered axis
    // The end must lie on the circle through the start (within one pulse), or the chip would stop
    // where the short axis happens to reach the end's coordinate.
    const double cx0 = CenterX, cy0 = CenterY; // exact: |values| < 2^31
    const double r0 = std::hypot(cx0, cy0), r1 = std::hypot(double(EndX) - cx0, double(EndY) - cy0);
    if (r0 < 1 || std::abs(r1 - r0) > 1.0) return err::interpolation_value;
    try {
        camc::circle_step_count({-std::int64_t{CenterX}, -std::int64_t{CenterY}},
                                {std::int64_t{EndX} - CenterX, std::int64_t{EndY} - CenterY},
                                Direction == dir_cw ? camc::ArcDirection::cw : camc::ArcDirection::ccw);
    } catch (const camc::InterpolationError&) {
        return err::interpolation_value;
    }
    QiMotionApi& api = AxisX->api();
    const std::uint32_t mask = (1u << AxisX->index()) | (1u << AxisY->index());
    const std::int32_t cx = CenterX, cy = CenterY, ex = EndX, ey = EndY;
    const double v = Velocity, a = Acceleration, d = Deceleration;
    const int dir = Direction;
    job_ = make_job({AxisX, AxisY}, AxisState::synchronized_motion, [&api, mask, cx, cy, ex, ey, v, a, d, dir] {
        api.SetCoord(1, mask);
        return api.CircleCenterMove(1, cx, cy, ex, ey, v, a, d, dir);
    });
    job_->blendable = true;
    job_->velocity = v;
    AxisX->submit(job_, Mode);
    return 0;
}

} // namespace rcsim::motion
