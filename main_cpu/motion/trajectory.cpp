// rcsim — the trajectory recorder. See trajectory.h.
#include "main_cpu/motion/trajectory.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <limits>

namespace rcsim::motion {

namespace {

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
constexpr std::size_t kVelAxes = 4;

/// The figures the pictures plot of one sample (NaN: not plotted for it), in Bucket's order.
std::array<double, 22> figures(const TrajectorySample& s) {
    std::array<double, 22> f;
    f.fill(kNone);
    const std::size_t n = std::min({s.cmd.size(), s.act.size(), kVelAxes});
    for (std::size_t a = 0; a < n; ++a) {
        f[5 * a] = double(s.cmd[a]);
        f[5 * a + 1] = double(s.act[a]);
        f[5 * a + 2] = double(s.cmd[a] - s.act[a]);
        if (s.has_velocity) f[5 * a + 3] = s.vel_cmd[a], f[5 * a + 4] = s.vel_act[a];
    }
    if (s.has_velocity && n >= 2) {
        f[20] = std::hypot(s.vel_cmd[0], s.vel_cmd[1]);
        f[21] = std::hypot(s.vel_act[0], s.vel_act[1]);
    }
    return f;
}

} // namespace

TrajectoryRecorder::TrajectoryRecorder(std::size_t plot_cap, std::size_t recent)
    : cap_(std::max<std::size_t>(plot_cap, 2 * 2 * (Bucket::kFigures + 1))), recent_cap_(std::max<std::size_t>(recent, 2)) {
    kept_.reserve(cap_ + 2 * Bucket::kFigures + 2); // its most: a run's pages are touched once
}

void TrajectoryRecorder::Bucket::add(const Kept& k) {
    const auto f = figures(k.s);
    if (!any) {
        any = true;
        first = k;
        lo_v.fill(kNone);
        hi_v.fill(kNone);
    }
    last = k;
    for (std::size_t i = 0; i < kFigures; ++i) {
        if (std::isnan(f[i])) continue;
        if (!(f[i] >= lo_v[i])) lo_v[i] = f[i], lo[i] = k; // true too while lo_v[i] is NaN
        if (!(f[i] <= hi_v[i])) hi_v[i] = f[i], hi[i] = k;
    }
}

std::vector<TrajectoryRecorder::Kept> TrajectoryRecorder::Bucket::picks() const {
    std::vector<Kept> out;
    if (!any) return out;
    out.push_back(first);
    out.push_back(last);
    for (std::size_t i = 0; i < kFigures; ++i)
        if (!std::isnan(lo_v[i])) out.push_back(lo[i]), out.push_back(hi[i]);
    std::sort(out.begin(), out.end(), [](const Kept& a, const Kept& b) { return a.index < b.index; });
    out.erase(std::unique(out.begin(), out.end(), [](const Kept& a, const Kept& b) { return a.index == b.index; }),
              out.end());
    return out;
}

void TrajectoryRecorder::add(double t, std::vector<std::int64_t> cmd, std::vector<std::int64_t> act) {
    TrajectorySample s{t, std::move(cmd), std::move(act)};
    if (const TrajectorySample* p = last(); p && t > p->t_s) {
        s.has_velocity = true;
        const std::size_t n = std::min({s.cmd.size(), s.act.size(), p->cmd.size(), p->act.size(), kVelAxes});
        for (std::size_t a = 0; a < n; ++a) {
            s.vel_cmd[a] = double(s.cmd[a] - p->cmd[a]) / (t - p->t_s);
            s.vel_act[a] = double(s.act[a] - p->act[a]) / (t - p->t_s);
        }
    }
    for (std::size_t a = 0; a < s.cmd.size() && a < s.act.size(); ++a)
        max_follow_ = std::max(max_follow_, double(std::llabs(s.cmd[a] - s.act[a])));
    for (const Sink& sink : sinks_) sink(s);
    if (window_open_) window_.push_back(s);

    const Kept k{count_++, s};
    if (width_ == 1) {
        kept_.push_back(k);
        if (kept_.size() > cap_) coarsen();
    } else {
        if (open_.any && k.index / width_ != open_.id) close_bucket();
        open_.id = k.index / width_;
        open_.add(k);
    }
    recent_.push_back(std::move(s));
    if (recent_.size() > recent_cap_) recent_.pop_front();
}

void TrajectoryRecorder::close_bucket() {
    for (Kept& k : open_.picks()) kept_.push_back(std::move(k));
    open_.any = false;
    if (kept_.size() > cap_) coarsen();
}

// Doubles the buckets' width until the picks fill at most half the cap: each sample is picked
// again O(log n) times over a run, and the pictures never hold more than the cap.
void TrajectoryRecorder::coarsen() {
    if (open_.any) {
        for (Kept& k : open_.picks()) kept_.push_back(std::move(k));
        open_.any = false;
    }
    while (kept_.size() > cap_ / 2) {
        width_ *= 2;
        std::vector<Kept> merged;
        Bucket b;
        for (const Kept& k : kept_) {
            if (b.any && k.index / width_ != b.id) {
                for (Kept& p : b.picks()) merged.push_back(std::move(p));
                b.any = false;
            }
            b.id = k.index / width_;
            b.add(k);
        }
        for (Kept& p : b.picks()) merged.push_back(std::move(p));
        kept_.assign(std::make_move_iterator(merged.begin()), std::make_move_iterator(merged.end()));
    }
}

std::vector<TrajectorySample> TrajectoryRecorder::plot_samples() const {
    std::vector<TrajectorySample> out;
    out.reserve(kept_.size() + 2 * Bucket::kFigures + 2);
    for (const Kept& k : kept_) out.push_back(k.s);
    for (const Kept& k : open_.picks()) out.push_back(k.s);
    return out;
}

const TrajectorySample* TrajectoryRecorder::last(std::size_t back) const {
    return recent_.size() > back ? &recent_[recent_.size() - 1 - back] : nullptr;
}

void TrajectoryRecorder::start_window() {
    window_.clear();
    window_open_ = true;
}

} // namespace rcsim::motion
