// rcsim — CAMC-QI 4-axis pulse/interpolation motion chip. See camc_qi.h and README.md.
#include "camc_qi/camc_qi.h"

#include "models/bus.h"
#include "models/clock.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace rcsim::camc {

namespace {
constexpr std::uint64_t unlimited = std::numeric_limits<std::uint64_t>::max();
constexpr std::uint32_t abnormal = endst::pelm | endst::nelm | endst::alarm | endst::estop_signal |
                                   endst::estop_cmd | endst::interp_data | endst::data_error;
// A drive's step count is floor(position + eps): the profile's floating-point position lands a
// hair below an integer at the exact time that step is due.
constexpr double step_eps = 1e-7;

std::string hex(unsigned v) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%02X", v);
    return buf;
}

bool is_interpolation(std::uint32_t mode) { return mode >= dcfg::linear; }
} // namespace

/// A drive in progress: a speed profile over steps, and how each member axis moves per step.
struct CamcQi::Drive {
    std::uint32_t mode = dcfg::preset;
    SpeedProfile profile;
    ProfileParams params;
    sc_core::sc_time start;
    std::uint64_t limit = unlimited; // total steps (unlimited for continuous and origin drives)
    std::uint32_t members = 0;       // axis mask
    std::array<std::int64_t, axes> base{};
    int dir = 1;                     // single-axis drives
    LinearPath line;
    std::array<int, axes> line_index{}; // axis -> index in `line`
    mutable CirclePath circle;
    unsigned cx = 0, cy = 1;         // circle axes
    std::uint32_t cause = 0;         // end-status bits of the stop cause (0 = normal end)
    double end_t = SpeedProfile::never; // seconds from start
    bool at_limit = false;           // the drive ends by reaching `limit`
    std::uint64_t stop_k = unlimited; // steps of a stop at a sensor edge's exact time
    std::array<std::int64_t, axes> origin{}; // pulse_count() of each member at the start
    // The next sensor edge that acts on the drive (plan_edges): drive time, step, axis, input.
    double edge_t = SpeedProfile::never;
    std::uint64_t edge_k = 0;
    unsigned edge_axis = 0;
    Pin edge_pin = Pin::pelm;
    // A signal search (modes 3/4) still looking for its edge.
    bool search = false;
    Pin search_pin = Pin::org;
    bool search_inactive = false, search_immediate = false;

    /// When the drive ends: its profile stops, or its last step is driven, whichever is first.
    void plan_end() {
        end_t = profile.end_time();
        at_limit = false;
        if (limit == unlimited) return;
        const double t_lim = profile.time_of(static_cast<double>(limit) - step_eps);
        if (t_lim <= end_t) {
            end_t = t_lim;
            at_limit = true;
        } else if (end_t != SpeedProfile::never) {
            // A preset profile planned over exactly `limit` steps ends a rounding error short.
            const double lim = static_cast<double>(limit);
            at_limit = profile.position(end_t) >= lim - std::max(1e-6, 1e-9 * lim);
        }
    }

    double rel(const sc_core::sc_time& now) const { return (now - start).to_seconds(); }
    /// The drive's end in kernel time: the one place a profile time becomes an sc_time, rounded
    /// up to the 1 ps resolution so that at that instant every step is due.
    sc_core::sc_time end_abs() const { return abs(end_t); }
    sc_core::sc_time edge_abs() const { return abs(edge_t); }
    sc_core::sc_time abs(double t) const { return start + ps(static_cast<std::uint64_t>(std::ceil(t * 1e12))); }

    std::uint64_t steps_at(const sc_core::sc_time& now) const { return steps_rel(rel(now)); }
    std::uint64_t steps_rel(double t) const {
        if (t >= end_t && stop_k != unlimited) return stop_k; // stopped at a sensor edge
        if (t >= end_t && at_limit) return limit; // a normal end: every step was driven
        t = std::min(t, end_t);
        const double s = std::floor(profile.position(t) + step_eps);
        if (s <= 0) return 0;
        return std::min<std::uint64_t>(static_cast<std::uint64_t>(s), limit);
    }

    std::int64_t offset(unsigned axis, std::uint64_t k) const {
        switch (mode) {
        case dcfg::linear: return line.position(static_cast<unsigned>(line_index[axis]), k);
        case dcfg::circle_cw:
        case dcfg::circle_ccw: {
            const Point p = circle.at(k), s = circle.start();
            return axis == cx ? p.x - s.x : p.y - s.y;
        }
        default: return dir * static_cast<std::int64_t>(k);
        }
    }

    /// Sign of the axis' motion at step k (for the limit inputs).
    int direction(unsigned axis, std::uint64_t k) const {
        switch (mode) {
        case dcfg::linear: {
            const std::int64_t d = line.delta(static_cast<unsigned>(line_index[axis]));
            return d > 0 ? 1 : (d < 0 ? -1 : 0);
        }
        case dcfg::circle_cw:
        case dcfg::circle_ccw: {
            // Tangent of the circle at the current point: CCW (-y, x), CW (y, -x).
            const Point p = circle.at(k);
            std::int64_t v = axis == cx ? -p.y : p.x;
            if (mode == dcfg::circle_cw) v = -v;
            return v > 0 ? 1 : (v < 0 ? -1 : 0);
        }
        default: return dir;
        }
    }
};

