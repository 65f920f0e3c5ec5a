// rcsim — CAMC-QI drives: start (and the checks that refuse one), stops and ends, the sensor edges
// met along the path and the kernel events that act on them, the pulse trace. The register
// interface that commands them is camc_qi.cpp; see camc_qi.h and README.md.
#include "camc_qi/drive.h"

#include <cmath>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <utility>

namespace rcsim::camc {

namespace {
constexpr std::uint32_t abnormal = endst::pelm | endst::nelm | endst::alarm | endst::estop_signal |
                                   endst::estop_cmd | endst::interp_data | endst::data_error;

bool is_interpolation(std::uint32_t mode) { return mode >= dcfg::linear; }
} // namespace

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
/// switch active in the direction of motion, except the one a signal search looks for
/// (`searched`). Sets the end status of the axis that refuses.
bool CamcQi::start_check(unsigned axis, int dir, std::optional<Pin> searched) {
    Axis& a = ax_[axis];
    std::uint32_t why = 0;
    if (limit_active(a, Pin::alarm)) why |= endst::alarm;
    if (estop_pin_) why |= endst::estop_signal;
    if (searched != Pin::pelm && dir >= 0 && limit_active(a, Pin::pelm)) why |= endst::pelm;
    if (searched != Pin::nelm && dir <= 0 && limit_active(a, Pin::nelm)) why |= endst::nelm;
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
    // host must wait for BUSY to fall (the pre-register queue is not modelled), unless it blends:
    // the same axes run one preset or interpolation drive, without a blended drive queued yet.
    std::shared_ptr<Drive> running;
    for (unsigned i = 0; i < axes; ++i)
        if ((members & (1u << i)) && ax_[i].drive) {
            running = ax_[i].drive;
            const bool blendable = (m.dcfg & dcfg::blend) && running->members == members && !running->next &&
                                   running->cause == 0 && running->limit != unlimited && !running->search &&
                                   mode != dcfg::cont_pos && mode != dcfg::cont_neg && mode != dcfg::origin_pos &&
                                   mode != dcfg::origin_neg;
            const bool single = members == (1u << axis) && running->members == members && !running->search &&
                                running->cause == 0 && !running->next && mode <= dcfg::cont_neg &&
                                running->mode <= dcfg::cont_neg;
            if (blendable || ((m.dcfg & dcfg::take_over) && single)) continue;
            SC_REPORT_WARNING(name(), ("start on axis " + std::to_string(axis) + " ignored: axis " +
                                       std::to_string(i) + " is busy").c_str());
            return;
        }

    auto d = std::make_shared<Drive>();
    d->mode = mode;
    d->members = members;
    d->master = axis;
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
        case dcfg::preset: {
            // A take-over's POS is the absolute target: the host cannot know the position at STRN.
            const std::int64_t rel = running && (m.dcfg & dcfg::take_over) ? m.pos - command_position(axis) : m.pos;
            d->dir = rel < 0 ? -1 : 1;
            d->limit = distance = static_cast<std::uint64_t>(std::llabs(rel));
            break;
        }
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
            const ArcDirection ad = mode == dcfg::circle_cw ? ArcDirection::cw : ArcDirection::ccw;
            d->circle = CirclePath(s, e, ad);
            d->end_fix = circle_walked_end(s, e, ad) != e;
            d->limit = distance = d->circle.steps() + (d->end_fix ? 1 : 0);
            if (m.dcfg & dcfg::vector_speed) {
                d->vector = true;
                d->radius = std::sqrt(static_cast<double>(d->circle.radius_squared()));
                d->sweep = arc_sweep(s, e, ad);
                d->steps_real = arc_steps_real(s, d->sweep, ad);
            }
        }
        }
    } catch (const InterpolationError& e) {
        SC_REPORT_INFO(name(), e.what());
        refuse(endst::interp_data | endst::data_error);
        return;
    }

    if (origin) {
        static constexpr Pin signals[] = {Pin::org, Pin::zphase, Pin::pelm, Pin::nelm};
        d->search = true;
        d->search_pin = signals[(m.dcfg & dcfg::signal_mask) >> dcfg::signal_shift];
        d->search_inactive = m.dcfg & dcfg::search_inactive;
        d->search_immediate = m.dcfg & dcfg::search_immediate;
    }
    // A search for a limit switch may start into that switch's side: it stops at it, or ends at
    // once below when it starts on it. The other limit still refuses a start towards it.
    std::optional<Pin> searched;
    if (origin && (d->search_pin == Pin::pelm || d->search_pin == Pin::nelm)) searched = d->search_pin;
    for (unsigned i = 0; i < axes; ++i)
        if (members & (1u << i)) {
            const int dir = (mode == dcfg::circle_cw || mode == dcfg::circle_ccw) ? 0 : d->direction(i, 0);
            if (!start_check(i, dir, searched)) {
                refuse(ax_[i].end_status);
                return;
            }
        }
    if (origin) {
        if (limit_active(m, d->search_pin) != d->search_inactive) { // the edge is behind: found at once
            m.end_status = d->search_pin == Pin::org ? endst::home_ok : endst::signal_ok;
            m.iflag |= intf::drive_end;
            return;
        }
    }

    const bool take_over = running && (m.dcfg & dcfg::take_over) && !(m.dcfg & dcfg::blend);
    if (take_over && d->dir != running->dir) {
        SC_REPORT_WARNING(name(), ("take-over on axis " + std::to_string(axis) + " ignored: it reverses").c_str());
        return;
    }
    const double now_speed = take_over ? current_speed(axis) : 0;
    if (mode == dcfg::cont_pos || mode == dcfg::cont_neg || origin) {
        d->profile = SpeedProfile::continuous(p, now_speed);
    } else if (is_interpolation(mode) && m.isnum != 0 && m.isnum != distance) {
        // Deceleration is planned over the host's QiISNUM, not over the real step count: too
        // small a number crawls on at STD, too large a number ends the drive still fast.
        d->profile = SpeedProfile::preset(p, d->pos_of_steps(static_cast<double>(m.isnum)), true);
    } else {
        const double entry = take_over ? now_speed : running ? m.jspd * static_cast<double>(m.range) : 0;
        d->profile = SpeedProfile::preset(p, d->pos_of_steps(static_cast<double>(distance)), false, entry);
    }
    d->plan_end();
    if (take_over) {
        // The running drive ends here with the steps it drove; the new one goes on from them.
        running->profile.stop(running->rel(d->start));
        running->end_t = running->rel(d->start);
        running->at_limit = false;
        finish(running, d->start);
        attach(d, d->start);
        return;
    }
    if (running) {
        // Blending: the running drive now ends at JEXIT, and this one takes over at that instant.
        const double exit = ax_[running->master].jexit * static_cast<double>(m.range);
        if (!running->profile.blend_exit(running->rel(d->start), exit, running->params)) {
            SC_REPORT_WARNING(name(), ("blended start on axis " + std::to_string(axis) + " ignored: the drive ends").c_str());
            return;
        }
        running->plan_end();
        plan_edges(*running);
        running->next = d;
        schedule();
        return;
    }
    attach(d, d->start);
}

