// rcsim — CAMC-QI speed profiles (see profile.h).
#include "camc_qi/profile.h"

#include <algorithm>
#include <cmath>

namespace rcsim::camc {

double ramp_distance(double v0, double v1, double rate, double jerk_share) {
    const double eff = rate * (1 - jerk_share / 2);
    return std::abs(v1 * v1 - v0 * v0) / (2 * eff);
}

void SpeedProfile::append(double dur, double a0, double j) {
    if (!(dur > 0)) return;
    seg_.push_back({t_end(), dur, s_end(), v_end(), a0, j});
}

void SpeedProfile::ramp(double v_from, double v_to, double rate, double p) {
    const double dv = std::abs(v_to - v_from);
    if (dv <= 0) return;
    const double sg = v_to > v_from ? 1.0 : -1.0;
    // Total ramp time with max acceleration `rate` and a share p of it in the two jerk ramps.
    const double T = dv / (rate * (1 - p / 2));
    if (p <= 0) {
        append(T, sg * rate, 0);
        return;
    }
    const double tj = p * T / 2, ta = T - 2 * tj;
    append(tj, 0, sg * rate / tj);
    append(ta, sg * rate, 0);
    append(tj, sg * rate, -sg * rate / tj);
}

SpeedProfile SpeedProfile::preset(const ProfileParams& p, double distance, bool tail) {
    SpeedProfile prof;
    const double v0 = p.start_speed, vm = std::max(p.object_speed, p.start_speed);
    prof.v_start_ = v0;
    prof.tail_v_ = tail ? v0 : 0;
    if (distance <= 0) return prof;
    const double up = ramp_distance(v0, vm, p.accel, p.accel_jerk);
    const double dn = ramp_distance(vm, v0, p.decel, p.decel_jerk);
    // A drive starting and ending at STD with no room to ramp runs at STD throughout.
    if (vm <= v0) {
        prof.append(distance / v0, 0, 0);
        prof.decel_from_ = prof.seg_.size();
        return prof;
    }
    if (up + dn <= distance) {
        prof.ramp(v0, vm, p.accel, p.accel_jerk);
        prof.append((distance - up - dn) / vm, 0, 0);
        prof.decel_from_ = prof.seg_.size();
        prof.ramp(vm, v0, p.decel, p.decel_jerk);
    } else {
        // Triangle (or S without cruise): the peak that makes up + down = distance.
        const double ea = p.accel * (1 - p.accel_jerk / 2), ed = p.decel * (1 - p.decel_jerk / 2);
        const double vp = std::sqrt(v0 * v0 + 2 * distance * ea * ed / (ea + ed));
        prof.ramp(v0, vp, p.accel, p.accel_jerk);
        prof.decel_from_ = prof.seg_.size();
        prof.ramp(vp, v0, p.decel, p.decel_jerk);
    }
    return prof;
}

SpeedProfile SpeedProfile::continuous(const ProfileParams& p) {
    SpeedProfile prof;
    const double v0 = p.start_speed, vm = std::max(p.object_speed, p.start_speed);
    prof.v_start_ = v0;
    prof.ramp(v0, vm, p.accel, p.accel_jerk);
    prof.tail_v_ = vm;
    return prof;
}

const SpeedProfile::Segment* SpeedProfile::find(double t) const {
    // Segments are few (at most 7 plus a stop ramp): a linear scan is the fastest.
    for (const Segment& s : seg_)
        if (t < s.end()) return &s;
    return nullptr;
}

double SpeedProfile::position(double t) const {
    if (t <= 0) return 0;
    if (const Segment* s = find(t)) return s->s(t - s->t0);
    return s_end() + tail_v_ * (t - t_end());
}

double SpeedProfile::velocity(double t) const {
    if (t < 0) return 0;
    if (const Segment* s = find(t)) return s->v(t - s->t0);
    return tail_v_;
}

SpeedProfile::Phase SpeedProfile::phase(double t) const {
    if (const Segment* s = find(t)) {
        const double a = s->a0 + s->j * (t - s->t0);
        if (a > 1e-9) return Phase::up;
        if (a < -1e-9) return Phase::down;
        return Phase::constant;
    }
    return tail_v_ > 0 ? Phase::constant : Phase::idle;
}

double SpeedProfile::end_time() const { return tail_v_ > 0 ? never : t_end(); }

double SpeedProfile::time_of(double target) const {
    if (target <= 0) return 0;
    if (target > s_end()) return tail_v_ > 0 ? t_end() + (target - s_end()) / tail_v_ : never;
    for (const Segment& s : seg_) {
        if (s.s(s.dur) < target) continue;
        // Position is monotone (speed >= 0): bisect inside the segment.
        double lo = 0, hi = s.dur;
        for (int i = 0; i < 80 && hi - lo > 1e-13; ++i) {
            const double mid = (lo + hi) / 2;
            (s.s(mid) < target ? lo : hi) = mid;
        }
        return s.t0 + hi;
    }
    return t_end();
}

void SpeedProfile::cut(double t) {
    if (t >= t_end()) {
        if (tail_v_ > 0) append(t - t_end(), 0, 0); // the tail runs at the last segment's end speed
    } else {
        auto it = std::find_if(seg_.begin(), seg_.end(), [&](const Segment& s) { return t < s.end(); });
        it->dur = t - it->t0;
        seg_.erase(it + 1, seg_.end());
        if (!(seg_.back().dur > 0)) seg_.pop_back();
    }
    tail_v_ = 0;
}

void SpeedProfile::slow_down(double t, const ProfileParams& p) {
    if (tail_v_ == 0 && t >= t_end()) return;              // already ended
    if (decel_from_ < seg_.size() && t >= seg_[decel_from_].t0) return; // already decelerating
    const double v = velocity(t);
    if (v <= p.start_speed) { // in the STD tail or at STD: stop now
        stop(t);
        return;
    }
    cut(t);
    decel_from_ = seg_.size();
    ramp(v, p.start_speed, p.decel, p.decel_jerk);
}

void SpeedProfile::stop(double t) {
    if (tail_v_ == 0 && t >= t_end()) return;
    cut(t);
    decel_from_ = seg_.size();
}

} // namespace rcsim::camc