CamcQi::CamcQi(sc_core::sc_module_name name, unsigned wait_states)
    : sc_module(name), socket("socket"), irq("irq"), wait_states_(wait_states), wake_("wake"),
      drive_ev_("drive_ev") {
    socket.register_b_transport(this, &CamcQi::b_transport);
    SC_HAS_PROCESS(CamcQi);
    SC_METHOD(settle);
    sensitive << wake_;
    dont_initialize();
}

CamcQi::~CamcQi() = default;

CamcQi::Axis& CamcQi::ax(unsigned a) {
    if (a >= axes) throw std::out_of_range("CAMC-QI: axis " + std::to_string(a) + " does not exist (0..3)");
    return ax_[a];
}
const CamcQi::Axis& CamcQi::ax(unsigned a) const {
    if (a >= axes) throw std::out_of_range("CAMC-QI: axis " + std::to_string(a) + " does not exist (0..3)");
    return ax_[a];
}

// ---------------------------------------------------------------------------------------------
// Bus interface

void CamcQi::b_transport(tlm::tlm_generic_payload& gp, sc_core::sc_time&) {
    BusView ext(gp, false);
    const std::uint64_t addr = gp.get_address();
    const unsigned len = gp.get_data_length();
    if (len == 0 || len > 4 || addr + len > win::size || gp.get_byte_enable_ptr()) {
        gp.set_response_status(len > 4 ? tlm::TLM_BURST_ERROR_RESPONSE : tlm::TLM_ADDRESS_ERROR_RESPONSE);
        return;
    }
    std::uint8_t* data = gp.get_data_ptr();
    // Bytes in ascending address order: a 32-bit write of DATA completes before a following
    // command byte, and a command written with DATA in one access executes last.
    for (unsigned i = 0; i < len; ++i) {
        const unsigned off = static_cast<unsigned>(addr) + i;
        if (gp.is_write())
            write_byte(off, data[i]);
        else
            data[i] = read_byte(off);
    }
    ext->wait_states = wait_states_;
    gp.set_response_status(tlm::TLM_OK_RESPONSE);
}

std::uint8_t CamcQi::read_byte(unsigned off) {
    if (off == win::irq_pending) {
        std::uint8_t m = 0;
        for (unsigned a = 0; a < axes; ++a)
            if (ax_[a].iflag & ax_[a].imask1) m |= static_cast<std::uint8_t>(1u << a);
        return m;
    }
    if (off == win::chip_id) return 0x06;
    if (off >= 0x40) return 0;
    const unsigned a = off / win::stride, f = off % win::stride;
    auto byte_of = [](std::uint32_t v, unsigned i) { return static_cast<std::uint8_t>(v >> (8 * i)); };
    if (f < 4) return byte_of(ax_[a].data, f);
    if (f == win::command) return ax_[a].last_cmd;
    if (f == win::drive_status || f == win::drive_status + 1) return byte_of(drive_status(a), f - win::drive_status);
    if (f == win::end_status || f == win::end_status + 1) return byte_of(ax_[a].end_status, f - win::end_status);
    if (f == win::mech_status || f == win::mech_status + 1) return byte_of(mech_status(a), f - win::mech_status);
    return 0;
}

void CamcQi::write_byte(unsigned off, std::uint8_t v) {
    if (off >= 0x40) return; // global registers are read-only
    const unsigned a = off / win::stride, f = off % win::stride;
    if (f < 4) {
        const unsigned sh = 8 * f;
        ax_[a].data = (ax_[a].data & ~(0xFFu << sh)) | (std::uint32_t{v} << sh);
    } else if (f == win::command) {
        ax_[a].last_cmd = v;
        execute(a, v);
    }
}

// ---------------------------------------------------------------------------------------------
// Commands and registers

void CamcQi::command(unsigned axis, std::uint8_t code, std::uint32_t data) {
    ax(axis).data = data;
    ax(axis).last_cmd = code;
    execute(axis, code);
}

std::uint32_t CamcQi::read_register(unsigned axis, std::uint8_t code) {
    command(axis, code, 0);
    return ax(axis).data;
}

