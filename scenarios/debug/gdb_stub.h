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
//   * Garbage on the socket is answered with '-' and a note on stderr; a disconnect drops the
//     breakpoints and lets the run go on; the next debugger may connect.
#pragma once

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
    void drop_client(const std::string& why);

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
    bool fresh_client_ = false; // connected, not yet stopped for it
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
