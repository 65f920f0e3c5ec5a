// rcsim — the thread-safe door from a host backend's OS thread into the SystemC kernel.
//
// A backend thread (a socket's or a pty's io thread) queues its input under its own mutex and
// calls async_request_update(); the kernel then runs update() in its update phase and `arrived`
// fires one delta later in the backend's SC_THREAD. While attached (async_attach_suspending) the
// kernel waits for such updates instead of ending by starvation (IEEE 1666-2011 §5.15).
#pragma once

#include <systemc>

#include <deque>
#include <mutex>
#include <optional>

namespace rcsim {

/// The oldest item a backend's io thread queued for its SystemC thread, taken under the backend's
/// mutex; none when the queue is empty.
template <class Item>
std::optional<Item> pop_front_locked(std::mutex& mu, std::deque<Item>& queue) {
    std::lock_guard<std::mutex> lock(mu);
    if (queue.empty()) return std::nullopt;
    std::optional<Item> item(std::move(queue.front()));
    queue.pop_front();
    return item;
}

class HostInbox : public sc_core::sc_prim_channel {
public:
    explicit HostInbox(const char* name) : sc_prim_channel(name) {}
    sc_core::sc_event arrived;
    using sc_prim_channel::async_attach_suspending;
    using sc_prim_channel::async_detach_suspending;
    using sc_prim_channel::async_request_update;

private:
    void update() override { arrived.notify(sc_core::SC_ZERO_TIME); }
};

} // namespace rcsim