void CamcQi::execute(unsigned axis, std::uint8_t code) {
    Axis& a = ax(axis);
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    switch (code) {
    case qi::STRN: start(axis); break;
    case qi::SSTOP:
        if (a.drive) {
            // The ramp down uses RATE2 as it is now (the host may lower it for this stop).
            const ProfileParams now = params(a, false);
            a.drive->params.decel = now.decel;
            a.drive->params.decel_jerk = now.decel_jerk;
            stop_drive(a.drive, true, endst::slowdown_cmd);
        }
        break;
    case qi::STOP:
        if (a.drive) stop_drive(a.drive, false, endst::stop_cmd);
        break;
    case qi::ESTOP:
        for (Axis& x : ax_)
            if (x.drive) stop_drive(x.drive, false, endst::estop_cmd);
        break;
    case qi::SWRESET:
        for (Axis& x : ax_)
            if (x.drive) stop_drive(x.drive, false, 0);
        for (Axis& x : ax_) {
            auto pins = x.pins;
            auto enc = std::move(x.encoder);
            const bool tr = x.trace;
            x = Axis{};
            x.pins = pins;
            x.encoder = std::move(enc);
            x.trace = tr;
        }
        break;
    case qi::INTGEN: a.iflag |= intf::user; break;
    case qi::ESCLR: a.end_status = 0; break;
    case qi::IFCLR1: a.iflag &= ~a.data; break;
    default:
        if (code & qi::write)
            write_register(axis, static_cast<std::uint8_t>(code & 0x7F), a.data);
        else
            a.data = [&]() -> std::uint32_t {
                switch (code) {
                case qi::RANGE: return a.range;
                case qi::STD: return a.std_speed;
                case qi::OBJ: return a.obj;
                case qi::RATE1: return a.rate1;
                case qi::RATE2: return a.rate2;
                case qi::SW1: return a.sw1;
                case qi::SW2: return a.sw2;
                case qi::DCFG: return a.dcfg;
                case qi::POS: return static_cast<std::uint32_t>(a.pos);
                case qi::CENT: return static_cast<std::uint32_t>(a.cent);
                case qi::ISNUM: return a.isnum;
                case qi::REMAIN: return static_cast<std::uint32_t>(a.remain);
                case qi::UIO: return a.uio;
                case qi::OBJORG: return a.objorg;
                case qi::CURSPD: return static_cast<std::uint32_t>(std::lround(current_speed(axis)));
                case qi::DRPCNT: return static_cast<std::uint32_t>(a.driven);
                case qi::CNT1: return static_cast<std::uint32_t>(command_position(axis));
                case qi::CNT2: return static_cast<std::uint32_t>(encoder_position(axis));
                case qi::CNT3: return static_cast<std::uint32_t>(command_position(axis) - encoder_position(axis));
                case qi::UCFG1: return a.ucfg1;
                case qi::IMASK1: return a.imask1;
                case qi::STAT1: return a.end_status;
                case qi::STAT2: return drive_status(axis);
                case qi::STAT3: return mech_status(axis);
                case qi::IFLAG1: return a.iflag;
                default:
                    SC_REPORT_WARNING(name(), ("read command code " + hex(code) + " is not modelled").c_str());
                    return 0;
                }
            }();
    }
    (void)now;
    wake_.notify(sc_core::SC_ZERO_TIME); // INT may change
}

void CamcQi::write_register(unsigned axis, std::uint8_t reg, std::uint32_t v) {
    Axis& a = ax(axis);
    switch (reg) {
    case qi::RANGE: a.range = v; break;
    case qi::STD: a.std_speed = v; break;
    case qi::OBJ: a.obj = v; break;
    case qi::RATE1: a.rate1 = v; break;
    case qi::RATE2: a.rate2 = v; break;
    case qi::SW1: a.sw1 = v; break;
    case qi::SW2: a.sw2 = v; break;
    case qi::DCFG: a.dcfg = v; break;
    case qi::POS: a.pos = static_cast<std::int32_t>(v); break;
    case qi::CENT: a.cent = static_cast<std::int32_t>(v); break;
    case qi::ISNUM: a.isnum = v; break;
    case qi::UIO: a.uio = v & 0x3; break;
    case qi::OBJORG: a.objorg = v; break;
    case qi::CNT1:
        // Presetting the command counter while pulsing would tear the path: the chip ignores it.
        if (!a.drive) {
            a.preset_shift += static_cast<std::int32_t>(v) - a.cnt1;
            a.cnt1 = static_cast<std::int32_t>(v);
        }
        break;
    case qi::CNT2: {
        const std::int64_t raw = a.encoder ? a.encoder() : command_position(axis);
        a.enc_offset = static_cast<std::int32_t>(v) - raw;
        break;
    }
    case qi::UCFG1:
        a.ucfg1 = v;
        check_inputs(axis);
        if (a.drive) plan_edges(*a.drive);
        schedule();
        break;
    case qi::IMASK1: a.imask1 = v; break;
    default:
        SC_REPORT_WARNING(name(), ("write command code " + hex(reg | qi::write) + " is not modelled").c_str());
    }
}

ProfileParams CamcQi::params(const Axis& a, bool origin) const {
    ProfileParams p;
    const double r = a.range;
    p.start_speed = a.std_speed * r;
    p.object_speed = (origin ? a.objorg : a.obj) * r;
    p.accel = a.rate1 * r;
    const unsigned prof = a.dcfg & dcfg::profile_mask;
    p.decel = (prof == 1 || prof == 3) ? a.rate2 * r : p.accel;
    if (prof >= 2) {
        p.accel_jerk = a.sw1 / 100.0;
        p.decel_jerk = (prof == 3 ? a.sw2 : a.sw1) / 100.0;
    }
    return p;
}

