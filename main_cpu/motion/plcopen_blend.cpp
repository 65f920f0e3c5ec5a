// rcsim — PLCopen buffer modes: blending (Part 1 §2.4.2, docs/motion.md "Buffer modes"). The
// CAMC-QI realises the junction: a blended start queues the next drive behind the running one,
// which re-plans its end to the junction speed (camc_qi/README.md "Blending"). See plcopen.h.
#include "main_cpu/motion/plcopen.h"

#include <algorithm>

namespace rcsim::motion {

bool valid(BufferMode m) { return static_cast<unsigned>(m) <= static_cast<unsigned>(BufferMode::blending_high); }

bool blending(BufferMode m) { return valid(m) && m >= BufferMode::blending_low; }

double blend_velocity(BufferMode m, double v1, double v2) {
    switch (m) {
    case BufferMode::blending_low: return std::min(v1, v2);
    case BufferMode::blending_previous: return v1;
    case BufferMode::blending_next: return v2;
    case BufferMode::blending_high: return std::max(v1, v2);
    default: return 0;
    }
}

int master_of(const Job& j) {
    unsigned m = j.axes.front()->index();
    for (const McAxis* a : j.axes) m = std::min(m, a->index());
    return static_cast<int>(m);
}

bool McAxis::try_blend(const std::shared_ptr<Job>& next) {
    const std::shared_ptr<Job> cur = active_;
    if (!next->blendable || !cur || !cur->started || !cur->blendable || cur->status != Job::Status::active ||
        cur->axes.size() != next->axes.size())
        return false;
    for (McAxis* a : next->axes)
        if (a->active_ != cur || a->queued_ != next) return false; // the same axes, this job next
    const int m = master_of(*next);
    if (!api_.InMotion(m) || api_.BlendQueued(m)) return false;
    double vb = blend_velocity(next->mode, cur->velocity, next->velocity);
    if (next->axes.size() == 1) {
        // One axis passes a junction without stopping only when it goes on the same way.
        const int running = (api_.DriveStatus(m) & camc::drvst::negative) ? -1 : 1;
        if (!next->direction || next->direction() != running) vb = 0;
    }
    if (!(vb > 0)) return false;
    api_.SetBlend(m, vb);
    if (next->start() != axl::success || !api_.BlendQueued(m)) {
        api_.SetBlend(m, 0); // not queued on the chip: it stays buffered, and starts after a stop
        return false;
    }
    next->started = true; // Busy, not Active, until the chip takes it at the junction
    return true;
}

bool room_to_take_over(QiMotionApi& api, int axis, std::int64_t rest, double dec) {
    const int way = (api.DriveStatus(axis) & camc::drvst::negative) ? -1 : 1;
    const double v = api.CurrentSpeed(axis);
    return rest * way > 0 && v * v / (2 * dec) <= static_cast<double>(rest * way);
}

bool McAxis::try_take_over(const std::shared_ptr<Job>& job) {
    const std::shared_ptr<Job> cur = active_;
    if (!job->can_take_over || job->axes.size() != 1 || job->axes[0] != this || !cur || !cur->started ||
        cur->status != Job::Status::active || cur->axes.size() != 1 || cur->is_stop || cur->is_home ||
        !(cur->blendable || cur->is_continuous) || (queued_ && queued_->started))
        return false;
    const int ax = static_cast<int>(index_);
    if (!api_.InMotion(ax) || api_.BlendQueued(ax) || !job->can_take_over()) return false;
    cur->status = Job::Status::aborted;
    active_.reset();
    if (queued_) {
        queued_->status = Job::Status::aborted;
        queued_.reset();
    }
    api_.SetTakeOver(ax);
    active_ = job;
    state_ = job->motion_state;
    start(job);
    api_.SetTakeOver(ax, false); // unused when the move failed before reaching the chip
    return true;
}

} // namespace rcsim::motion
