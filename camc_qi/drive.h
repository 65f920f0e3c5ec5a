// rcsim — CAMC-QI: one drive in progress, shared by the register side (camc_qi.cpp: it starts,
// stops and reads drives) and the drive side (drive.cpp: plans, stops and ends them). Internal to
// camc_qi/; the chip's interface is camc_qi.h.
#pragma once

#include "camc_qi/camc_qi.h"
#include "models/clock.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace rcsim::camc {

/// The step limit of a drive that has none (continuous and origin drives), and "no stop step".
constexpr std::uint64_t unlimited = std::numeric_limits<std::uint64_t>::max();
// A drive's step count is floor(position + eps): the profile's floating-point position lands a
// hair below an integer at the exact time that step is due.
constexpr double step_eps = 1e-7;

/// A drive in progress: a speed profile over steps, and how each member axis moves per step.
struct CamcQi::Drive {
    std::uint32_t mode = dcfg::preset;
    SpeedProfile profile;
    ProfileParams params;
    sc_core::sc_time start;
    std::uint64_t limit = unlimited; // total steps (unlimited for continuous and origin drives)
    std::uint32_t members = 0;       // axis mask
    unsigned master = 0;             // the axis STRN was written to: its registers hold the rates
    std::array<std::int64_t, axes> base{};
    int dir = 1;                     // single-axis drives
    LinearPath line;
    std::array<int, axes> line_index{}; // axis -> index in `line`
    mutable CirclePath circle;
    unsigned cx = 0, cy = 1;         // circle axes
    // The arc's end lies off the track (within a pulse): one final correction step onto the
    // programmed end point, so chained arcs do not drift.
    bool end_fix = false;
    // Constant vector speed: the profile runs in pulses of arc length (radius x angle), the step
    // count follows arc_steps_real() of the angle, scaled so that the arc's end is step `limit`.
    bool vector = false;
    double radius = 0, sweep = 0, steps_real = 0;

    /// Steps driven when the profile is at position s (identity unless vector).
    double steps_of_pos(double s) const {
        if (!vector) return s;
        const double length = radius * sweep;
        if (s >= length) return static_cast<double>(limit) * s / length;
        return static_cast<double>(limit) * arc_steps_real(circle.start(), s / radius, circle.direction()) / steps_real;
    }
    /// The profile position at which k steps are driven: the least s with steps_of_pos(s) >= k
    /// (to the bisection's resolution, from above, so that step k is due at that time).
    double pos_of_steps(double k) const {
        if (!vector) return k;
        const double length = radius * sweep;
        if (k >= static_cast<double>(limit)) return length * k / static_cast<double>(limit);
        double lo = 0, hi = length;
        for (int i = 0; i < 100 && hi - lo > 1e-9 * (1 + length); ++i) {
            const double mid = (lo + hi) / 2;
            (steps_of_pos(mid) < k ? lo : hi) = mid;
        }
        return hi;
    }
    std::uint32_t cause = 0;         // end-status bits of the stop cause (0 = normal end)
    std::shared_ptr<Drive> next;     // blending: the drive that starts when this one ends normally
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
        const double t_lim = profile.time_of(pos_of_steps(static_cast<double>(limit) - step_eps));
        if (t_lim <= end_t) {
            end_t = t_lim;
            at_limit = true;
        } else if (end_t != SpeedProfile::never) {
            // A preset profile planned over exactly `limit` steps ends a rounding error short.
            const double lim = static_cast<double>(limit);
            at_limit = steps_of_pos(profile.position(end_t)) >= lim - std::max(1e-6, 1e-9 * lim);
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
        const double s = std::floor(steps_of_pos(profile.position(t)) + step_eps);
        if (s <= 0) return 0;
        return std::min<std::uint64_t>(static_cast<std::uint64_t>(s), limit);
    }

    std::int64_t offset(unsigned axis, std::uint64_t k) const {
        switch (mode) {
        case dcfg::linear: return line.position(static_cast<unsigned>(line_index[axis]), k);
        case dcfg::circle_cw:
        case dcfg::circle_ccw: {
            const Point p = circle_point(circle, k), s = circle.start();
            return axis == cx ? p.x - s.x : p.y - s.y;
        }
        default: return dir * static_cast<std::int64_t>(k);
        }
    }

    /// The arc's point after k steps, `walk` being this drive's path or a copy of it.
    Point circle_point(CirclePath& walk, std::uint64_t k) const {
        return end_fix && k >= limit ? walk.programmed_end() : walk.at(k);
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

} // namespace rcsim::camc
