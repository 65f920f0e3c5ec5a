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

SpeedProfile SpeedProfile::preset(const ProfileParams& p, double distance, bool tail, double entry) {
    SpeedProfile prof;
    const double v0 = p.start_speed, vin = entry > 0 ? entry : v0;
    prof.v_start_ = vin;
    prof.tail_v_ = tail ? v0 : 0;
    if (distance <= 0) return prof;
    prof.plan(vin, v0, std::max(p.object_speed, v0), distance, p);
    return prof;
}

void SpeedProfile::plan(double v_in, double v_out, double vm, double distance, const ProfileParams& p) {
    // Up-ramps at RATE1/SW1, down-ramps at RATE2/SW2.
    auto rate = [&](double a, double b) { return b > a ? p.accel : p.decel; };
    auto share = [&](double a, double b) { return b > a ? p.accel_jerk : p.decel_jerk; };
    auto ramp_to = [&](double a, double b) { ramp(a, b, rate(a, b), share(a, b)); };
    const double up = ramp_distance(v_in, vm, rate(v_in, vm), share(v_in, vm));
    const double dn = ramp_distance(vm, v_out, rate(vm, v_out), share(vm, v_out));
    if (up + dn <= distance) {
        // A drive starting and ending at STD with no room to ramp (vm = STD) cruises throughout.
        ramp_to(v_in, vm);
        append((distance - up - dn) / vm, 0, 0);
        decel_from_ = seg_.size();
        ramp_to(vm, v_out);
        return;
    }
    // Triangle (or S without cruise): the peak that makes up + down = distance.
    const double ea = p.accel * (1 - p.accel_jerk / 2), ed = p.decel * (1 - p.decel_jerk / 2);
    const double vp = std::sqrt((2 * distance * ea * ed + ed * v_in * v_in + ea * v_out * v_out) / (ea + ed));
    if (vp >= v_in && vp >= v_out) {
        ramp_to(v_in, vp);
        decel_from_ = seg_.size();
        ramp_to(vp, v_out);
        return;
    }
    // No room to reach the wanted end speed at the programmed rates (a blend planned late): one
    // constant-rate ramp from v_in to v_out over exactly the distance, so the drive still ends
    // on its step.
    decel_from_ = seg_.size();
    if (std::abs(v_out - v_in) < 1e-9) {
        append(distance / v_in, 0, 0);
        return;
    }
    const double a = (v_out * v_out - v_in * v_in) / (2 * distance);
    append((v_out - v_in) / a, a, 0);
}

bool SpeedProfile::blend_exit(double t, double exit, const ProfileParams& p) {
    if (tail_v_ > 0 || t >= t_end()) return false;
    const double total = s_end(), s = position(t), v = velocity(t);
    cut(t);
    plan(v, exit, std::max(p.object_speed, p.start_speed), total - s, p);
    return true;
}

SpeedProfile SpeedProfile::continuous(const ProfileParams& p, double entry) {
    SpeedProfile prof;
    const double v0 = entry > 0 ? entry : p.start_speed, vm = std::max(p.object_speed, p.start_speed);
    prof.v_start_ = v0;
    if (vm >= v0) prof.ramp(v0, vm, p.accel, p.accel_jerk);
    else prof.ramp(v0, vm, p.decel, p.decel_jerk);
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
    // Already decelerating to STD (a drive re-planned to end faster, for blending, still stops).
    if (decel_from_ < seg_.size() && t >= seg_[decel_from_].t0 && v_end() <= p.start_speed) return;
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