void CamcQi::attach(std::shared_ptr<Drive> d, sc_core::sc_time at) {
    d->start = at;
    for (unsigned i = 0; i < axes; ++i)
        if (d->members & (1u << i)) {
            Axis& a = ax_[i];
            d->base[i] = a.cnt1;
            d->origin[i] = a.cnt1 - a.preset_shift;
            a.drive = d;
            a.end_status = 0;
            a.iflag |= intf::drive_start;
        }
    if (d->limit == 0) {
        finish(d, d->start);
    } else {
        plan_edges(*d);
    }
    schedule();
}

void CamcQi::stop_drive(std::shared_ptr<Drive> d, bool slow, std::uint32_t cause) {
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    const double t = d->rel(now);
    d->next.reset(); // a stop cancels a blended successor
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
    if (d->next && d->cause == 0) attach(std::exchange(d->next, nullptr), d->end_abs());
    wake_.notify(sc_core::SC_ZERO_TIME);
}

void CamcQi::stop_at(std::shared_ptr<Drive> d, bool slow, std::uint32_t cause, double t, std::uint64_t k) {
    d->cause |= cause;
    d->next.reset();
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
            const Point p = d.circle_point(walk, k);
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
    d.edge_t = std::max(now, d.profile.time_of(d.pos_of_steps(static_cast<double>(best) - step_eps)));
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
        const double t = replay.profile.time_of(replay.pos_of_steps(static_cast<double>(k) - step_eps));
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

} // namespace rcsim::camc