// ---------------------------------------------------------------------------------------------
// Drives

bool CamcQi::limit_active(const Axis& a, Pin p) const {
    const unsigned i = static_cast<unsigned>(&a - ax_.data());
    return active_at(i, p, pulse_count(i));
}

/// The electrical level of an input with the axis at `pos`: the set_pin level, or high while a
/// sensor has the axis in its range.
bool CamcQi::level(unsigned axis, Pin p, std::int64_t pos) const {
    const Axis& a = ax_[axis];
    if (a.pins[static_cast<unsigned>(p)]) return true;
    const Sensors& s = a.sensors;
    switch (p) {
    case Pin::pelm: return s.pelm && pos >= *s.pelm;
    case Pin::nelm: return s.nelm && pos <= *s.nelm;
    case Pin::org: return s.org && pos <= *s.org;
    case Pin::zphase: return s.z_pitch > 0 && ((pos - s.z_offset) % s.z_pitch + s.z_pitch) % s.z_pitch == 0;
    default: return false;
    }
}

bool CamcQi::active_at(unsigned axis, Pin p, std::int64_t pos) const {
    const Axis& a = ax_[axis];
    const bool lvl = level(axis, p, pos);
    switch (p) {
    case Pin::pelm: return (a.ucfg1 & ucfg::pelm_used) && lvl == bool(a.ucfg1 & ucfg::pelm_high);
    case Pin::nelm: return (a.ucfg1 & ucfg::nelm_used) && lvl == bool(a.ucfg1 & ucfg::nelm_high);
    case Pin::alarm: return (a.ucfg1 & ucfg::alarm_used) && lvl == bool(a.ucfg1 & ucfg::alarm_high);
    case Pin::org: return lvl == bool(a.ucfg1 & ucfg::org_high);
    default: return lvl;
    }
}

/// The conditions that refuse a start (AXL 4169 MOVE_SENSOR_CHECK): alarm, ESTOP, or a limit
/// switch active in the direction of motion. Sets the end status of the axis that refuses.
bool CamcQi::start_check(unsigned axis, int dir, bool limits) {
    Axis& a = ax_[axis];
    std::uint32_t why = 0;
    if (limit_active(a, Pin::alarm)) why |= endst::alarm;
    if (estop_pin_) why |= endst::estop_signal;
    if (limits && dir >= 0 && limit_active(a, Pin::pelm)) why |= endst::pelm;
    if (limits && dir <= 0 && limit_active(a, Pin::nelm)) why |= endst::nelm;
    if (!why) return true;
    a.end_status = why;
    a.iflag |= intf::error_stop;
    return false;
}

