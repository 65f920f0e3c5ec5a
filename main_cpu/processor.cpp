// rcsim — single-processor arbitration of the main CPU's activities (see processor.h).
// sc_spawn (the chooser, a method process of the processor's own)
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include "main_cpu/processor.h"

#include <algorithm>
#include <string>

namespace rcsim {

Processor::Processor(const char* name)
    : granted_((std::string(name) + "_granted").c_str()), choose_((std::string(name) + "_choose").c_str()) {
    sc_core::sc_spawn_options o;
    o.spawn_method();
    o.set_sensitivity(&choose_);
    o.dont_initialize();
    sc_core::sc_spawn([this] { choose(); }, (std::string(name) + "_chooser").c_str(), &o);
}

void Processor::acquire(Priority prio) {
    const std::uint64_t ticket = next_ticket_++;
    waiters_.push_back(Waiter{static_cast<int>(prio), ticket});
    if (!owned_) choose_soon();
    // Every waiter wakes on a grant; only the one whose ticket was chosen proceeds.
    while (owner_ticket_ != ticket) sc_core::wait(granted_);
}

void Processor::release() {
    owned_ = false;
    busy_total_ += sc_core::sc_time_stamp() - busy_since_;
    if (!waiters_.empty()) choose_soon();
}

// The processor is free and someone waits: the owner is chosen a delta cycle later, among all
// that asked by then. So the activities that release and ask for it at the same instant compete by
// priority, whatever order the kernel happens to run them in (that order follows the other
// processes' events at that time, e.g. how often the comm CPU synchronised, which must not change
// a report).
void Processor::choose_soon() {
    if (choosing_) return;
    choosing_ = true;
    choose_.notify(sc_core::SC_ZERO_TIME);
}

void Processor::choose() {
    choosing_ = false;
    if (owned_ || waiters_.empty()) return;
    auto best = std::min_element(waiters_.begin(), waiters_.end(), [](const Waiter& a, const Waiter& b) {
        return a.prio != b.prio ? a.prio < b.prio : a.ticket < b.ticket;
    });
    owned_ = true;
    busy_since_ = sc_core::sc_time_stamp();
    owner_ticket_ = best->ticket;
    owner_prio_ = static_cast<Priority>(best->prio);
    waiters_.erase(best);
    granted_.notify(sc_core::SC_ZERO_TIME);
}

const char* Processor::activity(Priority p) {
    switch (p) {
    case Priority::control_cycle: return "the control cycle";
    case Priority::interrupt: return "the INT_R handler";
    case Priority::command: return "command processing";
    case Priority::transmit: return "response transmission";
    }
    return "?";
}

sc_core::sc_time Processor::busy_time() const {
    return owned_ ? busy_total_ + (sc_core::sc_time_stamp() - busy_since_) : busy_total_;
}

} // namespace rcsim
