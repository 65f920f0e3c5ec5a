// rcsim — the motion layer module. See motion_controller.h.
#include "main_cpu/motion/motion_controller.h"

#include "models/bus.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

namespace rcsim::motion {

/// The paper's library reaches the chip through the main board's bus: DATA then COMMAND.
class MotionController::Bus : public QiBus {
public:
    Bus(tlm_utils::simple_initiator_socket<MotionController>& s, MotionController& mc) : s_(s), mc_(mc) {}
    void write(unsigned axis, std::uint8_t code, std::uint32_t data) override {
        std::uint8_t b[4] = {std::uint8_t(data), std::uint8_t(data >> 8), std::uint8_t(data >> 16),
                             std::uint8_t(data >> 24)};
        access(BusCycle::mem_write, axis * camc::win::stride + camc::win::data, b, 4);
        access(BusCycle::mem_write, axis * camc::win::stride + camc::win::command, &code, 1);
    }
    std::uint32_t read(unsigned axis, std::uint8_t code) override {
        access(BusCycle::mem_write, axis * camc::win::stride + camc::win::command, &code, 1);
        std::uint8_t b[4] = {};
        access(BusCycle::mem_read, axis * camc::win::stride + camc::win::data, b, 4);
        return b[0] | (b[1] << 8) | (b[2] << 16) | (std::uint32_t{b[3]} << 24);
    }

private:
    tlm_utils::simple_initiator_socket<MotionController>& s_;
    MotionController& mc_;
    // The access takes effect at its start (the chip answers at once, models/bus.h); the main
    // CPU is then busy for its bus cycles: one per byte on the byte-wide bus.
    void access(BusCycle k, unsigned addr, std::uint8_t* d, unsigned len) {
        const BusResult r = bus_access(s_, k, addr, d, len, sc_core::sc_time_stamp());
        if (!r.ok())
            SC_REPORT_ERROR("rcsim/motion", ("CAMC-QI bus access failed at offset " + std::to_string(addr)).c_str());
        ++mc_.chip_accesses_;
        const MotionConfig::Cost& c = mc_.cfg_.cost;
        const sc_core::sc_time t = c.bus_cycle * static_cast<double>(len * (c.access_cycles + r.wait_states));
        mc_.bus_time_ += t;
        mc_.spend(t);
    }
};

MotionController::MotionController(sc_core::sc_module_name name, const MotionConfig& cfg)
    : sc_module(name), bus("bus"), chip_("camc_qi"), qi_bus_(std::make_unique<Bus>(bus, *this)), api_(*qi_bus_),
      cfg_(cfg) {
    bus.bind(chip_.socket);
    for (unsigned a = 0; a < axes; ++a) {
        drives_[a] = Cia402Drive(cfg.drive);
        axes_[a] = std::make_unique<McAxis>(a, api_, drives_[a]);
        power_[a].Axis = axes_[a].get();
        Blocks& b = blocks_[a];
        b.reset.Axis = b.stop.Axis = b.home.Axis = b.move_abs.Axis = b.move_rel.Axis = b.move_vel.Axis = b.halt.Axis =
            b.set_pos.Axis =
            axes_[a].get();
        chip_.set_encoder_source(a, [this, a] { return drives_[a].actual_position(); });
        camc::Sensors sensors;
        sensors.pelm = cfg.switches[a].pelm, sensors.nelm = cfg.switches[a].nelm, sensors.org = cfg.switches[a].home;
        sensors.z_pitch = cfg.zphase[a].pitch, sensors.z_offset = cfg.zphase[a].offset;
        chip_.set_sensors(a, sensors);
        api_.SetStartSpeed(static_cast<int>(a), cfg.start_speed);
    }
    std::vector<McAxis*> group;
    for (auto& a : axes_) group.push_back(a.get());
    for (auto& a : axes_) a->set_group(group);
    line_.AxisX = circle_.AxisX = axes_[0].get();
    line_.AxisY = circle_.AxisY = axes_[1].get();
    SC_HAS_PROCESS(MotionController);
    SC_THREAD(first_pulse_watch);
}

void MotionController::spend(const sc_core::sc_time& t) {
    if (t == sc_core::SC_ZERO_TIME) return;
    if (sc_core::sc_get_current_process_handle().proc_kind() != sc_core::SC_THREAD_PROC_) {
        deferred_cost_ += t;
        return;
    }
    sc_core::wait(t);
}

void MotionController::call_block(McExecuteFb& fb) {
    fb.call();
    fb_time_ += cfg_.cost.fb_call;
    spend(cfg_.cost.fb_call);
}

void MotionController::note_move(const std::string& token) {
    if (moves_.size() >= kMaxMoveRecords) return;
    moves_.push_back(MoveRecord{token, sc_core::sc_time_stamp(), std::nullopt});
    move_accepted_.notify(sc_core::SC_ZERO_TIME);
}

// Command latency: from the accepted move, the pulse counters are polled every first_pulse_poll
// until one moves (at most 1 s: a move that never pulses stays unmeasured). The figure is exact
// to one poll interval.
void MotionController::first_pulse_watch() {
    if (cfg_.first_pulse_poll == sc_core::SC_ZERO_TIME) return;
    std::size_t next = 0;
    for (;;) {
        while (next >= moves_.size()) sc_core::wait(move_accepted_);
        std::array<std::int64_t, axes> at{};
        for (unsigned a = 0; a < axes; ++a) at[a] = chip_.pulse_count(a);
        const sc_core::sc_time give_up = sc_core::sc_time_stamp() + sc_core::sc_time(1, sc_core::SC_SEC);
        while (sc_core::sc_time_stamp() < give_up && next + 1 >= moves_.size()) {
            sc_core::wait(cfg_.first_pulse_poll);
            bool moved = false;
            for (unsigned a = 0; a < axes; ++a) moved |= chip_.pulse_count(a) != at[a];
            if (moved) {
                moves_[next].first_pulse = sc_core::sc_time_stamp();
                break;
            }
        }
        ++next; // a newer move before the first pulse: the older one is left unmeasured
    }
}

std::array<double, 2> MotionController::csp_point(const sc_core::sc_time& t) const {
    const MotionConfig::Csp& c = *cfg_.csp;
    const double s = t > c.start ? (t - c.start).to_seconds() : 0.0;
    const double phi = c.velocity * s / c.radius; // CCW around (-R, 0), from (0, 0)
    return {-c.radius + c.radius * std::cos(phi), c.radius * std::sin(phi)};
}

// The planner's time is the ideal cycle start (the cycle it belongs to), not when the cycle got
// the processor: the set-point is for this period's SYNC instant. Whether the drive takes it
// depends on when it is written, after the work of the cycle so far.
void MotionController::csp_cycle() {
    const MotionConfig::Csp& c = *cfg_.csp;
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    const auto k = static_cast<std::uint64_t>(now / c.period);
    const sc_core::sc_time sync = c.period * static_cast<double>(k) + c.sync_offset;
    if (!csp_running_) {
        if (now < c.start) return;
        for (unsigned a : {c.axis_x, c.axis_y}) drives_[a].set_mode(mode::csp);
        csp_running_ = true;
        csp_latched_ = csp_written_ = {0, 0};
    }
    const std::array<double, 2> want = csp_point(sync);
    const std::array<std::int32_t, 2> sp = {static_cast<std::int32_t>(std::lround(want[0])),
                                            static_cast<std::int32_t>(std::lround(want[1]))};
    fb_time_ += cfg_.cost.fb_call; // the set-point computation: one block call
    spend(cfg_.cost.fb_call);
    ++csp_stats_.setpoints;
    // At its SYNC the drive takes what 0x607A holds: this set-point, or if it came too late the
    // one written in the cycle before.
    const bool missed = sc_core::sc_time_stamp() > sync;
    if (!missed) csp_latched_ = sp;
    else csp_latched_ = csp_written_, ++csp_stats_.missed;
    csp_written_ = sp;
    double error = 0;
    for (unsigned i = 0; i < 2; ++i) {
        drives_[i == 0 ? c.axis_x : c.axis_y].target_position = csp_latched_[i];
        error = std::max(error, std::abs(csp_latched_[i] - want[i]));
    }
    csp_stats_.max_setpoint_error = std::max(csp_stats_.max_setpoint_error, error);
    if (missed && !csp_stats_.first_miss)
        csp_stats_.first_miss = CspStats::Miss{sync, sc_core::sc_time_stamp(), cycle_ideal_, cycle_start_, cycle_held_by_, error};
    const double ax = double(drives_[c.axis_x].actual_position()), ay = double(drives_[c.axis_y].actual_position());
    csp_stats_.max_actual_radial_error =
        std::max(csp_stats_.max_actual_radial_error, std::abs(std::hypot(ax + c.radius, ay) - c.radius));
}

void MotionController::cycle_context(const sc_core::sc_time& ideal, const std::string& held_by) {
    cycle_ideal_ = ideal;
    cycle_held_by_ = held_by;
    context_given_ = true;
}

MotionSnapshot MotionController::snapshot() const {
    MotionSnapshot s;
    s.t_s = sc_core::sc_time_stamp().to_seconds();
    for (unsigned a = 0; a < axes; ++a) {
        s.cmd[a] = chip_.command_position(a);
        s.act[a] = chip_.encoder_position(a);
        s.axis_state[a] = axes_[a]->state();
    }
    s.state = state();
    return s;
}

MotionController::~MotionController() = default;

void MotionController::update_mechanism() {
    // The switches are the chip's sensors (positions, acted on at their exact times); only the
    // drive's ALM output is a level sampled here, once per control cycle.
    for (unsigned a = 0; a < axes; ++a)
        if (chip_.pin(a, camc::Pin::alarm) != drives_[a].alarm_output())
            chip_.set_pin(a, camc::Pin::alarm, drives_[a].alarm_output());
}

void MotionController::control_cycle(const sc_core::sc_time& now) {
    if (!context_given_) cycle_ideal_ = now, cycle_held_by_.clear(); // called without the main CPU
    context_given_ = false;
    cycle_start_ = now;
    if (deferred_cost_ > sc_core::SC_ZERO_TIME) {
        const sc_core::sc_time t = deferred_cost_;
        deferred_cost_ = sc_core::SC_ZERO_TIME;
        spend(t);
    }
    const double dt = first_cycle_ ? 0.0 : (now - last_).to_seconds();
    first_cycle_ = false;
    last_ = now;
    for (unsigned a = 0; a < axes; ++a) {
        Cia402Drive& d = drives_[a];
        d.set_pulse_input(chip_.pulse_count(a));
        d.set_alarm_reset_input(chip_.alarm_reset(a));
        d.update(dt);
    }
    update_mechanism();
    for (auto& ax : axes_) ax->cycle();
    // The set-point first: it is due at this period's SYNC, the blocks' work is not. Written after
    // them it missed the SYNC whenever a late start (the INT_R handler holding the processor) and
    // the cycle's block calls together passed the SYNC offset.
    if (cfg_.csp) csp_cycle();
    run_blocks();
    if (circle_record_ && !circle_record_->outcome_at && (circle_.Done || circle_.Error || circle_.CommandAborted))
        circle_record_->outcome_at = sc_core::sc_time_stamp();
    if (cfg_.record) {
        std::vector<std::int64_t> cmd(axes), act(axes);
        for (unsigned a = 0; a < axes; ++a) {
            cmd[a] = chip_.command_position(a);
            act[a] = chip_.encoder_position(a);
        }
        if (csp_running_) cmd[cfg_.csp->axis_x] = csp_latched_[0], cmd[cfg_.csp->axis_y] = csp_latched_[1];
        recorder_.add(now.to_seconds(), std::move(cmd), std::move(act));
        // The circle the checks judge is kept whole, to its outcome's sample (trajectory.h).
        if (circle_record_ && circle_record_->outcome_at) recorder_.end_window();
    }
}

void MotionController::run_blocks() {
    auto run = [this](McExecuteFb& fb) {
        call_block(fb);
        // The token "program" drops Execute once the block reports an outcome.
        if ((fb.Done || fb.Error || fb.CommandAborted) && auto_.erase(&fb)) fb.Execute = false;
    };
    for (unsigned a = 0; a < axes; ++a) {
        power_[a].call();
        fb_time_ += cfg_.cost.fb_call;
        spend(cfg_.cost.fb_call);
        Blocks& b = blocks_[a];
        for (McExecuteFb* fb : std::initializer_list<McExecuteFb*>{&b.reset, &b.home, &b.move_abs, &b.move_rel, &b.move_vel, &b.halt})
            run(*fb);
        // MC_SetPosition acts at Execute's edge and is Done at once: called only while a command
        // of it is pending, so that the layer's cycle costs what it did without it.
        if (b.set_pos.Execute || b.set_pos.Done || b.set_pos.Error) run(b.set_pos);
        call_block(b.stop);
        if ((b.stop.Done || b.stop.Error) && auto_.erase(&b.stop)) b.stop.Execute = false;
    }
    run(line_);
    run(line_n_);
    run(circle_);
}

std::vector<std::int64_t> MotionController::positions() const {
    std::vector<std::int64_t> p(axes);
    for (unsigned a = 0; a < axes; ++a) p[a] = chip_.encoder_position(a);
    return p;
}

std::string MotionController::state() const {
    // The most significant axis state (errors first).
    static constexpr AxisState order[] = {AxisState::error_stop, AxisState::stopping, AxisState::homing,
                                          AxisState::synchronized_motion, AxisState::discrete_motion,
                                          AxisState::continuous_motion, AxisState::standstill, AxisState::disabled};
    for (AxisState s : order)
        for (const auto& a : axes_)
            if (a->state() == s) return to_string(s);
    return "DISABLED";
}

MotionReply MotionController::fb_reply(std::uint16_t e) const {
    switch (e) {
    case err::none: return {0x00, ""};
    case axl::in_motion: return {0x03, ""};
    case err::axis_disabled: case err::wrong_state: case err::axis_stopping: return {0x04, std::to_string(e)};
    case err::axis_error_stop: case err::limit_positive: case err::limit_negative: case err::drive_fault:
    case err::emergency_stop: case err::home_not_found: return {0x05, std::to_string(e)};
    default: return {0x02, std::to_string(e)};
    }
}

template <typename Fb> MotionReply MotionController::execute_now(Fb& fb) {
    // A falling edge first: a previous command on this block (or one just released whose block
    // has not yet been called with Execute low) must not swallow the new rising edge.
    fb.Execute = false;
    call_block(fb);
    fb.Execute = true;
    call_block(fb);
    if (fb.Error) {
        fb.Execute = false;
        return fb_reply(fb.ErrorID);
    }
    auto_release(fb);
    return {0x00, ""};
}

namespace {
/// The comma-separated fields of a token's data. Positions, distances and centres are decimal
/// integers, read as integers (never through a floating-point type: a float loses pulses above
/// 2^24); speeds and rates are decimal numbers.
class Fields {
public:
    explicit Fields(const std::string& data) {
        std::stringstream ss(data);
        std::string f;
        while (std::getline(ss, f, ',')) f_.push_back(f);
        if (!data.empty() && data.back() == ',') f_.emplace_back();
    }
    std::size_t size() const { return f_.size(); }
    bool number(std::size_t i, double& out) const {
        std::size_t used = 0;
        try {
            out = std::stod(f_.at(i), &used);
        } catch (const std::exception&) {
            return false;
        }
        return used == f_[i].size() && std::isfinite(out);
    }
    bool integer(std::size_t i, std::int64_t& out) const {
        const std::string& f = f_.at(i);
        const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), out);
        return ec == std::errc() && ptr == f.data() + f.size() && !f.empty();
    }

private:
    std::vector<std::string> f_;
};