void CamcQi::start(unsigned axis) {
    Axis& m = ax_[axis];
    const std::uint32_t mode = (m.dcfg & dcfg::mode_mask) >> dcfg::mode_shift;
    const std::uint32_t members = is_interpolation(mode) ? (m.dcfg >> dcfg::axes_shift) & 0xF : (1u << axis);
    auto refuse = [&](std::uint32_t why) {
        for (unsigned i = 0; i < axes; ++i)
            if ((members | (1u << axis)) & (1u << i)) {
                ax_[i].end_status = why;
                ax_[i].iflag |= intf::error_stop;
            }
    };
    // A start while any member is still driving is ignored (AXL 4152 ERROR_IN_MOTION); the
    // host must wait for BUSY to fall (the pre-register queue is not modelled).
    for (unsigned i = 0; i < axes; ++i)
        if ((members & (1u << i)) && ax_[i].drive) {
            SC_REPORT_WARNING(name(), ("start on axis " + std::to_string(axis) + " ignored: axis " +
                                       std::to_string(i) + " is busy").c_str());
            return;
        }

    auto d = std::make_shared<Drive>();
    d->mode = mode;
    d->members = members;
    d->start = sc_core::sc_time_stamp();
    const bool origin = mode == dcfg::origin_pos || mode == dcfg::origin_neg;
    d->params = params(m, origin);
    const ProfileParams& p = d->params;
    if (!(members & (1u << axis)) || !(p.start_speed >= 1) || !(p.object_speed >= 1) || !(p.accel >= 1) ||
        !(p.decel >= 1) || p.object_speed > max_pps || p.start_speed > max_pps || m.sw1 > 100 || m.sw2 > 100) {
        refuse(endst::data_error);
        return;
    }

    std::uint64_t distance = 0;
    try {
        switch (mode) {
        case dcfg::preset:
            d->dir = m.pos < 0 ? -1 : 1;
            d->limit = distance = static_cast<std::uint64_t>(std::llabs(m.pos));
            break;
        case dcfg::cont_pos: case dcfg::origin_pos: d->dir = 1; break;
        case dcfg::cont_neg: case dcfg::origin_neg: d->dir = -1; break;
        case dcfg::linear: {
            std::int64_t delta[axes];
            unsigned n = 0;
            for (unsigned i = 0; i < axes; ++i)
                if (members & (1u << i)) {
                    d->line_index[i] = static_cast<int>(n);
                    delta[n++] = ax_[i].pos;
                }
            d->line = LinearPath(delta, n);
            d->limit = distance = d->line.steps();
            break;
        }
        default: { // circles: exactly two axes, the lower is X
            unsigned ids[axes], n = 0;
            for (unsigned i = 0; i < axes; ++i)
                if (members & (1u << i)) ids[n++] = i;
            if (n != 2) throw InterpolationError("circular interpolation needs exactly 2 axes in DCFG, got " +
                                                 std::to_string(n));
            d->cx = ids[0];
            d->cy = ids[1];
            const Axis &X = ax_[d->cx], &Y = ax_[d->cy];
            const Point s{-std::int64_t{X.cent}, -std::int64_t{Y.cent}};
            const Point e{std::int64_t{X.pos} - X.cent, std::int64_t{Y.pos} - Y.cent};
            d->circle = CirclePath(s, e, mode == dcfg::circle_cw ? ArcDirection::cw : ArcDirection::ccw);
            d->limit = distance = d->circle.steps();
        }
        }
    } catch (const InterpolationError& e) {
        SC_REPORT_INFO(name(), e.what());
        refuse(endst::interp_data | endst::data_error);
        return;
    }

    for (unsigned i = 0; i < axes; ++i)
        if (members & (1u << i)) {
            const int dir = (mode == dcfg::circle_cw || mode == dcfg::circle_ccw) ? 0 : d->direction(i, 0);
            // A search for a limit switch may start into that switch's side: it stops at it.
            const bool searched = origin && (d->search_pin == Pin::pelm || d->search_pin == Pin::nelm);
            if (!start_check(i, dir, !searched)) {
                refuse(ax_[i].end_status);
                return;
            }
        }
    if (origin) {
        static constexpr Pin signals[] = {Pin::org, Pin::zphase, Pin::pelm, Pin::nelm};
        d->search = true;
        d->search_pin = signals[(m.dcfg & dcfg::signal_mask) >> dcfg::signal_shift];
        d->search_inactive = m.dcfg & dcfg::search_inactive;
        d->search_immediate = m.dcfg & dcfg::search_immediate;
        if (limit_active(m, d->search_pin) != d->search_inactive) { // the edge is behind: found at once
            m.end_status = d->search_pin == Pin::org ? endst::home_ok : endst::signal_ok;
            m.iflag |= intf::drive_end;
            return;
        }
    }

    if (mode == dcfg::cont_pos || mode == dcfg::cont_neg || origin) {
        d->profile = SpeedProfile::continuous(p);
    } else if (is_interpolation(mode) && m.isnum != 0 && m.isnum != distance) {
        // Deceleration is planned over the host's QiISNUM, not over the real step count: too
        // small a number crawls on at STD, too large a number ends the drive still fast.
        d->profile = SpeedProfile::preset(p, static_cast<double>(m.isnum), true);
    } else {
        d->profile = SpeedProfile::preset(p, static_cast<double>(distance));
    }
    d->plan_end();

    for (unsigned i = 0; i < axes; ++i)
        if (members & (1u << i)) {
            Axis& a = ax_[i];
            d->base[i] = a.cnt1;
            d->origin[i] = a.cnt1 - a.preset_shift;
            a.drive = d;
            a.end_status = 0;
            a.iflag |= intf::drive_start;
        }
    drive_ev_.notify(sc_core::SC_ZERO_TIME);
    if (distance == 0 && d->limit != unlimited) {
        finish(d, d->start);
    } else {
        plan_edges(*d);
    }
    schedule();
}

void CamcQi::stop_drive(std::shared_ptr<Drive> d, bool slow, std::uint32_t cause) {
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    const double t = d->rel(now);
    if (t >= d->end_t) return; // ending this instant anyway
    d->cause |= cause;
    if (slow) {
        d->profile.slow_down(t, d->params);
        d->plan_end();
        plan_edges(*d);
    } else {
        d->profile.stop(t);
        d->end_t = t;
        d->at_limit = false;
    }
    if (d->end_t <= t)
        finish(d, now);
    else
        schedule();
}

void CamcQi::finish(std::shared_ptr<Drive> d, sc_core::sc_time at) {
    const std::uint64_t k = d->steps_at(at);
    for (unsigned i = 0; i < axes; ++i) {
        if (!(d->members & (1u << i))) continue;
        Axis& a = ax_[i];
        a.cnt1 = d->base[i] + d->offset(i, k);
        a.driven = static_cast<std::int64_t>(k);
        a.remain = (d->mode == dcfg::preset) ? static_cast<std::int64_t>(d->limit - k) : 0;
        a.end_status |= d->cause;
        a.iflag |= intf::drive_end | ((d->cause & abnormal) ? intf::error_stop : 0);
        a.drive.reset();
    }
    d->end_t = std::min(d->end_t, d->rel(at));
    bool traced = false;
    for (unsigned i = 0; i < axes; ++i) traced |= (d->members & (1u << i)) && ax_[i].trace;
    if (traced) record_trace(*d);
    drive_ev_.notify(sc_core::SC_ZERO_TIME);
    wake_.notify(sc_core::SC_ZERO_TIME);
}

