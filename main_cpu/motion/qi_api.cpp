// rcsim — the motion-controller paper's C motion library over CAMC-QI registers. See qi_api.h.
#include "main_cpu/motion/qi_api.h"

#include <cmath>
#include <utility>

namespace rcsim::motion {

using namespace camc;

int QiMotionApi::SignalSetHomeLevel(int a, unsigned level) {
    if (!axis_ok(a)) return axl::invalid_axis;
    if (level == level_high) ucfg1_[a] |= ucfg::org_high;
    else ucfg1_[a] &= ~ucfg::org_high;
    bus_.write(a, qi::write | qi::UCFG1, ucfg1_[a]);
    return axl::success;
}

int QiMotionApi::SignalSetLimit(int a, unsigned stop_mode, unsigned pos_level, unsigned neg_level) {
    if (!axis_ok(a)) return axl::invalid_axis;
    std::uint32_t v = ucfg1_[a] & ~(ucfg::pelm_high | ucfg::pelm_used | ucfg::nelm_high | ucfg::nelm_used |
                                    ucfg::limit_slowdown);
    if (pos_level != level_unused) v |= ucfg::pelm_used | (pos_level == level_high ? ucfg::pelm_high : 0);
    if (neg_level != level_unused) v |= ucfg::nelm_used | (neg_level == level_high ? ucfg::nelm_high : 0);
    if (stop_mode == stop_slowdown) v |= ucfg::limit_slowdown;
    ucfg1_[a] = v;
    bus_.write(a, qi::write | qi::UCFG1, v);
    return axl::success;
}

void QiMotionApi::uio(int a, unsigned bit, bool on) {
    std::uint32_t v = bus_.read(a, qi::UIO);
    v = on ? (v | bit) : (v & ~bit);
    bus_.write(a, qi::write | qi::UIO, v);
}

int QiMotionApi::SignalServoOn(long a, unsigned on) {
    if (!axis_ok(a)) return axl::invalid_axis;
    uio(static_cast<int>(a), 1u, on != 0);
    return axl::success;
}

int QiMotionApi::SignalServoAlarmReset(int a, unsigned on) {
    if (!axis_ok(a)) return axl::invalid_axis;
    uio(a, 2u, on != 0);
    return axl::success;
}

namespace {
std::uint32_t reg(double v) { return static_cast<std::uint32_t>(std::max(1.0, std::round(v))); }
bool in_range(std::int64_t p) { return p >= -max_coordinate && p <= max_coordinate; }
} // namespace

namespace {
/// The jerk share (0..1) of a ramp of dv at rate `rate` whose jerk is `jerk`: a ramp of T = dv /
/// (rate (1 - p/2)) with jerk sections of p T / 2 each has jerk rate / (p T / 2), hence
/// p = 2 rate^2 / (jerk dv + rate^2). Below jerk = rate^2 / dv even p = 1 is too steep: the rate
/// is lowered to sqrt(jerk dv), a pure S with exactly that jerk.
double jerk_share(double& rate, double dv, double jerk) {
    if (!(dv > 0)) return 0;
    if (jerk * dv < rate * rate) {
        rate = std::sqrt(jerk * dv);
        return 1;
    }
    return 2 * rate * rate / (jerk * dv + rate * rate);
}
} // namespace

int QiMotionApi::speeds(int a, double vel, double acc, double dec, std::uint32_t mode_bits) {
    if (!(vel > 0)) return axl::invalid_velocity;
    if (!(acc > 0) || !(dec > 0)) return axl::invalid_accel;
    if (vel > CamcQi::max_pps) return axl::velocity_out_of_bound;
    const double std_speed = std::min(start_speed_[a], vel);
    static constexpr std::uint32_t chip_profile[] = {0, 1, 2, 2, 3}; // AXL mode -> DCFG 1:0
    std::uint32_t prof = chip_profile[profile_[a]];
    double pa = accel_jerk_[a] / 100, pd = 0; // no AxmMotSetDecelJerk: SW2 only from a Jerk
    if (const double jerk = std::exchange(jerk_[a], 0.0); jerk > 0) { // for this move only
        prof = 3; // asymmetric S: its own share per ramp
        pa = jerk_share(acc, vel - std_speed, jerk);
        pd = jerk_share(dec, vel - std_speed, jerk);
    }
    bus_.write(a, qi::write | qi::STD, reg(std_speed));
    bus_.write(a, qi::write | qi::OBJ, reg(vel));
    bus_.write(a, qi::write | qi::RATE1, reg(acc));
    bus_.write(a, qi::write | qi::RATE2, reg(dec));
    if (prof >= 2) { // S-curves: SW1/SW2 hold whole percent
        bus_.write(a, qi::write | qi::SW1, static_cast<std::uint32_t>(std::lround(100 * pa)));
        bus_.write(a, qi::write | qi::SW2, static_cast<std::uint32_t>(std::lround(100 * pd)));
    }
    bus_.write(a, qi::write | qi::DCFG, mode_bits | prof);
    set_master(1u << a, a, 1);
    return axl::success;
}

void QiMotionApi::set_master(std::uint32_t mask, int master, double scale) {
    for (int i = 0; i < 4; ++i)
        if (mask & (1u << i)) master_[i] = master, step_scale_[i] = scale;
}

int QiMotionApi::SetProfileMode(int a, unsigned mode) {
    if (!axis_ok(a)) return axl::invalid_axis;
    if (mode > 4 || mode == 2) return axl::profile_invalid;
    profile_[a] = mode;
    return axl::success;
}

int QiMotionApi::SetAccelJerk(int a, double percent) {
    if (!axis_ok(a)) return axl::invalid_axis;
    if (!(percent >= 0 && percent <= 100)) return axl::profile_invalid;
    accel_jerk_[a] = percent;
    return axl::success;
}

int QiMotionApi::SetJerk(int a, double jerk) {
    if (!axis_ok(a)) return axl::invalid_axis;
    if (!(jerk >= 0) || !std::isfinite(jerk)) return axl::profile_invalid;
    jerk_[a] = jerk;
    return axl::success;
}

int QiMotionApi::SetBlend(int a, double vel) {
    if (!axis_ok(a)) return axl::invalid_axis;
    if (!(vel >= 0) || !(vel <= CamcQi::max_pps)) return axl::invalid_velocity;
    blend_[a] = vel;
    return axl::success;
}

bool QiMotionApi::BlendQueued(int a) { return !(bus_.read(a, qi::STAT2) & drvst::queue_empty); }

double QiMotionApi::take_blend(int m, bool busy) {
    const double vb = std::exchange(blend_[m], 0.0);
    return busy && vb > 0 ? vb : 0;
}

void QiMotionApi::blend_speeds(int m, double vel, double new_scale) {
    // The running drive's rates are its master's, in its own steps (step_scale_ before this move).
    bus_.write(m, qi::write | qi::JSPD, reg(vel * new_scale));
    bus_.write(master_[m], qi::write | qi::JEXIT, reg(vel * step_scale_[m]));
}

int QiMotionApi::MovePos(int a, std::int32_t pos, double vel, double acc, double dec) {
    if (!axis_ok(a)) return axl::invalid_axis;
    if (!in_range(pos)) return axl::position_out_of_bound;
    const bool busy = InMotion(a);
    const bool over = std::exchange(take_over_[a], false) && busy;
    const double vb = over ? 0 : take_blend(a, busy);
    if (busy && !(vb > 0) && !over) return axl::in_motion;
    if (vb > 0) blend_speeds(a, vb, 1);
    if (int r = speeds(a, vel, acc, dec, (dcfg::preset << dcfg::mode_shift) | (vb > 0 ? dcfg::blend : 0) |
                                             (over ? dcfg::take_over : 0)))
        return r;
    // A blended move starts where the running one ends; a take-over's POS is absolute.
    // |dist| <= 2^31 - 2: fits POS.
    const std::int64_t dist = over ? pos : std::int64_t{pos} - (vb > 0 ? target_[a] : CmdPos(a));
    target_[a] = pos;
    bus_.write(a, qi::write | qi::POS, static_cast<std::uint32_t>(dist));
    bus_.write(a, qi::STRN, 0);
    return (EndStatus(a) & (endst::alarm | endst::pelm | endst::nelm | endst::estop_signal)) ? axl::sensor_check
                                                                                             : axl::success;
}

int QiMotionApi::MoveVel(int a, double vel, double acc, double dec) {
    if (!axis_ok(a)) return axl::invalid_axis;
    const bool over = std::exchange(take_over_[a], false) && InMotion(a);
    if (!over && InMotion(a)) return axl::in_motion;
    const std::uint32_t m = ((vel < 0 ? dcfg::cont_neg : dcfg::cont_pos) << dcfg::mode_shift) | (over ? dcfg::take_over : 0);
    if (int r = speeds(a, std::abs(vel), acc, dec, m)) return r;
    bus_.write(a, qi::STRN, 0);
    return (EndStatus(a) & ~endst::slowdown_cmd) ? axl::sensor_check : axl::success;
}

int QiMotionApi::HomeSetMethod(int a, const HomeMethod& m) {
    if (!axis_ok(a)) return axl::invalid_axis;
    if (!(m.vel_first > 0) || !(m.vel_second > 0) || !(m.vel_third > 0) || !(m.vel_last > 0)) return axl::invalid_velocity;
    if (!(m.acc_first > 0) || !(m.acc_second > 0)) return axl::invalid_accel;
    const double top = std::max({m.vel_first, m.vel_second, m.vel_third, m.vel_last});
    if (top > CamcQi::max_pps) return axl::velocity_out_of_bound;
    homing_[a].method = m;
    return axl::success;
}

int QiMotionApi::HomeSetStart(int a) {
    if (!axis_ok(a)) return axl::invalid_axis;
    if (InMotion(a)) return axl::in_motion;
    homing_[a].step = 0;
    homing_[a].result = home::searching;
    ClearEndStatus(a);
    return home_step(a);
}

/// Starts step `homing_[a].step` as a chip signal search.
int QiMotionApi::home_step(int a) {
    const HomeMethod& m = homing_[a].method;
    struct Step {
        int dir;
        double vel, acc;
        std::uint32_t signal;
        bool inactive, immediate;
    };
    // Search and back off stop with a ramp (fast); the approach and Z stop on the edge itself.
    const Step steps[] = {
        {m.dir, m.vel_first, m.acc_first, dcfg::sig_org, false, false},
        {-m.dir, m.vel_second, m.acc_second, dcfg::sig_org, true, false},
        {m.dir, m.vel_third, m.acc_second, dcfg::sig_org, false, true},
        {-m.dir, m.vel_last, m.acc_second, dcfg::sig_z, false, true},
    };
    const Step& st = steps[homing_[a].step];
    const std::uint32_t mode = ((st.dir < 0 ? dcfg::origin_neg : dcfg::origin_pos) << dcfg::mode_shift) |
                               (st.signal << dcfg::signal_shift) | (st.inactive ? dcfg::search_inactive : 0) |
                               (st.immediate ? dcfg::search_immediate : 0);
    if (int r = speeds(a, st.vel, st.acc, st.acc, mode)) return r;
    bus_.write(a, qi::write | qi::OBJORG, reg(st.vel));
    bus_.write(a, qi::STRN, 0);
    return axl::success;
}

unsigned QiMotionApi::HomeGetResult(int a) {
    if (!axis_ok(a)) return home::err_not_detect;
    Homing& h = homing_[a];
    if (h.step < 0) return h.result;
    if (InMotion(a)) return home::searching;
    const std::uint32_t es = EndStatus(a);
    const std::uint32_t found = h.step == 3 ? endst::signal_ok : endst::home_ok;
    unsigned r = home::searching;
    if (es & endst::pelm) r = home::err_pos_limit;
    else if (es & endst::nelm) r = home::err_neg_limit;
    else if (es & endst::alarm) r = home::err_amp_fault;
    else if (!(es & found)) r = home::err_not_detect;
    else if (h.step < (h.method.zphase ? 3 : 2)) {
        ++h.step;
        ClearEndStatus(a);
        if (home_step(a) != axl::success) r = home::err_not_detect;
    } else {
        r = home::success;
    }
    if (r != home::searching) {
        h.step = -1;
        h.result = r;
    }
    return r;
}

int QiMotionApi::SetCoord(int c, std::uint32_t mask) {
    if (c < 0 || c >= coords || mask == 0 || mask > 0xF) return axl::invalid_axis;
    coord_[c] = mask;
    return axl::success;
}

int QiMotionApi::LineMove(int c, const std::int32_t* pos, double vel, double acc, double dec) {
    if (c < 0 || c >= coords) return axl::invalid_axis;
    const std::uint32_t mask = coord_[c];
    int master = -1;
    double len2 = 0;
    std::int64_t longest = 0;
    unsigned n = 0;
    bool busy = false;
    for (int a = 0; a < 4; ++a) {
        if (!(mask & (1u << a))) continue;
        if (master < 0) master = a;
        busy |= InMotion(a);
        const std::int64_t d = pos[n++];
        if (!in_range(d)) return axl::position_out_of_bound;
        len2 += static_cast<double>(d) * static_cast<double>(d);
        longest = std::max(longest, d < 0 ? -d : d);
    }
    const double vb = master >= 0 ? take_blend(master, busy) : 0;
    if (busy && !(vb > 0)) return axl::in_motion;
    if (!(vel > 0)) return axl::invalid_velocity;
    if (len2 == 0) return axl::success; // nothing to move
    // The chip's speed is the long axis' step rate; scale so that the path speed is Vel.
    const double k = static_cast<double>(longest) / std::sqrt(len2);
    if (vb > 0) blend_speeds(master, vb, k);
    if (int r = speeds(master, vel * k, acc * k, dec * k,
                       (dcfg::linear << dcfg::mode_shift) | (mask << dcfg::axes_shift) | (vb > 0 ? dcfg::blend : 0)))
        return r;
    set_master(mask, master, k);
    n = 0;
    for (int a = 0; a < 4; ++a)
        if (mask & (1u << a)) bus_.write(a, qi::write | qi::POS, static_cast<std::uint32_t>(pos[n++]));
    bus_.write(master, qi::write | qi::ISNUM, static_cast<std::uint32_t>(longest));
    bus_.write(master, qi::STRN, 0);
    const std::uint32_t es = EndStatus(master);
    return (es & (endst::interp_data | endst::data_error)) ? axl::interpolation_value
           : (es & (endst::alarm | endst::pelm | endst::nelm | endst::estop_signal)) ? axl::sensor_check
                                                                                    : axl::success;
}

int QiMotionApi::CircleCenterMove(int c, std::int32_t cx, std::int32_t cy, std::int32_t ex, std::int32_t ey, double vel,
                                  double acc, double dec, int dir) {
    if (c < 0 || c >= coords) return axl::invalid_axis;
    int ids[2], n = 0;
    for (int a = 0; a < 4; ++a)
        if (coord_[c] & (1u << a)) {
            if (n == 2) return axl::invalid_axis;
            ids[n++] = a;
        }
    if (n != 2 || (dir != dir_cw && dir != dir_ccw)) return axl::invalid_axis;
    const bool busy = InMotion(ids[0]) || InMotion(ids[1]);
    const double vb = take_blend(ids[0], busy);
    if (busy && !(vb > 0)) return axl::in_motion;
    if (!(vel > 0)) return axl::invalid_velocity;
    const Point s{-std::int64_t{cx}, -std::int64_t{cy}};
    const Point e{std::int64_t{ex} - cx, std::int64_t{ey} - cy};
    const ArcDirection ad = dir == dir_cw ? ArcDirection::cw : ArcDirection::ccw;
    std::uint64_t steps = 0;
    try {
        // The paper's eqs. 1-10 on the pulse lattice, plus the chip's final correction step when
        // the end lies off the track (camc_qi/README.md "Circular interpolation").
        const CircleWalk w = circle_walk(s, e, ad);
        steps = w.steps + (w.end != e ? 1 : 0);
    } catch (const InterpolationError&) {
        return axl::interpolation_value;
    }
    // Constant vector speed: Vel, Acc and Dec are along the arc (PLCopen's path velocity), the
    // chip spaces the steps by the arc length they cover.
    if (vb > 0) blend_speeds(ids[0], vb, 1);
    if (int r = speeds(ids[0], vel, acc, dec,
                       ((dir == dir_cw ? dcfg::circle_cw : dcfg::circle_ccw) << dcfg::mode_shift) |
                           (coord_[c] << dcfg::axes_shift) | dcfg::vector_speed | (vb > 0 ? dcfg::blend : 0)))
        return r;
    set_master(coord_[c], ids[0], 1);
    bus_.write(ids[0], qi::write | qi::CENT, static_cast<std::uint32_t>(cx));
    bus_.write(ids[1], qi::write | qi::CENT, static_cast<std::uint32_t>(cy));
    bus_.write(ids[0], qi::write | qi::POS, static_cast<std::uint32_t>(ex));
    bus_.write(ids[1], qi::write | qi::POS, static_cast<std::uint32_t>(ey));
    bus_.write(ids[0], qi::write | qi::ISNUM, static_cast<std::uint32_t>(steps));
    bus_.write(ids[0], qi::STRN, 0);
    const std::uint32_t es = EndStatus(ids[0]);
    return (es & (endst::interp_data | endst::data_error)) ? axl::interpolation_value
           : es ? axl::sensor_check : axl::success;
}

int QiMotionApi::SlowStop(int a, double dec) {
    if (!axis_ok(a)) return axl::invalid_axis;
    homing_[a].step = -1; // a stop ends a homing sequence
    homing_[a].result = home::err_not_detect;
    if (dec > 0) {
        const int m = master_[a];
        bus_.write(m, qi::write | qi::RATE2, reg(dec * step_scale_[a]));
        bus_.write(m, qi::write | qi::DCFG, bus_.read(m, qi::DCFG) | 1u); // use RATE2
    }
    bus_.write(a, qi::SSTOP, 0);
    return axl::success;
}

int QiMotionApi::EmergencyStop(int a) {
    if (!axis_ok(a)) return axl::invalid_axis;
    homing_[a].step = -1;
    homing_[a].result = home::err_not_detect;
    bus_.write(a, qi::STOP, 0);
    return axl::success;
}

int QiMotionApi::EmergencyStopAll() {
    for (Homing& h : homing_) h = Homing{h.method, -1, home::err_not_detect};
    bus_.write(0, qi::ESTOP, 0);
    return axl::success;
}

bool QiMotionApi::InMotion(int a) { return bus_.read(a, qi::STAT2) & drvst::busy; }
std::uint32_t QiMotionApi::DriveStatus(int a) { return bus_.read(a, qi::STAT2); }
std::uint32_t QiMotionApi::EndStatus(int a) { return bus_.read(a, qi::STAT1); }
void QiMotionApi::ClearEndStatus(int a) { bus_.write(a, qi::ESCLR, 0); }
std::int64_t QiMotionApi::CmdPos(int a) { return static_cast<std::int32_t>(bus_.read(a, qi::CNT1)); }
double QiMotionApi::CurrentSpeed(int a) { return static_cast<double>(bus_.read(a, qi::CURSPD)); }
std::int64_t QiMotionApi::ActPos(int a) { return static_cast<std::int32_t>(bus_.read(a, qi::CNT2)); }
void QiMotionApi::SetPos(int a, std::int64_t pos) {
    const std::int64_t shift = pos - CmdPos(a);
    const std::int64_t act = ActPos(a);
    bus_.write(a, qi::write | qi::CNT1, static_cast<std::uint32_t>(pos));
    bus_.write(a, qi::write | qi::CNT2, static_cast<std::uint32_t>(act + shift));
}

void QiMotionApi::SetCmdPos(int a, std::int64_t pos) {
    bus_.write(a, qi::write | qi::CNT1, static_cast<std::uint32_t>(pos));
}

} // namespace rcsim::motion
