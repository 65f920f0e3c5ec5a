// rcsim — a TCP backend for a simulated serial port, and the real-time pacer it needs.
//
// `TcpHost` is the far end of one RS-232C line whose bytes come from, and go to, a TCP client on
// the host machine (a terminal, nc, a Python script speaking ENQ/ACK/SOH..ETX). Design
// (docs/serial.md "Connecting your own tools"; kernel rules: docs/architecture.md "Time model"):
//
//   * An Asio io_context on its own OS thread listens, accepts one client at a time (the next
//     one after a disconnect) and reads. Received bytes go into a mutex-protected queue, and
//     reach SystemC only through async_request_update() on an sc_prim_channel (the only
//     thread-safe entry into the kernel). The channel is attached with async_attach_suspending()
//     while the backend is active, so the kernel waits for the client instead of ending by
//     starvation.
//   * Wire-accurate input: an SC_THREAD puts the queued bytes on the line one character at a time,
//     one frame time apart, as a real terminal at that baud would; the firmware can be overrun
//     exactly as with a real host (overruns show in the 82510 statistics).
//   * Bounded input: a client can send far faster than the line carries (9600 bps is ~870 B/s).
//     As a real port's driver holds a few KiB to transmit and then blocks its writer, the queue
//     holds at most kMaxInput bytes: then the io thread stops reading the socket, so TCP flow
//     control holds the client back (nothing is lost), and reads again once the line drained
//     half of it. What the client sent that never reached the line by the end of the run (queued,
//     or unread in the socket) is reported as `bytes_unsent`.
//   * Output: bytes the controller sends are queued and written to the socket by the io thread
//     (the SystemC thread never blocks on the network). Bytes produced before a client connects,
//     or between clients, are buffered (up to `max_buffer`, oldest dropped and counted beyond)
//     and delivered when one connects.
//   * Determinism: with `record_path`, every byte put on the line is written with its simulated
//     START time, every byte received with its stop-bit time (replay_host.h); `host: replay`
//     plays such a log back without any socket.
//
// `RealtimePacer` keeps simulated time from running ahead of wall-clock time (sim <= wall x rtf
// + one step) by sleeping in bounded naps inside an SC_THREAD, yielding to the kernel between
// naps so network input is taken in promptly. It never slows a simulation that is already behind
// real time; it reports how far behind it fell.
#pragma once

#include "models/serial_line.h"
#include "scenarios/host/host_inbox.h"
#include "scenarios/host/host_line.h"
#include "scenarios/host/host_outbox.h"
#include "scenarios/host/replay_host.h"
#include "scenarios/host/telnet.h"

#include <boost/asio.hpp>
#include <systemc>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace rcsim {

struct TcpHostConfig {
    SerialFormat format = SerialFormat::rs232(9600);
    std::string address = "127.0.0.1"; // the interface to listen on
    unsigned port = 0;                 // 0 = ephemeral (read port() back)
    std::string record_path;           // session log ("" = none)
    std::string port_file;             // write the bound port number here ("" = none)
    bool end_on_disconnect = false;    // sc_pause() when the client goes away (duration_s: 0)
    std::size_t max_buffer = 1u << 20; // controller bytes held for an absent client
    /// The stream is telnet-style (telnet.h): IAC BRK from the client is a BREAK of
    /// `break_duration` on the line, a 255 byte is IAC IAC both ways. Off: a plain byte stream.
    bool telnet = false;
    sc_core::sc_time break_duration = sc_core::sc_time(250, sc_core::SC_MS); // tcsendbreak's 0.25 s

    /// Parses "HOST:PORT" ("127.0.0.1:5510", "[::1]:0", ":5510" = 127.0.0.1); throws
    /// std::invalid_argument.
    void set_listen(const std::string& text);
};

class TcpHost : public sc_core::sc_module, public HostLineEnd {
public:
    struct Counters {
        std::uint64_t bytes_in = 0;        // received from clients
        std::uint64_t bytes_sent = 0;      // put on the line
        std::uint64_t bytes_received = 0;  // from the controller
        std::uint64_t bytes_out = 0;       // written to clients
        std::uint64_t bytes_buffered = 0;  // controller bytes produced while no client was connected
        std::uint64_t bytes_dropped = 0;   // beyond max_buffer
        std::uint64_t line_errors = 0;     // controller bytes with a parity/framing error
        std::uint64_t breaks = 0;          // BREAKs from the controller (not forwarded)
        std::uint64_t breaks_sent = 0;     // BREAKs put on the line (telnet IAC BRK)
        std::uint64_t connections = 0;
        std::uint64_t disconnects = 0;
        std::uint64_t input_stalls = 0;    // times the input queue was full and reading paused
    };

