// rcsim — the simulated external system: the host side of the serial protocol of docs/system.md §5,
// written from the specification alone (it knows nothing of the comm CPU firmware).
//
// Sending a command:   ENQ -> (ACK | NAK | T1 timeout)
//                      SOH token STX BCH data checksum ETX -> (EOT | NAK | T1 timeout)
//   NAK or timeout on ENQ: ENQ again; NAK on the frame: the whole frame again (without ENQ);
//   timeout on the frame: start over with ENQ. At most `max_retries` retries per command, the
//   n-th after a pause of n x `backoff`; then the command is reported failed.
// Receiving a frame:   ENQ -> ACK (or NAK while configured to refuse), then the frame; EOT if
//   it is good, NAK if any byte had a parity/framing error or was outside the allowed set, the
//   frame was too long or the checksum wrong. A gap over T2 between two bytes drops the partial
//   frame without an answer. The first byte must come within T1 of the ACK.
// ENQ collision: the external system wins, so an ENQ that arrives while this host waits for its
//   own ACK is ignored (counted); the controller answers ours and retries its own later.
//
// Every transaction step is logged with its simulation time. Traffic generation: fixed rate,
// Poisson, bursts, or saturate ("as fast as the line allows": the next command as soon as the
// previous one finished, and its response arrived when wait_response is set); data sizes fixed or
// uniformly random up to 8192; tokens drawn from a weighted mix; everything from one seed. At most
// kMaxQueuedCommands generated commands wait for the line; then generation waits for room.
// Script: a given list of commands (token + data), one at a time, each optionally waiting for its
// response (and checking its BCH) or, by polling ST, for a robot state (docs/scenarios.md
// "Scripted hosts").
#pragma once

#include "models/serial_line.h"
#include "scenarios/host/host_line.h"
#include "models/stats.h"
#include "models/frame_codec.h"

#include <systemc>

#include <cstdint>
#include <deque>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rcsim {

/// The protocol's timers and retry rule (docs/system.md §6.1 defaults).
struct ProtocolTiming {
    sc_core::sc_time t1{50, sc_core::SC_MS};      // ENQ -> ACK/NAK, ETX -> EOT/NAK, ACK -> SOH
                                                  // (end of the stop bit to the answer's START)
    sc_core::sc_time t2{20, sc_core::SC_MS};      // longest gap between two bytes of a frame
    sc_core::sc_time backoff{10, sc_core::SC_MS}; // pause before retry n: n x backoff
    unsigned max_retries = 3;
    sc_core::sc_time reply_delay = sc_core::SC_ZERO_TIME; // the host's own turnaround
};

/// One step of a scripted host: a command, a pause, or a wait for a robot state.
struct ScriptStep {
    enum class Kind { command, wait_state, delay };
    Kind kind = Kind::command;
    std::string token, data;            // command: the frame; wait_state: "ST" and ""
    bool wait_response = true;          // command: the next step only after the response frame
    int expect_bch = -1;                // command with wait_response: the BCH it must carry (-1: any)
    std::string state;                  // wait_state: the first field of the ST reply to wait for
    sc_core::sc_time poll{10, sc_core::SC_MS};    // wait_state: from one ST reply to the next ST
    sc_core::sc_time timeout{10, sc_core::SC_SEC}; // wait_state: give up (a failed step) after this
    sc_core::sc_time duration;          // delay
    sc_core::sc_time at;                // not before this time of the run
    int line = 0;                       // the scenario line, for the report
};

/// What a scripted host did: steps completed, and the first step that went wrong.
struct ScriptResult {
    std::size_t steps = 0;     // in the script
    std::size_t completed = 0; // steps done as the script wanted, from the first
    bool failed = false;       // a step went wrong: the script stopped there
    std::size_t failed_step = 0;
    int failed_line = 0;
    std::string failure;       // why
    sc_core::sc_time finished_at; // when the last step completed (completed == steps)
    /// Every command step's frame as delivered, in order: token, the ETX of the frame (a motion
    /// command's latency is measured from here) and the response's BCH (-1: none awaited).
    struct Sent {
        std::string token;
        sc_core::sc_time etx;
        int bch = -1;
    };
    std::vector<Sent> commands;
    bool done() const { return !failed && completed == steps; }
};