void CamcQi::stop_at(std::shared_ptr<Drive> d, bool slow, std::uint32_t cause, double t, std::uint64_t k) {
    d->cause |= cause;
    if (slow) {
        d->profile.slow_down(t, d->params);
        d->plan_end();
        plan_edges(*d);
    } else {
        d->profile.stop(t);
        d->end_t = t;
        d->at_limit = false;
        d->stop_k = k;
    }
    if (d->end_t <= d->rel(sc_core::sc_time_stamp()))
        finish(d, sc_core::sc_time_stamp());
    else
        schedule();
}

// ---------------------------------------------------------------------------------------------
// Sensor edges: where an input changes along the drive's path, and when the profile gets there

/// The first position cur + dir*m (m >= 1) at which input `p` is active (`want`) or inactive,
/// given the sensor ranges, the configured levels and a set_pin level; none if never.
std::optional<std::int64_t> CamcQi::next_level(unsigned axis, Pin p, std::int64_t cur, int dir, bool want) const {
    const Axis& a = ax_[axis];
    const std::int64_t next = cur + dir;
    if (active_at(axis, p, next) == want) return next;
    if (a.pins[static_cast<unsigned>(p)]) return std::nullopt; // held high: the state never changes
    const Sensors& s = a.sensors;
    // Half-line sensors: the state changes once, at the range's edge (if motion goes that way).
    auto half = [&](const std::optional<std::int64_t>& edge, bool above) -> std::optional<std::int64_t> {
        if (!edge) return std::nullopt;
        const std::int64_t in = *edge, out = above ? *edge - 1 : *edge + 1; // first position in / out
        const std::int64_t target = active_at(axis, p, in) == want ? in : out;
        if (dir > 0 ? target > cur : target < cur) return target;
        return std::nullopt;
    };
    switch (p) {
    case Pin::pelm: return half(s.pelm, true);
    case Pin::nelm: return half(s.nelm, false);
    case Pin::org: return half(s.org, false);
    case Pin::zphase: {
        if (s.z_pitch <= 0 || !want) return s.z_pitch > 1 && !want ? std::optional(next + dir) : std::nullopt;
        const std::int64_t n = s.z_pitch, r = ((next - s.z_offset) % n + n) % n;
        return dir > 0 ? next + (n - r) % n : next - r; // the next lattice point in the direction of motion
    }
    default: return std::nullopt;
    }
}

/// The first step after `from` at which `axis` of drive `d` is at position q (pulse_count
/// coordinates); none if the path never gets there.
std::optional<std::uint64_t> CamcQi::step_reaching(const Drive& d, unsigned axis, std::int64_t q,
                                                   std::uint64_t from) const {
    const std::int64_t o = q - d.origin[axis];
    switch (d.mode) {
    case dcfg::linear: {
        // Every axis of a line moves monotonically: bisect over the steps.
        const unsigned idx = static_cast<unsigned>(d.line_index[axis]);
        const std::int64_t delta = d.line.delta(idx);
        if (o == 0 || (o > 0) != (delta > 0)) return std::nullopt;
        auto reach = [&](std::uint64_t k) { return std::llabs(d.line.position(idx, k)) >= std::llabs(o); };
        std::uint64_t lo = from + 1, hi = d.line.steps();
        if (lo > hi || !reach(hi)) return std::nullopt;
        while (lo < hi) {
            const std::uint64_t mid = lo + (hi - lo) / 2;
            if (reach(mid))
                hi = mid;
            else
                lo = mid + 1;
        }
        return lo;
    }
    case dcfg::circle_cw:
    case dcfg::circle_ccw: {
        // Not monotone: walk a copy of the path (only when q is within the circle's reach).
        const Point s0 = d.circle.start();
        const double r = std::sqrt(static_cast<double>(d.circle.radius_squared())) + 2;
        const double c = static_cast<double>(axis == d.cx ? -s0.x : -s0.y); // centre, relative to the start
        if (std::abs(static_cast<double>(o) - c) > r) return std::nullopt;
        CirclePath walk = d.circle;
        walk.at(0);
        for (std::uint64_t k = 1; k <= d.limit; ++k) {
            const Point p = walk.at(k);
            if (k > from && (axis == d.cx ? p.x - s0.x : p.y - s0.y) == o) return k;
        }
        return std::nullopt;
    }
    default: {
        if (o * d.dir <= 0) return std::nullopt;
        const auto k = static_cast<std::uint64_t>(o * d.dir);
        if (k <= from || k > d.limit) return std::nullopt;
        return k;
    }
    }
}

