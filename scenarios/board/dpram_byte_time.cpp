// rcsim — the DP-RAM time per byte, gathered online. See dpram_byte_time.h.
#include "scenarios/board/dpram_byte_time.h"

#include "models/clock.h"

#include <algorithm>

namespace rcsim {

using sc_core::sc_time;

namespace {
/// The part of [a, b] inside [first, end], added to `sum`: one term of the handler time.
void add_inside(double& sum, const sc_time& first, const sc_time& end, const sc_time& a, const sc_time& b) {
    const sc_time lo = std::max(first, a), hi = std::min(end, b);
    if (hi > lo) sum += to_us(hi - lo);
}
} // namespace

void DpramByteTime::data_write(unsigned port, const sc_time& t, unsigned width) {
    Chunk*& open = open_[port];
    if (!open) {
        chunks_.push_back(Chunk{port, t, t});
        open = &chunks_.back(); // a deque keeps its elements in place as it grows at either end
    } else {
        // Every interrupt completed since the last write ended before this one (bus order).
        open->isr_us = open->isr_more_us;
    }
    open->last = t;
    ++open->writes;
    open->bytes += width;
    if (chunks_.size() > kMaxPending && !chunks_.front().closed) {
        chunk_closed(chunks_.front().port);
        settle();
    }
}

void DpramByteTime::chunk_closed(unsigned port) {
    if (!open_[port]) return;
    open_[port]->closed = true; // isr_us already ends the span at the last write
    open_[port] = nullptr;
}

void DpramByteTime::interrupt(const sc_time& inta1, const sc_time& iret_done) {
    for (Chunk& c : chunks_) {
        add_inside(c.isr_us, c.first, c.last, inta1, iret_done);
        if (!c.closed) add_inside(c.isr_more_us, c.first, sc_core::sc_max_time(), inta1, iret_done);
    }
}

void DpramByteTime::sum_front() {
    const Chunk& c = chunks_.front();
    if (c.writes >= 2) {
        time_us_ += to_us(c.last - c.first) - c.isr_us;
        gaps_ += c.writes - 1;
        bytes_ += c.bytes;
    }
    chunks_.pop_front();
}

void DpramByteTime::settle() {
    // Summed in the order the chunks began: an open chunk holds back the closed ones behind it.
    while (!chunks_.empty() && chunks_.front().closed) sum_front();
}

void DpramByteTime::finish() {
    for (unsigned p = 0; p < kPorts; ++p) chunk_closed(p);
    settle();
}

std::optional<double> DpramByteTime::per_byte_us() const {
    if (!gaps_) return std::nullopt;
    return time_us_ / static_cast<double>(gaps_);
}

} // namespace rcsim