bool parse_mask(const std::string& data, unsigned& mask) {
    const Fields f(data);
    std::int64_t v = 0;
    if (f.size() != 1 || !f.integer(0, v) || v < 1 || v > 15) return false;
    mask = static_cast<unsigned>(v);
    return true;
}

bool in_chip_range(std::int64_t p) { return p >= -camc::max_coordinate && p <= camc::max_coordinate; }
} // namespace

MotionReply MotionController::home(unsigned mask, double velocity) {
    for (unsigned a = 0; a < axes; ++a) {
        if (!(mask & (1u << a))) continue;
        blocks_[a].home.Velocity = velocity;
        if (MotionReply r = execute_now(blocks_[a].home); r.bch) return r;
    }
    return {0x00, ""};
}

MotionReply MotionController::command(const std::string& token, const std::string& data) {
    std::optional<CircleRecord> arc;
    if (token == "MC") {
        arc = CircleRecord{};
        arc->at = sc_core::sc_time_stamp();
        arc->start_x = static_cast<double>(chip_.command_position(0));
        arc->start_y = static_cast<double>(chip_.command_position(1));
    }
    MotionReply r = execute(token, data);
    if (r.bch == 0 && starts_move(token)) note_move(token);
    if (r.bch == 0 && arc) {
        arc->center_x = arc->start_x + circle_.CenterX, arc->center_y = arc->start_y + circle_.CenterY;
        arc->end_x = arc->start_x + circle_.EndX, arc->end_y = arc->start_y + circle_.EndY;
        arc->ccw = circle_.Direction == dir_ccw;
        circle_record_ = arc;
        recorder_.start_window();
    }
    return r;
}