/// The next sensor edge that acts on `d`: a limit switch turning active in the direction of
/// motion (a circle may meet one going either way), or the edge a signal search looks for.
void CamcQi::plan_edges(Drive& d) const {
    d.edge_t = SpeedProfile::never;
    const double now = d.rel(sc_core::sc_time_stamp());
    if (now >= d.end_t) return;
    const std::uint64_t from = d.steps_rel(now);
    std::uint64_t best = unlimited;
    auto consider = [&](std::optional<std::uint64_t> k, unsigned axis, Pin p) {
        if (k && *k < best) best = *k, d.edge_axis = axis, d.edge_pin = p;
    };
    const bool circle = d.mode == dcfg::circle_cw || d.mode == dcfg::circle_ccw;
    for (unsigned i = 0; i < axes; ++i) {
        if (!(d.members & (1u << i))) continue;
        const std::int64_t cur = d.origin[i] + d.offset(i, from);
        for (Pin lim : {Pin::pelm, Pin::nelm}) {
            if (d.search && d.search_pin == lim) continue;
            if (active_at(i, lim, cur)) continue; // already on: it acted (or refused) already
            const int toward = lim == Pin::pelm ? 1 : -1;
            if (circle) {
                for (std::int64_t step : {std::int64_t{1}, std::int64_t{-1}})
                    if (auto q = next_level(i, lim, cur, static_cast<int>(step), true)) consider(step_reaching(d, i, *q, from), i, lim);
            } else if (d.direction(i, from) == toward) {
                if (auto q = next_level(i, lim, cur, toward, true)) consider(step_reaching(d, i, *q, from), i, lim);
            }
        }
        if (d.search && !circle)
            if (auto q = next_level(i, d.search_pin, cur, d.dir, !d.search_inactive))
                consider(step_reaching(d, i, *q, from), i, d.search_pin);
    }
    if (best == unlimited) return;
    d.edge_k = best;
    d.edge_t = std::max(now, d.profile.time_of(static_cast<double>(best) - step_eps));
    if (!(d.edge_t < d.end_t)) d.edge_t = SpeedProfile::never; // the drive ends first (or there)
}

/// A planned edge is due: stop at its exact time as the input's stop mode says.
void CamcQi::on_edge(std::shared_ptr<Drive> d) {
    const double t = d->edge_t;
    const std::uint64_t k = d->edge_k;
    const unsigned i = d->edge_axis;
    const Pin p = d->edge_pin;
    d->edge_t = SpeedProfile::never;
    if (d->search && p == d->search_pin) {
        d->search = false;
        stop_at(d, !d->search_immediate, p == Pin::org ? endst::home_ok : endst::signal_ok, t, k);
    } else {
        stop_at(d, ax_[i].ucfg1 & ucfg::limit_slowdown, p == Pin::pelm ? endst::pelm : endst::nelm, t, k);
    }
}

void CamcQi::record_trace(const Drive& d) {
    // Replays the drive: step k happens when the profile's position reaches k.
    const std::uint64_t n = d.steps_rel(d.end_t);
    Drive replay = d; // own copy of the circle walker, restarted from step 0
    std::array<std::int64_t, axes> prev{};
    for (std::uint64_t k = 1; k <= n; ++k) {
        const double t = replay.profile.time_of(static_cast<double>(k) - step_eps);
        const sc_core::sc_time at = d.start + ps(static_cast<std::uint64_t>(std::llround(t * 1e12)));
        for (unsigned i = 0; i < axes; ++i) {
            if (!(d.members & (1u << i)) || !ax_[i].trace) continue;
            const std::int64_t o = replay.offset(i, k);
            if (o != prev[i]) trace_.push_back({at, i, o > prev[i] ? 1 : -1});
            prev[i] = o;
        }
    }
}

void CamcQi::settle() {
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    for (unsigned i = 0; i < axes; ++i) {
        auto d = ax_[i].drive;
        if (d && d->edge_t != SpeedProfile::never && d->edge_abs() <= now) on_edge(d);
    }
    for (unsigned i = 0; i < axes; ++i) {
        auto d = ax_[i].drive;
        if (d && d->end_t != SpeedProfile::never && d->end_abs() <= now) finish(d, now);
    }
    bool pending = false;
    for (const Axis& a : ax_) pending |= (a.iflag & a.imask1) != 0;
    if (irq.read() != pending) irq.write(pending);
    schedule();
}

void CamcQi::schedule() {
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    std::optional<sc_core::sc_time> next;
    for (const Axis& a : ax_) {
        if (!a.drive) continue;
        for (double t : {a.drive->end_t, a.drive->edge_t}) {
            if (t == SpeedProfile::never) continue;
            const sc_core::sc_time at = a.drive->abs(t);
            if (!next || at < *next) next = at;
        }
    }
    if (next) wake_.notify(*next > now ? *next - now : sc_core::SC_ZERO_TIME);
}

// ---------------------------------------------------------------------------------------------
// Pins and observation

void CamcQi::set_pin(unsigned axis, Pin p, bool level) {
    ax(axis).pins[static_cast<unsigned>(p)] = level;
    check_inputs(axis);
    if (auto d = ax_[axis].drive) plan_edges(*d);
    schedule();
    wake_.notify(sc_core::SC_ZERO_TIME);
}

