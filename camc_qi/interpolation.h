// rcsim — CAMC-QI interpolation: linear (long-axis DDA) and circular (octant method).
//
// Sources (camc_qi/README.md "Sources"): NOVA MCX514 manual §3.1/3.2 (accuracy and end-point rule),
// PCL6045B manual (octant table and step-count rule) and the motion-controller paper, P2 of
// docs/system.md §1 (octants 0..7, short axis X in 1,2,5,6 and Y in 0,3,4,7; total pulses = sum of
// the short-axis lengths; eqs. 1-10).
//
// Both interpolators are plain C++ (no SystemC): the chip model asks "where is the path after k
// interpolation steps" and never schedules an event per pulse.
//
// Coordinates are pulses, relative to the arc centre for circles. Octants are numbered CCW from
// +X (octant n covers angles [45n, 45(n+1)) degrees); a point on an octant border belongs to the
// octant the motion is entering (for the start) or leaving (for the end point).
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace rcsim::camc {

/// Largest coordinate magnitude the interpolators accept (31-bit counters, as on MCX514, with
/// headroom so that x^2 + y^2 fits an int64 exactly).
constexpr std::int64_t max_coordinate = (std::int64_t{1} << 30) - 1;

/// Bad interpolation data (the chip reports it as End status b19; the API layer as an error).
class InterpolationError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

// ---------------------------------------------------------------------------------------------
// Linear interpolation

/// A straight line from the origin to `delta` on up to 4 axes. The long axis (largest |delta|)
/// pulses every step; the others keep the DDA accumulator e += |d|; if 2e >= L {pulse; e -= L},
/// which puts every axis at round-half-up(k*|d|/L) after step k: within 0.5 pulse of the ideal
/// line, and each axis emits exactly |d| pulses over L steps.
class LinearPath {
public:
    static constexpr unsigned max_axes = 4;
    LinearPath() = default;
    /// `axes` in 1..4; throws InterpolationError for out-of-range values.
    LinearPath(const std::int64_t* delta, unsigned axes);

    unsigned axes() const { return axes_; }
    /// Total interpolation steps (= the long axis distance).
    std::uint64_t steps() const { return steps_; }
    std::int64_t delta(unsigned axis) const { return delta_[axis]; }
    /// Position of `axis` after `k` steps (k clamped to steps()); closed form, O(1).
    std::int64_t position(unsigned axis, std::uint64_t k) const;

private:
    std::array<std::int64_t, max_axes> delta_{};
    unsigned axes_ = 0;
    std::uint64_t steps_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Circular interpolation

enum class ArcDirection : std::uint8_t { cw = 0, ccw = 1 };

struct Point {
    std::int64_t x = 0, y = 0;
    bool operator==(const Point& o) const { return x == o.x && y == o.y; }
    bool operator!=(const Point& o) const { return !(*this == o); }
};

/// Octant of `p` (relative to the centre) for motion in `dir`: the octant the motion is in or
/// entering at p. p must not be the centre.
int octant_of(Point p, ArcDirection dir);
/// The octant an arc *ending* at `p` arrives through (a border point belongs to the octant before it).
int end_octant_of(Point p, ArcDirection dir);
/// True when octant `o` has Y as its short axis (0,3,4,7); otherwise X is short (1,2,5,6).
inline bool y_is_short(int o) { return o == 0 || o == 3 || o == 4 || o == 7; }

/// An arc about the centre, from `start` to the end point `end` (both relative to the centre).
/// Each step moves the short axis of the current octant by one pulse and the long axis by zero or
/// one pulse, whichever keeps |F| = |x^2 + y^2 - R^2| smaller (R^2 taken from the start point,
/// so the start is exactly on the track). The arc ends, on its last pass through the end point's
/// octant, when the short-axis coordinate reaches the end point's; end == start is a full circle.
class CirclePath {
public:
    CirclePath() = default;
    /// Throws InterpolationError if start is the centre, a coordinate exceeds max_coordinate,
    /// or the end point is not on the track (its short coordinate is never reached).
    CirclePath(Point start, Point end, ArcDirection dir);

    Point start() const { return start_; }
    Point programmed_end() const { return end_; }
    ArcDirection direction() const { return dir_; }
    std::int64_t radius_squared() const { return r2_; }
    /// The step count, from step_count() below (the value a host writes into QiISNUM).
    std::uint64_t steps() const { return steps_; }

    /// Walks the path forward: the point after step k (k >= the previous call's k, or 0 restarts;
    /// k is clamped to steps()). Amortised O(1) per step for monotone queries.
    Point at(std::uint64_t k);
    /// Steps actually walked by the interpolator to reach its own end condition (a full walk; for
    /// tests and the chip's self-check).
    std::uint64_t walk_to_end();
    /// Point reached by the interpolator when it stopped (after walk_to_end()).
    Point walked_end() const { return cur_; }

private:
    // Step machine state.
    Point start_, end_, cur_;
    ArcDirection dir_ = ArcDirection::ccw;
    std::int64_t r2_ = 0;
    std::uint64_t steps_ = 0, k_ = 0;
    int end_octant_ = 0, oct_ = 0;
    int pieces_needed_ = 0; // octant borders to cross before the final pass through the end octant
    int pieces_done_ = 0;
    bool finished_ = false;

    void restart();
    void step();
};

/// The total interpolation steps of an arc, computed the way the paper does it (eqs. 1-10): the
/// sum over the octant pieces the arc crosses of the short-axis length of each piece; the octant
/// borders are taken on the pulse lattice (the first track point of the next octant), so the sum
/// is exact, not rounded. Throws InterpolationError as CirclePath does.
std::uint64_t circle_step_count(Point start, Point end, ArcDirection dir);

/// The point where the interpolator stops after circle_step_count() steps (closed form, no
/// walk): the end point itself when it lies on the track, else the track point with the end's
/// short coordinate (within one pulse of the end, MCX514 §3.2).
Point circle_walked_end(Point start, Point end, ArcDirection dir);
struct CircleWalk {
    std::uint64_t steps = 0;
    Point end;
};
/// Both of the above in one pass.
CircleWalk circle_walk(Point start, Point end, ArcDirection dir);

/// The same sum with real numbers (R from the start point, borders at exact 45-degree angles):
/// full circle = 4*sqrt(2)*R. Differs from circle_step_count() by < 1 per diagonal border crossed.
double circle_step_count_real(Point start, Point end, ArcDirection dir);

/// The angle (radians, > 0) an arc sweeps from start to end in `dir`; 2 pi when end == start.
double arc_sweep(Point start, Point end, ArcDirection dir);
/// The step-count sum of circle_step_count_real() over the first `sweep` radians of an arc from
/// `start`: the interpolation steps per unit of arc angle, for the constant vector speed mode.
double arc_steps_real(Point start, double sweep, ArcDirection dir);

/// Integer square root (floor) for 0 <= v < 2^62.
std::int64_t isqrt(std::int64_t v);

} // namespace rcsim::camc