    /// The most client bytes waiting for the line (a real port's transmit buffer; Linux's serial
    /// core holds 4 KiB). Beyond it the socket is not read until half of it went out.
    static constexpr std::size_t kMaxInput = 4096;

    /// Binds and listens at once (the port is known when the constructor returns) and starts the
    /// io thread. Throws rcsim::ConfigError when it cannot listen or write the record/port file.
    TcpHost(sc_core::sc_module_name name, const TcpHostConfig& cfg);
    ~TcpHost() override;

    unsigned short port() const { return port_; }
    std::string endpoint() const; // "127.0.0.1:5510"
    bool client_connected() const;
    /// A consistent copy (the io thread updates some counters).
    Counters counters() const;
    /// Bytes the clients sent that are not on the line (call at the end of the run): those still
    /// queued plus those unread in the connected client's socket (a lower bound: the client's own
    /// send buffer is out of sight).
    std::uint64_t bytes_unsent();
    /// True once a client disconnected with end_on_disconnect set and the host paused the run.
    bool ended() const { return ended_; }
    /// Ends the session log with its `end` line (at the current simulated time, unless the session
    /// already ended) and throws rcsim::ConfigError when the log could not be written completely.
    void finish_log();

    SerialFormat rx_format() const override { return cfg_.format; }
    void rx_char(const SerialRx& c) override;
    void rx_break(bool active) override;

private:
    struct Item {
        enum Kind : std::uint8_t { byte, connected, disconnected, brk } kind;
        std::uint8_t value;
    };

    TcpHostConfig cfg_;
    HostInbox inbox_;
    SessionLogWriter rec_;
    bool attached_ = false;
    bool ended_ = false;
    bool end_logged_ = false; // the `end` line is written

    // Shared between the io thread and SystemC: the input under mu_, the output in the outbox.
    mutable std::mutex mu_;
    std::deque<Item> in_;  // client -> line, at most kMaxInput + one read
    bool connected_ = false;
    bool read_paused_ = false; // in_ was full: the io thread reads again when the line drained it
    Counters counters_;    // the outbox's counters are its own
    HostOutbox out_;       // controller -> client

    // io thread only (after construction).
    boost::asio::io_context io_;
    // Keeps io_.run() going while no operation is pending (reading paused, the client connected).
    boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work_{io_.get_executor()};
    boost::asio::ip::tcp::acceptor acceptor_;
    std::optional<boost::asio::ip::tcp::socket> sock_;
    std::array<std::uint8_t, 1024> rbuf_{};
    std::vector<std::uint8_t> wbuf_;
    TelnetDecoder telnet_; // with cfg_.telnet; reset for each client
    bool writing_ = false;
    std::atomic<bool> stopping_{false};
    unsigned short port_ = 0;
    std::thread thread_;

    void start_of_simulation() override;
    void end_of_elaboration() override;
    void run();
    void detach();
    // io thread
    void start_accept();
    void start_read();
    void resume_read();
    void start_write();
    void drop_client();
    void push(Item it);
};

class RealtimePacer : public sc_core::sc_module {
public:
    struct Stats {
        double rtf = 1.0;           // the target: simulated seconds per wall second
        std::uint64_t naps = 0;     // sleeps taken
        double slept_s = 0;         // total wall time slept
        double max_lag_s = 0;       // the furthest simulated time fell behind wall x rtf
        double max_lead_s = 0;      // the furthest it ran ahead (bounded by one step)
        double sim_s = 0, wall_s = 0; // at the last check
    };

    /// `rtf` > 0: simulated seconds per wall second (1.0 = real time). `step`: simulated time
    /// between checks; `max_nap`: the longest single sleep.
    RealtimePacer(sc_core::sc_module_name name, double rtf, sc_core::sc_time step = sc_core::sc_time(1, sc_core::SC_MS),
                  std::chrono::microseconds max_nap = std::chrono::milliseconds(10));

    const Stats& stats() const { return stats_; }
    /// Measures from now on: the next check takes the current simulated and wall time as its
    /// origin. Call after simulated time stood still while wall time went on (a paused run), or
    /// the pacer would see the run that far behind and let it race to catch up.
    void rebase() { rebase_ = true; }
    /// A new target (> 0), or 0: unpaced (no sleeps) until the next set_rtf. Rebases.
    void set_rtf(double rtf);
    double rtf() const { return paced_ ? stats_.rtf : 0.0; }

private:
    sc_core::sc_time step_;
    std::chrono::microseconds max_nap_;
    Stats stats_;
    bool paced_ = true;
    bool rebase_ = false;
    void run();
};

} // namespace rcsim