/// What commands the host generates by itself.
struct HostTraffic {
    enum class Pattern { none, fixed, poisson, burst, saturate, script };
    Pattern pattern = Pattern::none;
    double rate = 10.0;                                // fixed, poisson: commands a second
    unsigned burst_size = 4;                           // burst: commands queued at once
    sc_core::sc_time burst_period{1, sc_core::SC_SEC}; // burst: from one burst to the next
    std::uint64_t count = 0;                           // commands in all (0: no limit)
    sc_core::sc_time start = sc_core::SC_ZERO_TIME;    // when generation begins
    bool random_size = false;                          // uniform 0..data_size instead of fixed
    std::size_t data_size = 16;
    std::vector<std::pair<std::string, double>> tokens{{"EC", 1.0}}; // token, weight
    std::uint64_t seed = 1;
    bool wait_response = true; // hold the next command until a response frame (or the timeout)
    sc_core::sc_time response_timeout{1, sc_core::SC_SEC};
    std::vector<ScriptStep> script; // Pattern::script: the steps, in order

    /// "none", "fixed", "poisson", "burst", "saturate", "script"; throws std::invalid_argument.
    static Pattern parse_pattern(const std::string& s);
};

struct ProtocolHostConfig {
    SerialFormat format = SerialFormat::rs232(9600);
    ProtocolTiming timing;
    HostTraffic traffic;
    unsigned nak_enqs = 0; // refuse the first n controller ENQs with NAK (exercises its retries)
    /// Throws std::invalid_argument naming the offending value.
    void validate() const;
};

class ProtocolHost : public sc_core::sc_module, public HostLineEnd {
public:
    /// Generated commands waiting for the line, at most (docs/scenarios.md "Limits"): beyond
    /// this the traffic generator waits for room. 256 x 8192 data bytes = 2 MB a port.
    static constexpr std::size_t kMaxQueuedCommands = 256;

    struct Counters {
        std::uint64_t frames_sent = 0;      // commands started
        std::uint64_t frames_delivered = 0; // EOT received
        std::uint64_t frames_failed = 0;    // given up after the retries
        std::uint64_t naks = 0;             // NAKs received (to ENQ or frame)
        std::uint64_t timeouts = 0;         // T1 expired waiting for ACK/NAK or EOT/NAK
        std::uint64_t retries = 0;
        std::uint64_t collisions = 0;       // controller ENQ while waiting for our ACK
        std::uint64_t enqs_received = 0;
        std::uint64_t responses_received = 0; // controller frames answered with EOT
        std::uint64_t naks_sent = 0;          // controller ENQs refused and bad frames
        std::uint64_t frames_dropped = 0;     // partial frames dropped on a T2 gap or T1 silence
        std::uint64_t response_timeouts = 0;  // wait_response gave up
        std::uint64_t line_errors = 0;        // bytes received with a parity/framing error
    };
    struct LogEntry {
        sc_core::sc_time at;
        std::string text;
    };

    ProtocolHost(sc_core::sc_module_name name, const ProtocolHostConfig& cfg = {});

    /// Queues a command; it is sent when the host is free. Throws on a frame encode() rejects.
    void send(const proto::Frame& f);

