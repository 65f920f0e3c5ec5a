// rcsim — CAMC-QI interpolation: linear (long-axis DDA) and circular (octant method).
// See interpolation.h for the sources and conventions.
#include "camc_qi/interpolation.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace rcsim::camc {
namespace {

std::int64_t iabs(std::int64_t v) { return v < 0 ? -v : v; }

void check_range(std::int64_t v, const char* what) {
    if (iabs(v) > max_coordinate)
        throw InterpolationError(std::string(what) + " " + std::to_string(v) +
                                 " is outside +-" + std::to_string(max_coordinate) + " pulses");
}

/// floor(theta / 45 deg) of p: the octant for CCW motion (a border point opens the next octant).
int octant_ccw(Point p) {
    const std::int64_t x = p.x, y = p.y, ax = iabs(x), ay = iabs(y);
    if (y >= 0) {
        if (x > 0 && y < x) return 0;
        if (x > 0) return 1;         // y >= x > 0
        if (y > ax) return 2;        // x <= 0, above the 135-degree diagonal
        if (y > 0) return 3;         // x < 0, 0 < y <= |x|
        return 4;                    // y == 0, x < 0
    }
    if (x < 0 && ay < ax) return 4;
    if (x < 0) return 5;             // |y| >= |x|
    if (ay > x) return 6;            // x >= 0
    return 7;                        // x > 0, |y| <= x
}

/// Per-octant step directions for CCW motion (velocity (-y, x)); CW negates both.
struct OctantMoves {
    Point short_step, long_step;
};
constexpr OctantMoves ccw_moves[8] = {
    {{0, 1}, {-1, 0}},  // 0: Y always +, X by calculation -
    {{-1, 0}, {0, 1}},  // 1: X always -, Y +
    {{-1, 0}, {0, -1}}, // 2
    {{0, -1}, {-1, 0}}, // 3
    {{0, -1}, {1, 0}},  // 4
    {{1, 0}, {0, -1}},  // 5
    {{1, 0}, {0, 1}},   // 6
    {{0, 1}, {1, 0}},   // 7
};

OctantMoves moves(int oct, ArcDirection dir) {
    OctantMoves m = ccw_moves[oct];
    if (dir == ArcDirection::cw) {
        m.short_step = {-m.short_step.x, -m.short_step.y};
        m.long_step = {-m.long_step.x, -m.long_step.y};
    }
    return m;
}

std::int64_t short_coord(Point p, int oct) { return y_is_short(oct) ? p.y : p.x; }
std::int64_t short_dir(int oct, ArcDirection dir) {
    const Point s = moves(oct, dir).short_step;
    return y_is_short(oct) ? s.y : s.x;
}

/// Octant borders crossed going from octant a to octant b in direction dir (0..7).
int advance(int a, int b, ArcDirection dir) {
    return dir == ArcDirection::ccw ? (b - a + 8) % 8 : (a - b + 8) % 8;
}

std::int64_t radius_error(Point p, std::int64_t r2) { return p.x * p.x + p.y * p.y - r2; }

/// The track point of octant `oct` whose short coordinate is s: the long coordinate (with the
/// octant's sign) that minimises |F|. The interpolator walks exactly these points (see tests).
Point track_point(int oct, std::int64_t s, std::int64_t r2) {
    const std::int64_t c = r2 - s * s;
    std::int64_t m = 0;
    if (c > 0) {
        m = isqrt(c);
        if ((m + 1) * (m + 1) - c < c - m * m) ++m; // never a tie: the two differ by an odd number
    }
    // The long axis' sign in each octant: X > 0 in 0,7; X < 0 in 3,4; Y > 0 in 1,2; Y < 0 in 5,6.
    switch (oct) {
    case 0: case 7: return {m, s};
    case 3: case 4: return {-m, s};
    case 1: case 2: return {s, m};
    default: return {s, -m};
    }
}

/// One interpolation step in octant `oct`: the short axis always moves; the long axis moves
/// too when that lands nearer the circle (never a tie: the two |F| differ by an odd number).
Point chip_step(Point p, int oct, ArcDirection dir, std::int64_t r2) {
    const OctantMoves m = moves(oct, dir);
    const Point p1{p.x + m.short_step.x, p.y + m.short_step.y};
    const Point p2{p1.x + m.long_step.x, p1.y + m.long_step.y};
    return iabs(radius_error(p2, r2)) < iabs(radius_error(p1, r2)) ? p2 : p1;
}

/// The last step n (from p, in octant `oct`) whose track point is still in the octant: the
/// interpolator walks exactly the track points up to there.
std::int64_t last_track_step(Point p, int oct, ArcDirection dir, std::int64_t r2) {
    const std::int64_t s0 = short_coord(p, oct), sd = short_dir(oct, dir);
    auto outside = [&](std::int64_t n) { return octant_of(track_point(oct, s0 + sd * n, r2), dir) != oct; };
    // Past |s| > R the track point lies on an axis of another octant, so this bound is outside.
    std::int64_t hi = iabs(s0) + isqrt(r2) + 2, lo = 0; // lo inside (n = 0 is p), hi outside
    while (hi - lo > 1) {
        const std::int64_t mid = lo + (hi - lo) / 2;
        (outside(mid) ? hi : lo) = mid;
    }
    return hi - 1;
}

/// The point the interpolator reaches n steps after p in octant `oct` (n within the piece).
Point point_in_piece(Point p, int oct, ArcDirection dir, std::int64_t r2, std::int64_t n) {
    const std::int64_t j = std::min(n, last_track_step(p, oct, dir, r2));
    Point cur = j == 0 ? p : track_point(oct, short_coord(p, oct) + short_dir(oct, dir) * j, r2);
    for (std::int64_t i = j; i < n; ++i) cur = chip_step(cur, oct, dir, r2);
    return cur;
}

/// Steps the interpolator spends in octant `oct` starting at p before it reaches a point of
/// another octant (that point, the first track point of the next octant, is returned in `exit`).
std::int64_t steps_to_exit(Point p, int oct, ArcDirection dir, std::int64_t r2, Point& exit) {
    const std::int64_t s0 = short_coord(p, oct), sd = short_dir(oct, dir);
    // The border step itself is taken as the chip takes it: from the last point inside, the long
    // axis moves at most one pulse, so near a border of a tiny circle it can lag the track point.
    std::int64_t n = last_track_step(p, oct, dir, r2);
    Point cur = n == 0 ? p : track_point(oct, s0 + sd * n, r2);
    do {
        cur = chip_step(cur, oct, dir, r2);
        ++n;
    } while (octant_of(cur, dir) == oct);
    exit = cur;
    return n;
}

void validate_arc(Point start, Point end) {
    check_range(start.x, "arc start x (relative to the centre)");
    check_range(start.y, "arc start y (relative to the centre)");
    check_range(end.x, "arc end x (relative to the centre)");
    check_range(end.y, "arc end y (relative to the centre)");
    if (start == Point{}) throw InterpolationError("arc start point equals the centre (radius 0)");
    if (end == Point{}) throw InterpolationError("arc end point equals the centre");
}

/// Octant borders to cross before the final pass through the end octant (0 = the arc stays in
/// the start octant; 8 = it comes back round to it).
int pieces_needed(Point start, Point end, ArcDirection dir) {
    const int so = octant_of(start, dir), eo = end_octant_of(end, dir);
    const int k = advance(so, eo, dir);
    if (k != 0) return k;
    const std::int64_t ahead = (short_coord(end, so) - short_coord(start, so)) * short_dir(so, dir);
    return ahead > 0 ? 0 : 8;
}

} // namespace