void CamcQi::set_sensors(unsigned axis, const Sensors& s) {
    ax(axis).sensors = s;
    check_inputs(axis);
    if (auto d = ax_[axis].drive) plan_edges(*d);
    schedule();
    wake_.notify(sc_core::SC_ZERO_TIME);
}

bool CamcQi::pin(unsigned axis, Pin p) const { return ax(axis).pins[static_cast<unsigned>(p)]; }

void CamcQi::set_estop_pin(bool active) {
    estop_pin_ = active;
    if (active)
        for (Axis& a : ax_)
            if (a.drive) stop_drive(a.drive, false, endst::estop_signal);
    wake_.notify(sc_core::SC_ZERO_TIME);
}

void CamcQi::check_inputs(unsigned axis) {
    Axis& a = ax_[axis];
    if (!a.drive) return;
    auto d = a.drive;
    if (limit_active(a, Pin::alarm)) {
        stop_drive(d, false, endst::alarm);
        return;
    }
    const int dir = direction(axis);
    const bool slow = a.ucfg1 & ucfg::limit_slowdown;
    // A limit acts once (a slow-down stop runs on into it); a search for it is not stopped by it.
    auto acts = [&](Pin p, std::uint32_t bit) {
        return !(d->cause & bit) && !(d->search && d->search_pin == p) && limit_active(a, p);
    };
    if (dir > 0 && acts(Pin::pelm, endst::pelm)) {
        stop_drive(d, slow, endst::pelm);
        return;
    }
    if (dir < 0 && acts(Pin::nelm, endst::nelm)) {
        stop_drive(d, slow, endst::nelm);
        return;
    }
    if (d->search && limit_active(a, d->search_pin) != d->search_inactive) {
        d->search = false;
        stop_drive(d, !d->search_immediate, d->search_pin == Pin::org ? endst::home_ok : endst::signal_ok);
    }
}

int CamcQi::direction(unsigned axis) const {
    const Axis& a = ax(axis);
    if (!a.drive) return 0;
    return a.drive->direction(axis, a.drive->steps_at(sc_core::sc_time_stamp()));
}

void CamcQi::set_encoder_source(unsigned axis, std::function<std::int64_t()> src) {
    ax(axis).encoder = std::move(src);
}

void CamcQi::trace_pulses(unsigned axis, bool on) { ax(axis).trace = on; }

std::int64_t CamcQi::command_position(unsigned axis) const {
    const Axis& a = ax(axis);
    if (!a.drive) return a.cnt1;
    return a.drive->base[axis] + a.drive->offset(axis, a.drive->steps_at(sc_core::sc_time_stamp()));
}

std::int64_t CamcQi::encoder_position(unsigned axis) const {
    const Axis& a = ax(axis);
    return (a.encoder ? a.encoder() : command_position(axis)) + a.enc_offset;
}

bool CamcQi::busy(unsigned axis) const { return ax(axis).drive != nullptr; }

double CamcQi::current_speed(unsigned axis) const {
    const Axis& a = ax(axis);
    if (!a.drive) return 0;
    const double t = a.drive->rel(sc_core::sc_time_stamp());
    return t >= a.drive->end_t ? 0 : a.drive->profile.velocity(t);
}

std::uint32_t CamcQi::drive_status(unsigned axis) const {
    const Axis& a = ax(axis);
    std::uint32_t s = drvst::queue_empty;
    if (!a.drive) return s;
    const Drive& d = *a.drive;
    const double t = d.rel(sc_core::sc_time_stamp());
    s |= drvst::busy | drvst::pulsing;
    switch (t >= d.end_t ? SpeedProfile::Phase::idle : d.profile.phase(t)) {
    case SpeedProfile::Phase::up: s |= drvst::up; break;
    case SpeedProfile::Phase::down: s |= drvst::down; break;
    case SpeedProfile::Phase::constant: s |= drvst::constant; break;
    default: break;
    }
    switch (d.mode) {
    case dcfg::preset: s |= drvst::preset; break;
    case dcfg::cont_pos: case dcfg::cont_neg: s |= drvst::continuous; break;
    case dcfg::origin_pos: case dcfg::origin_neg: s |= drvst::home; break;
    case dcfg::linear: s |= drvst::interpolating | drvst::linear; break;
    default: s |= drvst::interpolating | drvst::circular; break;
    }
    if (direction(axis) < 0) s |= drvst::negative;
    return s;
}

std::uint32_t CamcQi::mech_status(unsigned axis) const {
    const Axis& a = ax(axis);
    std::uint32_t s = 0;
    if (limit_active(a, Pin::pelm)) s |= mech::pelm;
    if (limit_active(a, Pin::nelm)) s |= mech::nelm;
    if (limit_active(a, Pin::alarm)) s |= mech::alarm;
    if (limit_active(a, Pin::org)) s |= mech::org;
    if (a.pins[static_cast<unsigned>(Pin::inp)]) s |= mech::inp;
    if (level(axis, Pin::zphase, pulse_count(axis))) s |= mech::zphase;
    if (estop_pin_) s |= mech::estop;
    return s;
}

} // namespace rcsim::camc
