// rcsim — CAMC-QI speed profiles: trapezoid and S-curve, preset and continuous drives.
//
// Source: Ajinextek's AXL API (AXM.h) and the chip-class profile rules listed in camc_qi/README.md
// "Sources" (STD start speed, OBJ object speed, RATE1/RATE2 accel/decel, SW1/SW2 S-curve sections;
// AXL profile modes 0-4, jerk given as percent of the accel phase spent in jerk ramps).
//
// A profile is a list of constant-jerk segments, so the step count at any time is a closed-form
// cubic: the chip evaluates it when asked and never schedules an event per pulse. Times are
// seconds from the start of the drive, positions in steps (pulses or interpolation steps).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

namespace rcsim::camc {

struct ProfileParams {
    double start_speed = 1;   // STD, steps/s: speed at start and end of a drive
    double object_speed = 1;  // OBJ, steps/s
    double accel = 1;         // RATE1, steps/s^2
    double decel = 1;         // RATE2, steps/s^2
    double accel_jerk = 0;    // SW1: share of the accel phase spent in jerk ramps, 0..1 (0 = trapezoid)
    double decel_jerk = 0;    // SW2: the same for decel
};

class SpeedProfile {
public:
    enum class Phase : std::uint8_t { idle, up, constant, down };
    static constexpr double never = std::numeric_limits<double>::infinity();

    /// A drive of `distance` steps: STD -> OBJ (or a lower peak when too short) -> STD, ending at
    /// `distance`. With `tail` the speed stays at STD after the profile (interpolation whose
    /// QiISNUM is smaller than the real step count crawls on at STD).
    /// `entry` > 0: the drive starts at that speed instead of STD (a blended drive taking over
    /// from the one before it, README "Blending"); it ramps from there to OBJ at RATE1 (RATE2
    /// when above OBJ).
    static SpeedProfile preset(const ProfileParams& p, double distance, bool tail = false, double entry = 0);
    /// A drive without a target: STD -> OBJ, then OBJ forever.
    static SpeedProfile continuous(const ProfileParams& p, double entry = 0);

    /// Steps driven by time t (continuous; the chip floors it).
    double position(double t) const;
    double velocity(double t) const;
    Phase phase(double t) const;
    /// When the motion of the profile itself ends (never for continuous drives or a tail).
    double end_time() const;
    /// The first time the position reaches s, or `never`.
    double time_of(double s) const;

    /// Slow-down stop at t: from the speed at t decelerate (RATE2/SW2) to STD, then end.
    /// Ignored during the final deceleration. (The acceleration restarts from zero: a jerk step.)
    void slow_down(double t, const ProfileParams& p);
    /// Immediate stop at t: the position freezes.
    void stop(double t);
    /// Blending (README "Blending"): from t, re-plans the rest of the drive so that it still ends
    /// at the same distance, but at speed `exit` instead of STD (cruise at OBJ as room allows).
    /// False, and unchanged, when the drive has no end or has ended by t.
    bool blend_exit(double t, double exit, const ProfileParams& p);

private:
    struct Segment {
        double t0, dur, s0, v0, a0, j;
        double s(double tau) const { return s0 + tau * (v0 + tau * (a0 / 2 + tau * j / 6)); }
        double v(double tau) const { return v0 + tau * (a0 + tau * j / 2); }
        double end() const { return t0 + dur; }
    };
    std::vector<Segment> seg_;
    double tail_v_ = 0;            // speed after the last segment (0 = stopped)
    double v_start_ = 0;           // STD: the speed at t = 0
    std::size_t decel_from_ = ~std::size_t{0}; // first segment of the final deceleration

    const Segment* find(double t) const;
    void cut(double t);
    void append(double dur, double a0, double j);
    void ramp(double v_from, double v_to, double rate, double jerk_share);
    /// Appends v_in -> (cruise at most vm) -> v_out over `distance` (rates by direction).
    void plan(double v_in, double v_out, double vm, double distance, const ProfileParams& p);
    double t_end() const { return seg_.empty() ? 0 : seg_.back().end(); }
    double s_end() const { return seg_.empty() ? 0 : seg_.back().s(seg_.back().dur); }
    double v_end() const { return seg_.empty() ? v_start_ : seg_.back().v(seg_.back().dur); }
};

/// Distance covered by a ramp v0 -> v1 at `rate` with jerk share p (the S-curve's symmetric
/// velocity curve covers the same distance as a trapezoid at the effective rate rate*(1-p/2)).
double ramp_distance(double v0, double v1, double rate, double jerk_share);

} // namespace rcsim::camc
