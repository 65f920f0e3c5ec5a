// rcsim — single-processor arbitration of the main CPU's activities (see processor.h).
#include "main_cpu/processor.h"

#include <algorithm>

namespace rcsim {

Processor::Processor(const char* name) : granted_((std::string(name) + "_granted").c_str()) {}

void Processor::acquire(Priority prio) {
    const std::uint64_t ticket = next_ticket_++;
    if (!owned_) {
        owned_ = true;
        owner_ticket_ = ticket;
        busy_since_ = sc_core::sc_time_stamp();
        return;
    }
    waiters_.push_back(Waiter{static_cast<int>(prio), ticket});
    // Every waiter wakes on a grant; only the one whose ticket was chosen proceeds.
    while (owner_ticket_ != ticket) sc_core::wait(granted_);
}

void Processor::release() {
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    if (waiters_.empty()) {
        owned_ = false;
        busy_total_ += now - busy_since_;
        return;
    }
    // Hand over without going idle, so nobody can slip in between release and grant.
    auto best = std::min_element(waiters_.begin(), waiters_.end(), [](const Waiter& a, const Waiter& b) {
        return a.prio != b.prio ? a.prio < b.prio : a.ticket < b.ticket;
    });
    owner_ticket_ = best->ticket;
    waiters_.erase(best);
    granted_.notify(sc_core::SC_ZERO_TIME);
}

sc_core::sc_time Processor::busy_time() const {
    return owned_ ? busy_total_ + (sc_core::sc_time_stamp() - busy_since_) : busy_total_;
}

} // namespace rcsim
