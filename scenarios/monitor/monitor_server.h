// rcsim — the remote monitor's network side (docs/monitor.md): an HTTP server with a WebSocket
// endpoint on its own thread (Boost.Beast over Boost.Asio, one io_context).
//
// It knows nothing of the simulation. The simulation thread and the io thread meet in three
// places only, none of which can make the simulation wait for a client:
//   - requests: every message a client sends is parsed on the io thread and queued (mutex-guarded,
//     bounded); the simulation thread takes them between two slices of simulated time;
//   - replies and updates: the simulation thread hands a serialised message to a client with
//     send(), which only posts it to the io thread; what a client has not read (the messages
//     not yet written and the bytes in its socket's send queue) is bounded, and a client that
//     lets it fill (it does not read) is dropped;
//   - the latest snapshot text, which plain HTTP GETs are answered with (mutex-guarded).
// A client that disconnects, sends something that is not a JSON object with an "op" (or nested
// deeper than kMaxJsonDepth), a message over kMaxMessageBytes, or more than kMaxClientRequests
// requests the simulation has not yet taken, is dropped with one log line; the others and the
// run go on. Plain HTTP connections are capped at kMaxHttpSessions, kMaxHttpSessionsPerPeer from
// one address; past a cap a new connection takes the place of the oldest one that has sent nothing
// (or not yet its whole request), so idle sockets cannot lock the page out. A connection gets
// kRequestTimeout for its request and kAnswerTimeout for the answer.
#pragma once

#include <nlohmann/json.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <ostream>
#include <string>
#include <thread>
#include <vector>

namespace rcsim::monitor {

/// The version of the JSON API (docs/monitor.md); every message the server sends carries it.
constexpr int kApiVersion = 1;

class MonitorServer {
public:
    static constexpr std::size_t kMaxMessageBytes = 64 * 1024; // one client message, WebSocket or HTTP
    // Per client, not yet read: messages waiting to be written, and their bytes with those in
    // the socket's send queue. A slice answers up to kMaxClientRequests of a client's requests
    // at once: the message bound leaves room for them and the updates.
    static constexpr std::size_t kMaxQueuedMessages = 4096;
    static constexpr std::size_t kMaxQueuedBytes = 8u << 20;
    static constexpr int kSocketSendBuffer = 256 * 1024;       // per client, the kernel's share
    static constexpr std::size_t kMaxClients = 16;
    static constexpr std::size_t kMaxPendingRequests = 1024;   // all clients, not yet taken
    static constexpr std::size_t kMaxClientRequests = 256;     // one client's, not yet taken
    static constexpr std::size_t kMaxHttpSessions = 64;        // plain HTTP connections at once
    static constexpr std::size_t kMaxHttpSessionsPerPeer = 16; // the same, from one address
    static constexpr std::chrono::seconds kRequestTimeout{2};  // from accept to a whole request
    static constexpr std::chrono::seconds kAnswerTimeout{10};  // writing the answer
    static constexpr std::size_t kMaxJsonDepth = 32;           // nesting of a client's message

    /// A client's message, parsed. `client` 0 with `op` "closed": client `closed_client` is gone.
    struct Request {
        std::uint64_t client = 0;
        nlohmann::json message; // an object with a string "op"
    };

    /// Binds HOST:PORT (numeric address; port 0 = ephemeral) and starts the io thread, which
    /// answers GET / with `page`. `log` receives one line per client event (connected, dropped and
    /// why). Throws ConfigError when the address cannot be bound.
    MonitorServer(const std::string& host, unsigned port, std::string page, std::ostream& log);
    ~MonitorServer();
    MonitorServer(const MonitorServer&) = delete;
    MonitorServer& operator=(const MonitorServer&) = delete;

    /// "http://127.0.0.1:8080/"
    const std::string& url() const { return url_; }
    unsigned port() const { return port_; }

    // ---- the simulation thread's side; none of these waits for a client ----
    /// The requests queued since the last call, in arrival order.
    std::vector<Request> take_requests();
    /// Waits up to `timeout` for a request (used while paused, when nothing else is to do).
    void wait_for_request(std::chrono::milliseconds timeout);
    /// Queues `text` (one JSON message) for `client`; nothing happens if it is gone.
    void send(std::uint64_t client, std::shared_ptr<const std::string> text);
    /// What GET /api/v1/snapshot answers with from now on.
    void publish_snapshot(std::shared_ptr<const std::string> text);
    /// Clients connected now (a count from the io thread, for the log and tests).
    std::size_t clients() const;

    // ---- io-thread internals, public for the session classes in monitor_server.cpp ----
    class Impl;

private:
    std::unique_ptr<Impl> impl_;
    unsigned port_ = 0;
    std::string url_;
};

} // namespace rcsim::monitor
