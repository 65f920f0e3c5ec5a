// rcsim — the gdb remote stub of `rcsim run --gdb [HOST:]PORT` (docs/tools.md "gdb").
//
// Design:
//   * Everything runs in the 8086's SC_THREAD, through the core's instruction-boundary hook
//     (i8086::StepHook) and the module's debug bus observer: no thread of its own. A breakpoint,
//     a finished stepi, a watchpoint hit or a Ctrl-C from gdb stops the core at an instruction
//     boundary by serving gdb's packets *inside* the hook. While it blocks there the SystemC
//     kernel cannot run, so the whole board stands still in simulated time: no UART timer
//     runs, no character arrives, no host waits. Resuming returns from the hook and the
//     instruction executes as it would have; the hook never asks the core to end its slice, so a
//     run with gdb attached is bus-cycle for bus-cycle the run without it (the same report).
//   * Boost.Asio on one io_context, polled: while the CPU runs, every 1024 instruction
//     boundaries (a non-blocking poll: an accept, one read, a disconnect); while stopped, in waits
//     of at most 100 ms so that SIGINT/SIGTERM of the run still end it.
//   * Abuse (docs/tools.md "gdb", limits): nothing the client does can block the simulation
//     thread or grow memory without bound. Reads are 4 KB at a time: while the board runs, one
//     per poll, and only Ctrl-C is acted on (a flag the boundary tests, O(1) per instruction);
//     other packets are counted and dropped, as gdbserver does (in all-stop mode gdb sends nothing
//     else then), and a client that sends more than kMaxRunningInput meanwhile is dropped. While
//     the board is held, the next read waits until the packets of the last are served, and the
//     next packet is served once the reply to the last is in the socket (the protocol's one
//     packet at a time). Writes are asynchronous; a reply the socket has not taken for
//     kMaxWriteStall means a client that does not read: it is dropped.
//   * The time the board stood still is taken out of real-time pacing (RealtimePacer), so a
//     paced run resumes at its pace instead of racing to catch up.
//   * Watchpoints are on physical addresses and data bus cycles (memory reads and writes, not
//     code fetches): the bus observer notes the hit; the stop is reported at the next boundary,
//     after the instruction that made the access, as on a hardware debug register.
//   * A peer attaches as a debugger with its first packet, not its connection (issue #48): the
//     board runs on while a newcomer has sent nothing, and stops for it once its first bytes are
//     a well-formed packet ('+' acknowledgements, then "$...#xx" with a good checksum, as gdb's
//     qSupported). A peer whose first bytes are anything else (an HTTP request, noise), that
//     sends nothing for kFirstPacketWait, or more than kMaxGreeting bytes without finishing a
//     packet, is no debugger: it is dropped without ever stopping the board. `--gdb-wait` holds
//     the board before its first instruction until a debugger has attached, not a connection.
//   * Connection lines on stderr (attached, dropped, disconnected) are rate-limited: at most
//     kMaxConnectionLines per kConnectionLogWindow, the rest counted in one line.
//   * Garbage from an attached debugger is answered with '-' and a note on stderr; a disconnect
//     drops the breakpoints and lets the run go on; the next debugger may connect. gdb's `kill`
//     ends the run as SIGTERM does (reports written, `interrupted`, exit 143); `detach` leaves it
//     running.
#pragma once

#include "models/plumbing/log_limiter.h"
#include "scenarios/debug/gdb_protocol.h"

#include <boost/asio.hpp>

#include <array>
#include <chrono>
#include <deque>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace rcsim {
class CommBoard;
class RealtimePacer;
} // namespace rcsim

namespace rcsim::debug {

struct GdbStubConfig {
    std::string address = "127.0.0.1";
    unsigned port = 0;  // 0: an ephemeral port (endpoint() tells which)
    bool wait = false;  // --gdb-wait: stop before the first instruction until gdb connects
    /// "[HOST:]PORT"; throws ConfigError naming the value.
    void set_listen(const std::string& text);
};

class GdbStub {
public:
    /// Listens at once; throws ConfigError when it cannot. Messages go to `log` (stderr).
    GdbStub(const GdbStubConfig& config, CommBoard& board, RealtimePacer* pacer, std::ostream& log);
    ~GdbStub();
    GdbStub(const GdbStub&) = delete;
    GdbStub& operator=(const GdbStub&) = delete;