std::int64_t isqrt(std::int64_t v) {
    if (v <= 0) return 0;
    auto r = static_cast<std::int64_t>(std::sqrt(static_cast<long double>(v)));
    while (r * r > v) --r;
    while ((r + 1) * (r + 1) <= v) ++r;
    return r;
}

int octant_of(Point p, ArcDirection dir) {
    if (dir == ArcDirection::ccw) return octant_ccw(p);
    // CW: mirror in the X axis (CW becomes CCW), then map the mirrored octant back.
    return 7 - octant_ccw({p.x, -p.y});
}

int end_octant_of(Point p, ArcDirection dir) {
    return octant_of(p, dir == ArcDirection::ccw ? ArcDirection::cw : ArcDirection::ccw);
}

// ---------------------------------------------------------------------------------------------

LinearPath::LinearPath(const std::int64_t* delta, unsigned axes) : axes_(axes) {
    if (axes < 1 || axes > max_axes)
        throw InterpolationError("linear interpolation needs 1..4 axes, got " + std::to_string(axes));
    for (unsigned i = 0; i < axes; ++i) {
        check_range(delta[i], "linear interpolation distance");
        delta_[i] = delta[i];
        steps_ = std::max<std::uint64_t>(steps_, static_cast<std::uint64_t>(iabs(delta[i])));
    }
}

