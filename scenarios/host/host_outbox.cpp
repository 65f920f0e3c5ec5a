// rcsim — the bounded queue of controller bytes for a host backend's client (host_outbox.h).
#include "scenarios/host/host_outbox.h"

#include <stdexcept>

namespace rcsim {

HostOutbox::HostOutbox(std::size_t max_bytes) : max_bytes_(max_bytes) {
    if (max_bytes == 0) throw std::invalid_argument("HostOutbox: max_bytes must be > 0");
}

void HostOutbox::push(const SerialRx& c) {
    std::lock_guard<std::mutex> lock(mu_);
    ++counters_.received;
    if (c.parity_error || c.framing_error) ++counters_.line_errors;
    // Dropped before the push, so the deque never holds more than max_bytes_.
    if (bytes_.size() == max_bytes_) {
        bytes_.pop_front();
        ++counters_.dropped;
    }
    bytes_.push_back(static_cast<std::uint8_t>(c.data));
}

void HostOutbox::note_break(bool active) {
    if (!active) return;
    std::lock_guard<std::mutex> lock(mu_);
    ++counters_.breaks;
}

bool HostOutbox::take(std::vector<std::uint8_t>& out) {
    std::lock_guard<std::mutex> lock(mu_);
    if (bytes_.empty()) return false;
    out.assign(bytes_.begin(), bytes_.end());
    bytes_.clear();
    return true;
}

HostOutbox::Counters HostOutbox::counters() const {
    std::lock_guard<std::mutex> lock(mu_);
    return counters_;
}

std::size_t HostOutbox::held() const {
    std::lock_guard<std::mutex> lock(mu_);
    return bytes_.size();
}

} // namespace rcsim