    std::string endpoint() const;
    /// The run is over: a connected gdb is told the exit status (W packet) and the connection
    /// closed. The board is not touched (it may be gone).
    void finish(int exit_code);

    static constexpr unsigned kPollEvery = 1024; // instruction boundaries between socket polls
    static constexpr std::size_t kReadChunk = 4096;
    /// Bytes a client may send while the board runs before it is dropped as a flood (gdb sends
    /// one byte then: Ctrl-C).
    static constexpr std::size_t kMaxRunningInput = 65536;
    static constexpr std::chrono::seconds kMaxWriteStall{2};
    static constexpr std::chrono::milliseconds kDrainAtEnd{200}; // for a detach's OK, the W at the end
    static constexpr std::size_t kMaxNotes = 10; // bad packets noted on stderr per hold; the rest counted
    /// A newcomer that has not sent its first packet within this (wall time) is dropped.
    static constexpr std::chrono::seconds kFirstPacketWait{2};
    /// A first packet is a few hundred bytes (gdb's qSupported); a newcomer that sent more without
    /// finishing one is dropped.
    static constexpr std::size_t kMaxGreeting = 4096;
    static constexpr unsigned kMaxConnectionLines = 8;
    static constexpr std::chrono::seconds kConnectionLogWindow{10};

private:
    class BoardTarget;
    static bool on_step(void* self, const i8086::Cpu& cpu);
    static void on_bus(void* self, const i8086::BusRecord& record);
    void boundary(const i8086::Cpu& cpu);
    void halt(const StopReason& why, bool report);
    void serve(const RspDecoder::Event& e);
    void serve_pending();
    void send(const std::string& payload);
    void send_raw(const std::string& bytes);
    void flush();
    void drain(std::chrono::milliseconds limit);
    bool write_stalled() const;
    void arm_accept();
    void arm_read();
    void received(std::size_t n);
    void note_ignored();
    void poll();
    void wait_for(std::chrono::milliseconds timeout);
    void drop_client(const std::string& why); // why: the log line, "" for none
    void check_greeting(const char* data, std::size_t n);
    bool newcomer_attached();

    GdbStubConfig config_;
    CommBoard& board_;
    RealtimePacer* pacer_;
    std::ostream& log_;
    std::unique_ptr<BoardTarget> target_;
    GdbSession session_;

    boost::asio::io_context io_;
    boost::asio::ip::tcp::acceptor acceptor_;
    std::optional<boost::asio::ip::tcp::socket> socket_;
    bool accepting_ = false;
    bool closed_ = false;      // the peer closed or the socket failed
    bool fresh_client_ = false; // connected, its first packet not yet received (not attached)
    std::chrono::steady_clock::time_point connected_at_;
    std::size_t greeting_bytes_ = 0;  // received from the newcomer so far
    bool greeting_started_ = false;   // its first byte other than '+' was '$'
    std::string not_debugger_;        // why the newcomer is no debugger ("" while it may be one)
    LogLimiter connection_lines_; // attached, dropped, gone
    std::array<char, kReadChunk> rx_{};
    bool reading_ = false;                    // a read is pending
    RspDecoder decoder_;
    std::vector<RspDecoder::Event> decoded_;  // of the last read (reused)
    std::deque<RspDecoder::Event> pending_;   // packets to serve while held: at most one read's
    bool held_ = false;                       // inside halt(): packets are served
    bool interrupt_ = false;                  // Ctrl-C while the board ran
    std::size_t running_input_ = 0;           // bytes received while the board ran, since the last hold
    std::size_t bad_packets_ = 0;             // answered '-' in this hold
    std::size_t ignored_ = 0;                 // packets dropped while the board ran, since the last hold
    std::string unsent_;                      // replies waiting for the write in progress
    std::string writing_;                     // the write in progress
    bool write_busy_ = false;
    std::chrono::steady_clock::time_point write_start_;

    bool stepping_ = false;
    std::optional<StopReason> watch_hit_;
    unsigned countdown_ = kPollEvery;
    bool waiting_first_ = false;
    bool resume_ = false;
};

} // namespace rcsim::debug