std::int64_t LinearPath::position(unsigned axis, std::uint64_t k) const {
    if (axis >= axes_ || steps_ == 0) return 0;
    if (k > steps_) k = steps_;
    const std::int64_t d = iabs(delta_[axis]);
    const auto L = static_cast<std::int64_t>(steps_);
    // The accumulator's closed form: pulses after k steps = floor(k*d/L + 1/2).
    // k*d < 2^60 because both are below 2^30.
    const std::int64_t p = (2 * static_cast<std::int64_t>(k) * d + L) / (2 * L);
    return delta_[axis] < 0 ? -p : p;
}

// ---------------------------------------------------------------------------------------------

CirclePath::CirclePath(Point start, Point end, ArcDirection dir) : start_(start), end_(end), dir_(dir) {
    steps_ = circle_step_count(start, end, dir); // validates, throws on bad data
    r2_ = start.x * start.x + start.y * start.y;
    end_octant_ = end_octant_of(end, dir);
    pieces_needed_ = pieces_needed(start, end, dir);
    restart();
}

void CirclePath::restart() {
    cur_ = start_;
    k_ = 0;
    oct_ = octant_of(start_, dir_);
    pieces_done_ = 0;
    finished_ = false;
}

void CirclePath::step() {
    const int o = oct_;
    cur_ = chip_step(cur_, o, dir_, r2_);
    ++k_;

    const bool final_pass = pieces_done_ == pieces_needed_ && o == end_octant_;
    if (final_pass && short_coord(cur_, o) == short_coord(end_, o)) {
        finished_ = true;
        return;
    }
    const int next = octant_of(cur_, dir_);
    if (next == o) return;
    pieces_done_ += advance(o, next, dir_);
    oct_ = next;
    // Leaving the end octant on the final pass, or jumping over it (tiny radii): the walk ends
    // here. circle_step_count() has checked up front that this point is the end point.
    if (final_pass || pieces_done_ > pieces_needed_) {
        finished_ = true;
        return;
    }
    // Entering the end octant on the final pass already at the end's short coordinate (a step
    // that crossed the border diagonally).
    if (pieces_done_ == pieces_needed_ && next == end_octant_ &&
        short_coord(cur_, next) == short_coord(end_, next))
        finished_ = true;
}

Point CirclePath::at(std::uint64_t k) {
    if (k > steps_) k = steps_;
    if (k < k_) restart();
    while (k_ < k && !finished_) step();
    return cur_;
}

std::uint64_t CirclePath::walk_to_end() {
    restart();
    // A generous bound in case the walk and the formula ever disagree: 8 pieces of at most R+2.
    const std::uint64_t bound = 8 * static_cast<std::uint64_t>(isqrt(r2_) + 2) + 8;
    while (!finished_ && k_ < bound) step();
    return k_;
}

// ---------------------------------------------------------------------------------------------

std::uint64_t circle_step_count(Point start, Point end, ArcDirection dir) {
    return circle_walk(start, end, dir).steps;
}

Point circle_walked_end(Point start, Point end, ArcDirection dir) {
    return circle_walk(start, end, dir).end;
}