MotionReply MotionController::execute(const std::string& token, const std::string& data) {
    const MotionReply bad{0x02, "bad data: '" + data + "'"};
    const MotionReply out_of_range{0x02, std::to_string(err::position_out_of_bound)};
    const Fields f(data);
    // Reads `count` fields: integers where `ints` has a 1 (positions, centres, distances, axes),
    // decimal numbers elsewhere.
    std::vector<std::int64_t> iv;
    std::vector<double> nv;
    auto read = [&](std::size_t count, const std::vector<bool>& ints) {
        if (f.size() != count) return false;
        iv.assign(count, 0);
        nv.assign(count, 0);
        for (std::size_t i = 0; i < count; ++i)
            if (ints[i] ? !f.integer(i, iv[i]) : !f.number(i, nv[i])) return false;
        return true;
    };
    if (token == "SV") {
        if (data != "0" && data != "1") return bad;
        for (auto& p : power_) p.Enable = data == "1";
        return {0x00, ""};
    }
    if (token == "HM" && f.size() == 2) { // HM mask,velocity: the search velocity
        unsigned mask = 0;
        double vel = 0;
        if (!parse_mask(data.substr(0, data.find(',')), mask) || !f.number(1, vel)) return bad;
        return home(mask, vel);
    }
    if (token == "HM" || token == "RS") {
        unsigned mask = 0;
        if (!parse_mask(data, mask)) return bad;
        if (token == "HM") return home(mask, MC_Home{}.Velocity); // the AXL default, 10 kpps
        for (unsigned a = 0; a < axes; ++a) {
            if (!(mask & (1u << a))) continue;
            MotionReply r = execute_now(blocks_[a].reset);
            if (r.bch) return r;
        }
        return {0x00, ""};
    }
    if (token == "MA" || token == "MR") {
        if (!read(5, {true, true, false, false, false})) return bad;
        if (iv[0] < 0 || iv[0] >= axes) return {0x02, "unknown axis " + std::to_string(iv[0])};
        const unsigned a = static_cast<unsigned>(iv[0]);
        if (token == "MA") {
            if (!in_chip_range(iv[1])) return out_of_range;
            auto& fb = blocks_[a].move_abs;
            fb.Position = static_cast<std::int32_t>(iv[1]);
            fb.Velocity = nv[2], fb.Acceleration = nv[3], fb.Deceleration = nv[4];
            return execute_now(fb);
        }
        // A distance reaches at most from one end of the range to the other.
        if (iv[1] < -2 * camc::max_coordinate || iv[1] > 2 * camc::max_coordinate) return out_of_range;
        auto& fb = blocks_[a].move_rel;
        fb.Distance = static_cast<std::int32_t>(iv[1]);
        fb.Velocity = nv[2], fb.Acceleration = nv[3], fb.Deceleration = nv[4];
        return execute_now(fb);
    }
    if (token == "MV") {
        if (!read(4, {true, false, false, false})) return bad;
        if (iv[0] < 0 || iv[0] >= axes) return {0x02, "unknown axis " + std::to_string(iv[0])};
        auto& fb = blocks_[static_cast<unsigned>(iv[0])].move_vel;
        fb.Velocity = nv[1], fb.Acceleration = nv[2], fb.Deceleration = nv[3];
        fb.Direction = McDirection::positive; // the sign of the velocity gives the direction
        return execute_now(fb);
    }
    if (token == "ML") {
        if (!read(5, {true, true, false, false, false})) return bad;
        if (!in_chip_range(iv[0]) || !in_chip_range(iv[1])) return out_of_range;
        // Absolute targets on axes 0/1 for the host; the block takes them relative (both within
        // +-(2^30 - 1), so the difference fits 32 bits).
        line_.X = static_cast<std::int32_t>(iv[0] - chip_.command_position(0));
        line_.Y = static_cast<std::int32_t>(iv[1] - chip_.command_position(1));
        line_.Velocity = nv[2], line_.Acceleration = nv[3], line_.Deceleration = nv[4];
        return execute_now(line_);
    }
    if (token == "LM") { // LM mask,p...,vel,acc,dec: absolute targets of the 2-4 axes in the mask
        std::int64_t m = 0;
        if (f.size() < 1 || !f.integer(0, m) || m < 1 || m > 15) return bad;
        std::vector<unsigned> ids;
        for (unsigned a = 0; a < axes; ++a)
            if (m & (1 << a)) ids.push_back(a);
        if (ids.size() < 2) return {0x02, "LM needs 2-4 axes in its mask, got " + std::to_string(m)};
        std::vector<bool> ints(ids.size() + 4, true);
        ints[ids.size() + 1] = ints[ids.size() + 2] = ints[ids.size() + 3] = false;
        if (!read(ids.size() + 4, ints)) return bad;
        line_n_.Axes.clear();
        line_n_.Distances.clear();
        for (std::size_t i = 0; i < ids.size(); ++i) {
            if (!in_chip_range(iv[i + 1])) return out_of_range;
            line_n_.Axes.push_back(axes_[ids[i]].get());
            line_n_.Distances.push_back(static_cast<std::int32_t>(iv[i + 1] - chip_.command_position(ids[i])));
        }
        line_n_.Velocity = nv[ids.size() + 1], line_n_.Acceleration = nv[ids.size() + 2];
        line_n_.Deceleration = nv[ids.size() + 3];
        return execute_now(line_n_);
    }
    if (token == "MC") {
        if (!read(6, {true, true, true, true, true, false})) return bad;
        if (iv[4] != 0 && iv[4] != 1) return bad;
        for (int i = 0; i < 4; ++i)
            if (!in_chip_range(iv[i])) return out_of_range;
        const std::int64_t x = chip_.command_position(0), y = chip_.command_position(1);
        circle_.CenterX = static_cast<std::int32_t>(iv[0] - x), circle_.CenterY = static_cast<std::int32_t>(iv[1] - y);
        circle_.EndX = static_cast<std::int32_t>(iv[2] - x), circle_.EndY = static_cast<std::int32_t>(iv[3] - y);
        circle_.Direction = iv[4] == 1 ? dir_cw : dir_ccw;
        circle_.Velocity = nv[5];
        circle_.Acceleration = circle_.Deceleration = 10 * nv[5]; // ramps of 0.1 s
        return execute_now(circle_);
    }
    if (token == "ES") {
        // Every axis, moving or not, latches ErrorStop until RS (docs/motion.md).
        axes_[0]->emergency_stop_all();
        return {0x00, ""};
    }
    return {0x01, "unknown token " + token};
}

} // namespace rcsim::motion
