// rcsim — the controller's bytes on their way out of the simulation to a host backend's client
// (a socket's or a pty's: TcpHost, PtyHost).
//
// The line delivers the controller's characters on the SystemC thread (rx_char); the backend's io
// thread writes them to the client whenever it can. A client that does not read (a terminal
// nobody looks at, a socket nobody has connected to yet) must not make the simulation wait nor
// grow memory without limit, so the outbox holds at most `max_bytes`: beyond that the oldest
// byte is dropped and counted, and what is kept stays in the order the controller sent it.
#pragma once

#include "models/serial_line.h"

#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <vector>

namespace rcsim {

class HostOutbox {
public:
    struct Counters {
        std::uint64_t received = 0;    // characters from the controller
        std::uint64_t line_errors = 0; // of those, with a parity or framing error
        std::uint64_t dropped = 0;     // the oldest, dropped beyond max_bytes
        std::uint64_t breaks = 0;      // BREAKs from the controller (not forwarded)
    };

    /// `max_bytes` > 0: the most bytes held for the client.
    explicit HostOutbox(std::size_t max_bytes);

    // ---- the SystemC side ----
    /// A character the controller sent (its data bits as the byte, its errors counted).
    void push(const SerialRx& c);
    /// A BREAK edge from the controller: counted when it begins, never forwarded (a byte stream
    /// has no BREAK).
    void note_break(bool active);

    // ---- the io thread's side ----
    /// Moves every byte held into `out` (replacing its contents), oldest first; false when there
    /// was none.
    bool take(std::vector<std::uint8_t>& out);

    /// Thread-safe copies.
    Counters counters() const;
    std::size_t held() const;
    /// Copies the counters into a host's own (its fields bytes_received, line_errors,
    /// bytes_dropped and breaks).
    template <class HostCounters>
    void copy_counters(HostCounters& c) const {
        const Counters o = counters();
        c.bytes_received = o.received;
        c.line_errors = o.line_errors;
        c.bytes_dropped = o.dropped;
        c.breaks = o.breaks;
    }
    /// A host's counters as its counters() returns them: its own, copied under the host's mutex
    /// (its io thread updates them), completed with the outbox's.
    template <class HostCounters>
    HostCounters host_counters(std::mutex& host_mu, const HostCounters& own) const {
        HostCounters c;
        {
            std::lock_guard<std::mutex> lock(host_mu);
            c = own;
        }
        copy_counters(c);
        return c;
    }

private:
    const std::size_t max_bytes_;
    mutable std::mutex mu_;
    std::deque<std::uint8_t> bytes_;
    Counters counters_;
};

} // namespace rcsim