CircleWalk circle_walk(Point start, Point end, ArcDirection dir) {
    validate_arc(start, end);
    const std::int64_t r2 = start.x * start.x + start.y * start.y;
    const int end_oct = end_octant_of(end, dir);
    const int needed = pieces_needed(start, end, dir);

    Point p = start;
    int oct = octant_of(start, dir), done = 0;
    std::uint64_t steps = 0;
    auto off_track = [&]() {
        return InterpolationError("arc end point (" + std::to_string(end.x) + "," +
                                  std::to_string(end.y) + ") relative to the centre is not on the track from (" +
                                  std::to_string(start.x) + "," + std::to_string(start.y) + ")");
    };
    for (;;) {
        Point exit;
        const std::int64_t piece = steps_to_exit(p, oct, dir, r2, exit);
        if (done == needed && oct == end_oct) {
            // The final piece: the short-axis length from here to the end point, which must be
            // reached before the track leaves this octant (0 when a diagonal step entered the
            // octant right at the end's short coordinate).
            const std::int64_t n = (short_coord(end, oct) - short_coord(p, oct)) * short_dir(oct, dir);
            if (n < 0 || n > piece) throw off_track();
            return {steps + static_cast<std::uint64_t>(n), point_in_piece(p, oct, dir, r2, n)};
        }
        const int next = octant_of(exit, dir);
        const int adv = advance(oct, next, dir);
        steps += static_cast<std::uint64_t>(piece);
        if (done + adv > needed) {
            // The track jumps over the end octant (radius of a few pulses): only its landing
            // point can be the end.
            if (exit == end) return {steps, exit};
            throw off_track();
        }
        done += adv;
        p = exit;
        oct = next;
    }
}

double arc_sweep(Point start, Point end, ArcDirection dir) {
    validate_arc(start, end);
    const double pi = std::acos(-1.0);
    const double a = std::atan2(static_cast<double>(start.y), static_cast<double>(start.x));
    const double b = std::atan2(static_cast<double>(end.y), static_cast<double>(end.x));
    // The paper's TotalRadian (eqs. 3-4 of step 3/4): the angle swept, a full turn when equal.
    double sweep = dir == ArcDirection::ccw ? b - a : a - b;
    while (sweep <= 0) sweep += 2 * pi;
    while (sweep > 2 * pi) sweep -= 2 * pi;
    if (start == end) sweep = 2 * pi;
    return sweep;
}

double arc_steps_real(Point start, double sweep, ArcDirection dir) {
    const double eighth = std::acos(-1.0) / 4;
    const double R = std::sqrt(static_cast<double>(start.x) * start.x + static_cast<double>(start.y) * start.y);
    const double a = std::atan2(static_cast<double>(start.y), static_cast<double>(start.x));
    const double sgn = dir == ArcDirection::ccw ? 1.0 : -1.0;
    // Octant borders at integer multiples of 45 degrees, visited by index so that rounding of
    // the angle can never stall the walk.
    long border = dir == ArcDirection::ccw ? static_cast<long>(std::floor(a / eighth)) + 1
                                           : static_cast<long>(std::ceil(a / eighth)) - 1;
    double total = 0, theta = a, done = 0;
    while (done < sweep) {
        const double to_border = std::abs(static_cast<double>(border) * eighth - theta);
        const double step = std::min(to_border, sweep - done);
        const double next = theta + sgn * step;
        const long oct_index = dir == ArcDirection::ccw ? border - 1 : border; // octant being crossed
        const int oct = static_cast<int>(((oct_index % 8) + 8) % 8);
        total += y_is_short(oct) ? R * std::abs(std::sin(next) - std::sin(theta))
                                 : R * std::abs(std::cos(next) - std::cos(theta));
        done += step;
        theta = next;
        border += dir == ArcDirection::ccw ? 1 : -1;
    }
    return total;
}

double circle_step_count_real(Point start, Point end, ArcDirection dir) {
    return arc_steps_real(start, arc_sweep(start, end, dir), dir);
}

} // namespace rcsim::camc
