// rcsim — serial session logs and the replay host.
//
// A session log is the deterministic record of what an interactive host (rcsim::TcpHost) did on
// a simulated port: every byte it put on the line with the simulated time of its START edge, and
// every byte the controller sent back with the time of its stop bit. `host: replay` feeds such a
// log back at exactly the same simulated times, with no socket and no wall clock, and compares
// what the controller answers with what it answered in the recorded session. A bug seen
// interactively thereby becomes a deterministic regression scenario (docs/serial.md "Record and
// replay"; why wall time stays out of the model: docs/architecture.md "Time model").
//
// The log is text, one event a line, times in picoseconds (exact):
//
//     # rcsim serial session log v1
//     format 9600,8E1
//     0 listen 127.0.0.1:5510
//     152000000000 connect
//     250123000000 in 05            host -> controller, START edge
//     251416000000 out 06           controller -> host, end of the stop bit; "P"/"F" flag errors
//     900000000000 disconnect
//     900000000000 end              when the run stopped
//
// Lines starting with '#' and blank lines are ignored; unknown event words are errors.
#pragma once

#include "models/serial_line.h"
#include "scenarios/host/host_line.h"

#include <systemc>

#include <cstdint>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

namespace rcsim {

/// Times in a log are at most this (3600 s, the longest run, in picoseconds).
constexpr std::uint64_t kMaxSessionTimePs = 3600ULL * 1000000000000ULL;
/// The largest session log read (about two million events: an hour at 9600 baud both ways).
constexpr std::uintmax_t kMaxSessionLogBytes = 64u << 20;

struct SessionEvent {
    enum class Kind : std::uint8_t { in, out, connect, disconnect, listen, end } kind = Kind::in;
    sc_core::sc_time at;
    std::uint8_t byte = 0;
    bool parity_error = false;
    bool framing_error = false;
    std::string text; // listen: the address
};

/// Writes a session log (every line flushed: an interrupted run still leaves a usable log).
class SessionLogWriter {
public:
    /// Throws rcsim::ConfigError when the file cannot be opened.
    void open(const std::string& path, const SerialFormat& f);
    bool is_open() const { return os_.is_open(); }
    void in(const sc_core::sc_time& at, std::uint8_t byte);
    void out(const sc_core::sc_time& at, std::uint8_t byte, bool parity_error, bool framing_error);
    /// connect, disconnect, listen (with `text`), end.
    void event(const sc_core::sc_time& at, SessionEvent::Kind k, const std::string& text = "");
    /// Throws rcsim::ConfigError naming the file when a write failed (a full disk): called after
    /// the run, so that a log with missing lines never passes as complete.
    void check() const;

private:
    std::ofstream os_;
    std::string path_;
    std::string error_; // the first write failure, "" if none
    void note_failure();
};

struct SessionLog {
    std::optional<SerialFormat> format; // the `format` line
    std::vector<SessionEvent> events;   // in file order
};

/// Reads a session log (a regular file of at most kMaxSessionLogBytes); throws
/// rcsim::ConfigError naming the file and line of a bad entry: a time that is not a plain decimal
/// 0 .. kMaxSessionTimePs, that goes backwards, an unknown event or trailing text.
SessionLog read_session_log(const std::string& path);

struct ReplayHostConfig {
    std::string file;                    // the session log to replay
    std::optional<SerialFormat> format;  // overrides the log's `format` line
    bool end_at_log_end = false;         // sc_pause() at the log's `end` time (duration_s: 0)
    std::string record_path;             // "" = none; re-record this run in the same format
};

class ReplayHost : public sc_core::sc_module, public HostLineEnd {
public:
    struct Counters {
        std::uint64_t bytes_sent = 0;       // `in` bytes put on the line
        std::uint64_t bytes_late = 0;       // sent later than recorded (the transmitter was busy)
        std::uint64_t bytes_received = 0;   // from the controller
        std::uint64_t out_expected = 0;     // `out` bytes in the log
        std::uint64_t out_matched = 0;      // same byte, same flags, same time, same position
        std::uint64_t out_mismatched = 0;   // differing byte, flags or time, or extra bytes
    };

    /// Throws rcsim::ConfigError for an unreadable or malformed log.
    ReplayHost(sc_core::sc_module_name name, const ReplayHostConfig& cfg);

    const Counters& counters() const { return counters_; }
    /// Recorded `out` bytes never received (counted at the call).
    std::uint64_t out_missing() const;
    /// The first difference, "" when none: "out #3 at 1234 ps: expected 06, got 15 at 1234 ps".
    const std::string& first_mismatch() const { return first_mismatch_; }
    /// The log's end time (its `end` line, else its last event).
    sc_core::sc_time end_time() const { return end_; }
    const SerialFormat& format() const { return format_; }
    /// Throws rcsim::ConfigError when the re-recorded log could not be written completely.
    void finish_log() const { rec_.check(); }

    SerialFormat rx_format() const override { return format_; }
    void rx_char(const SerialRx& c) override;
    void rx_break(bool) override {}

private:
    ReplayHostConfig cfg_;
    SerialFormat format_;
    std::vector<SessionEvent> in_, out_;
    sc_core::sc_time end_;
    Counters counters_;
    std::string first_mismatch_;
    SessionLogWriter rec_;

    void end_of_elaboration() override;
    void run();
};

} // namespace rcsim