    const Counters& counters() const { return counters_; }
    /// The first command given up after its retries: when, and its token; none without one.
    struct Failure {
        sc_core::sc_time at;
        std::string token;
    };
    const std::optional<Failure>& first_failure() const { return first_failure_; }
    /// responses(), delivered() and log() keep every entry while `keep_history` is on (the
    /// default, for tests); a long run turns it off and listens to on_delivered.
    void keep_history(bool on) { keep_history_ = on; }
    const std::vector<proto::Frame>& responses() const { return responses_; }
    /// The commands that got EOT, in order (what the controller accepted).
    const std::vector<proto::Frame>& delivered() const { return delivered_; }
    /// Called with each command that got EOT, in order.
    std::function<void(const proto::Frame&)> on_delivered;
    /// Generates no further commands; what is queued or in progress still completes (a scenario's
    /// drain phase).
    void stop_traffic() { stopped_ = true; }
    const std::vector<LogEntry>& log() const { return log_; }
    /// The latest transaction step logged ("> ENQ", "< ACK", ...), kept with history off too.
    const LogEntry& last_step() const { return last_step_; }
    /// Also writes every log entry as a line to `os` (nullptr: off).
    void log_to(std::ostream* os) { log_os_ = os; }
    /// ENQ of a command to its EOT, in microseconds.
    const Samples& delivery_us() const { return delivery_us_; }
    /// ENQ of a command to the ETX of the next response frame, in microseconds.
    const Samples& response_us() const { return response_us_; }
    /// No command queued or in progress and no response awaited.
    bool idle() const { return commands_.empty() && !busy_ && !awaiting_response_; }
    /// Commands queued and not yet begun.
    std::size_t queued() const { return commands_.size(); }
    const ProtocolHostConfig& config() const { return cfg_; }
    /// Pattern::script: how far the script got.
    const ScriptResult& script_result() const { return script_; }

    SerialFormat rx_format() const override { return cfg_.format; }
    void rx_char(const SerialRx& c) override;
    void rx_break(bool active) override;

private:
    struct RxByte {
        std::uint8_t byte;
        bool error;
        sc_core::sc_time at;
    };
    enum class Reply { positive, nak, timeout };

    ProtocolHostConfig cfg_;
    std::deque<RxByte> rx_;
    sc_core::sc_event rx_ev_, cmd_ev_, cmd_taken_ev_;
    std::deque<proto::Frame> commands_;
    bool busy_ = false;
    bool awaiting_response_ = false;
    sc_core::sc_time response_deadline_;
    sc_core::sc_time command_start_;
    std::uint64_t generated_ = 0;
    std::uint64_t rng_;
    unsigned nak_enqs_left_;
    proto::FrameDecoder decoder_;

    Counters counters_;
    std::vector<proto::Frame> responses_;
    std::vector<LogEntry> log_;
    LogEntry last_step_;
    std::ostream* log_os_ = nullptr;
    Samples delivery_us_, response_us_;

    void end_of_elaboration() override;
    void run();
    void generate();
    void queue_generated();
    void do_command(const proto::Frame& f);
    void serve_controller();
    sc_core::sc_time t1_deadline() const;
    Reply await_reply(std::uint8_t positive, const char* what);
    bool wait_byte(const sc_core::sc_time& timeout, RxByte& out);
    void send_bytes(const std::string& bytes);
    void note(const std::string& text);
    bool may_generate() const {
        return !stopped_ && (cfg_.traffic.count == 0 || generated_ < cfg_.traffic.count);
    }
    bool stopped_ = false;
    bool keep_history_ = true;
    // Script mode: the step thread waits on idle_ev_ for its command to finish.
    ScriptResult script_;
    sc_core::sc_event idle_ev_;
    bool last_failed_ = false;               // the last command was given up after its retries
    std::optional<Failure> first_failure_;
    bool last_response_timed_out_ = false;
    std::optional<proto::Frame> last_response_; // the response to the last command
    sc_core::sc_time last_etx_;              // when the last command frame's ETX left
    bool script_await_ = true;               // the script's command awaits its response
    bool scripted() const { return cfg_.traffic.pattern == HostTraffic::Pattern::script; }
    void run_script();
    void script_step(const ScriptStep& s);
    /// Sends `f` and waits until it is delivered (or failed) and, with `wait_response`, answered.
    void transact(const proto::Frame& f, bool wait_response);
    void fail_step(const ScriptStep& s, const std::string& why);
    std::vector<proto::Frame> delivered_;
    proto::Frame make_command();
    std::uint64_t next_random();
    double next_uniform() { return static_cast<double>(next_random() >> 11) * (1.0 / 9007199254740992.0); }
};

} // namespace rcsim
