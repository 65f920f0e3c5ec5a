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

} // namespace rcsim::motion
