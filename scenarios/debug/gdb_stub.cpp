// rcsim — the gdb remote stub on the communication board (gdb_stub.h).
#include "scenarios/debug/gdb_stub.h"

#include "comm_cpu/comm_board.h"
#include "models/plumbing/config_error.h"
#include "scenarios/host/tcp_host.h"
#include "models/plumbing/stop_signal.h"

#include <csignal>
#include <cstdarg>
#include <cstdio>
#include <ostream>
#include <sstream>

namespace rcsim::debug {

namespace asio = boost::asio;
using asio::ip::tcp;

void GdbStubConfig::set_listen(const std::string& text) {
    // A bare PORT listens on the loopback interface, as ":PORT" does.
    TcpHostConfig t;
    try {
        t.set_listen(text.find(':') == std::string::npos ? ":" + text : text);
    } catch (const std::invalid_argument& e) {
        throw ConfigError("--gdb '" + text + "': " + e.what());
    }
    address = t.address;
    port = t.port;
}

// ---- the board as gdb sees it ----

class GdbStub::BoardTarget : public DebugTarget {
public:
    explicit BoardTarget(CommBoard& b) : b_(b) {}

    i8086::Registers registers() const override { return b_.cpu.core().regs(); }

    void set_registers(const i8086::Registers& r) override {
        auto& core = b_.cpu.core();
        const bool moved = r.s[i8086::CS] != core.regs().s[i8086::CS] || r.ip != core.regs().ip;
        core.regs() = r;
        // The 8086's flags: bits 12-15 and 1 read as 1, 3 and 5 as 0 (as at reset).
        core.regs().flags = std::uint16_t((r.flags & 0x0FD5) | 0xF002);
        // A new CS:IP: the prefetched opcode belongs to the old stream.
        if (moved) core.debug_jump(r.s[i8086::CS], r.ip);
    }

    bool read_memory(std::uint32_t a, std::uint8_t* out, std::size_t n) override { return b_.cpu.debug_read(a, out, n); }
    bool write_memory(std::uint32_t a, const std::uint8_t* in, std::size_t n) override {
        return b_.cpu.debug_write(a, in, n);
    }

    std::string monitor(const std::string& command) override;

private:
    std::string time() const;
    std::string pending() const;
    std::string pic() const;
    std::string uart(unsigned port) const;

    CommBoard& b_;
};

namespace {
std::string fmt(const char* f, ...) __attribute__((format(printf, 1, 2)));
std::string fmt(const char* f, ...) {
    char buf[256];
    va_list ap;
    va_start(ap, f);
    std::vsnprintf(buf, sizeof buf, f, ap);
    va_end(ap);
    return buf;
}
} // namespace

std::string GdbStub::BoardTarget::time() const {
    // The core runs ahead of kernel time by at most one slice that no event falls into
    // (docs/architecture.md "Time model"): its time is the board's.
    const double core_us = b_.cpu.time_of(b_.cpu.cycles()).to_seconds() * 1e6;
    return fmt("simulated time %.3f us (kernel %.3f us)\n", core_us, sc_core::sc_time_stamp().to_seconds() * 1e6);
}

std::string GdbStub::BoardTarget::pending() const {
    const auto& pic = b_.pic;
    const int level = pic.pending_level();
    std::string s = fmt("8259A IRR %02X ISR %02X IMR %02X; next to acknowledge: ", pic.irr(), pic.isr(), pic.imr());
    s += level < 0 ? std::string("none") : fmt("IR%d (vector %02X)", level, unsigned(pic.vector_base() + level));
    s += fmt("\nINTR %s, IF %d\n", b_.intr.read() ? "high" : "low",
             (b_.cpu.core().regs().flags & i8086::flag::IF) ? 1 : 0);
    return s;
}

std::string GdbStub::BoardTarget::pic() const {
    const auto& p = b_.pic;
    std::string s = fmt("8259A: %s, vector base %02X, %s triggered%s%s\n", to_string(p.init_state()),
                        p.vector_base(), p.level_triggered() ? "level" : "edge", p.auto_eoi() ? ", auto EOI" : "",
                        p.special_mask_mode() ? ", special mask" : "");
    s += fmt("IRR %02X  ISR %02X  IMR %02X  lowest priority IR%u\n", p.irr(), p.isr(), p.imr(), p.lowest_priority());
    s += "acknowledged:";
    for (unsigned l = 0; l < 8; ++l) s += fmt(" IR%u=%llu", l, static_cast<unsigned long long>(p.acks(l)));
    return s + fmt(" spurious=%llu\n", static_cast<unsigned long long>(p.spurious_acks()));
}

std::string GdbStub::BoardTarget::uart(unsigned port) const {
    const auto& u = b_.uart[port];
    // Every register as a read would return it, bank by bank, without the read's side effects
    // (a read of RXD would take a character out of the FIFO).
    std::string s = fmt("82510 #%u (I/O %04X): bank %u, %s, RX FIFO %u, TX FIFO %u\n", port,
                        unsigned(b_.uart_io_address(port, 0)), u.bank(), u.tx_format().describe().c_str(),
                        u.rx_level(), u.tx_level());
    const char* names[4][8] = {{"RXD", "GER", "GIR", "LCR", "MCR", "LSR", "MSR", "ACR0"},
                               {"RXF", "TXF", "GIR", "TMST", "FLR", "RST", "TCM", "GSR"},
                               {"-", "FMD", "GIR", "TMD", "IMD", "ACR1", "RIE", "RMD"},
                               {"CLCF", "BACF", "GIR", "BBCF", "PMD", "MIE", "TMIE", "-"}};
    for (unsigned bank = 0; bank < 4; ++bank) {
        s += fmt("bank %u:", bank);
        for (unsigned off = 0; off < 8; ++off) s += fmt(" %s=%02X", names[bank][off], u.peek(bank, off));
        s += "\n";
    }
    return s;
}

std::string GdbStub::BoardTarget::monitor(const std::string& command) {
    std::istringstream in(command);
    std::string word, arg;
    in >> word >> arg;
    if (word == "time") return time();
    if (word == "cycles")
        return fmt("cycles %llu, instructions %llu\n", static_cast<unsigned long long>(b_.cpu.cycles()),
                   static_cast<unsigned long long>(b_.cpu.instructions()));
    if (word == "irq") return pending();
    if (word == "pic") return pic();
    if (word == "uart") {
        if (arg.size() == 1 && arg[0] >= '0' && arg[0] < char('0' + CommBoard::kPorts)) return uart(unsigned(arg[0] - '0'));
        return "monitor uart N: N is 0, 1 or 2\n";
    }
    return "rcsim monitor commands:\n"
           "  time      simulated time\n"
           "  cycles    8086 clock cycles and instructions so far\n"
           "  irq       pending interrupts (8259A IRR/ISR/IMR, INTR, IF)\n"
           "  pic       8259A registers and counters\n"
           "  uart N    82510 #N registers, all four banks (N = 0..2)\n";
}

// ---- the stub ----

GdbStub::GdbStub(const GdbStubConfig& config, CommBoard& board, RealtimePacer* pacer, std::ostream& log)
    : config_(config), board_(board), pacer_(pacer), log_(log), target_(std::make_unique<BoardTarget>(board)),
      session_(*target_), acceptor_(io_),
      // At most kMaxConnectionLines per window, so that a flood of peers cannot flood the log.
      connection_lines_(log, kMaxConnectionLines, kConnectionLogWindow, [](std::uint64_t n) {
          return "gdb: " + std::to_string(n) +
                 " more connection lines not shown (peers dropped, debuggers attached or gone; " +
                 std::to_string(kMaxConnectionLines) + " are shown every " +
                 std::to_string(kConnectionLogWindow.count()) + " s)";
      }) {
    boost::system::error_code ec;
    const auto addr = asio::ip::make_address(config_.address, ec);
    if (ec) throw ConfigError("--gdb: bad address '" + config_.address + "'");
    const tcp::endpoint ep(addr, static_cast<unsigned short>(config_.port));
    acceptor_.open(ep.protocol(), ec);
    if (!ec) acceptor_.set_option(tcp::acceptor::reuse_address(true), ec);
    if (!ec) acceptor_.bind(ep, ec);
    // One debugger at a time, but a backlog of a few: peers that are no debuggers, each dropped
    // at once, queue instead of waiting a second for the kernel's SYN-ACK retries.
    if (!ec) acceptor_.listen(8, ec);
    if (ec) throw ConfigError("--gdb " + config_.address + ":" + std::to_string(config_.port) + ": cannot listen: " + ec.message());
    arm_accept();
    waiting_first_ = config_.wait;
    board_.cpu.set_step_observer(&GdbStub::on_step, this);
    board_.cpu.set_debug_bus_observer(&GdbStub::on_bus, this);
}

GdbStub::~GdbStub() {
    boost::system::error_code ec;
    if (socket_) socket_->close(ec);
    acceptor_.close(ec);
}

std::string GdbStub::endpoint() const {
    boost::system::error_code ec;
    const auto ep = acceptor_.local_endpoint(ec);
    return ep.address().to_string() + ":" + std::to_string(ep.port());
}

void GdbStub::arm_accept() {
    if (accepting_ || !acceptor_.is_open()) return;
    accepting_ = true;
    acceptor_.async_accept([this](const boost::system::error_code& ec, tcp::socket s) {
        accepting_ = false;
        if (ec) return;
        socket_.emplace(std::move(s));
        boost::system::error_code ignore;
        socket_->set_option(tcp::no_delay(true), ignore);
        closed_ = false;
        fresh_client_ = true; // not yet a debugger: the board runs on (gdb_stub.h)
        connected_at_ = std::chrono::steady_clock::now();
        greeting_bytes_ = 0;
        greeting_started_ = false;
        not_debugger_.clear();
        decoder_ = RspDecoder();
        arm_read();
    });
}

void GdbStub::arm_read() {
    if (reading_ || !socket_ || closed_) return;
    reading_ = true;
    socket_->async_read_some(asio::buffer(rx_), [this](const boost::system::error_code& ec, std::size_t n) {
        reading_ = false;
        if (n) received(n);
        if (ec) {
            closed_ = true;
            return;
        }
        // While held, read on once the packets of this read are served (halt()); while running,
        // at the next poll: one read per poll keeps a flood from slowing the run.
        if (held_ && pending_.empty()) arm_read();
    });
}

void GdbStub::received(std::size_t n) {
    if (fresh_client_) check_greeting(rx_.data(), n);
    decoded_.clear();
    decoder_.feed(rx_.data(), n, decoded_);
    const bool serving = held_ || fresh_client_; // a new client's first packets wait for its stop
    if (!held_) running_input_ += n;
    if (fresh_client_ && not_debugger_.empty() && pending_.empty()) {
        if (!decoded_.empty() && decoded_.front().kind != RspDecoder::Event::Kind::packet)
            not_debugger_ = decoded_.front().kind == RspDecoder::Event::Kind::bad_packet
                                ? "its first packet has " + decoded_.front().payload
                                : "it sent Ctrl-C before any packet";
        else if (decoded_.empty() && greeting_bytes_ > kMaxGreeting)
            not_debugger_ = "it sent " + std::to_string(greeting_bytes_) + " bytes without finishing a packet";
    }
    for (auto& e : decoded_) {
        if (e.kind == RspDecoder::Event::Kind::interrupt) {
            if (!held_) interrupt_ = true; // while held it is stopped already
        } else if (serving) {
            pending_.push_back(std::move(e));
        } else {
            ++ignored_;
        }
    }
}

namespace {
/// Up to 24 bytes of what a peer sent, quoted, unprintable bytes as \xNN.
std::string quoted(const char* data, std::size_t n) {
    std::string s = "\"";
    for (std::size_t i = 0; i < n && i < 24; ++i) {
        const auto c = static_cast<unsigned char>(data[i]);
        s += c >= 0x20 && c < 0x7F && c != '"' && c != '\\' ? std::string(1, char(c)) : fmt("\\x%02X", c);
    }
    return s + (n > 24 ? "\"..." : "\"");
}
} // namespace

// A debugger's first bytes: '+' acknowledgements, then '$' (a packet). Anything else, an HTTP
// request or noise, is no debugger.
void GdbStub::check_greeting(const char* data, std::size_t n) {
    for (std::size_t i = 0; i < n && !greeting_started_ && not_debugger_.empty(); ++i) {
        if (data[i] == '+') continue;
        if (data[i] == '$') greeting_started_ = true;
        else not_debugger_ = "its first bytes are no gdb packet: " + quoted(data + i, n - i);
    }
    greeting_bytes_ += n;
}

// Whether the newcomer has attached (its first packet is in); drops it when it is no debugger,
// has gone, or has sent nothing for kFirstPacketWait.
bool GdbStub::newcomer_attached() {
    if (!not_debugger_.empty()) {
        drop_client("dropped a peer that is not a debugger (" + not_debugger_ + ")");
        return false;
    }
    if (!pending_.empty()) return true;
    if (closed_) {
        drop_client("a peer closed its connection before any packet");
    } else if (std::chrono::steady_clock::now() - connected_at_ > kFirstPacketWait) {
        drop_client("dropped a peer that sent no packet within " + std::to_string(kFirstPacketWait.count()) +
                    " s (not a debugger)");
    }
    return false;
}

void GdbStub::note_ignored() {
    if (ignored_)
        log_ << "gdb: ignored " << ignored_ << " packets sent while the board ran (only Ctrl-C is read then)"
             << std::endl;
    ignored_ = 0;
    running_input_ = 0;
}

void GdbStub::poll() {
    connection_lines_.flush();
    arm_read();
    io_.restart();
    io_.poll();
}

void GdbStub::wait_for(std::chrono::milliseconds timeout) {
    // Returns as soon as something happened (a read, a write, an accept), at the latest after
    // `timeout`.
    io_.restart();
    if (io_.run_one_for(timeout)) io_.poll();
}

void GdbStub::drop_client(const std::string& why) {
    if (!why.empty()) connection_lines_.line("gdb: " + why + "; the run continues");
    boost::system::error_code ec;
    socket_->close(ec);
    poll(); // lets the cancelled read and write finish before the socket goes
    socket_.reset();
    session_.clear_points();
    stepping_ = false;
    watch_hit_.reset();
    pending_.clear();
    fresh_client_ = false;
    interrupt_ = false;
    ignored_ = 0;
    running_input_ = 0;
    unsent_.clear();
    writing_.clear();
    write_busy_ = false;
    arm_accept();
}

void GdbStub::send_raw(const std::string& bytes) {
    if (!socket_ || closed_) return;
    unsent_ += bytes;
    flush();
}

void GdbStub::flush() {
    if (write_busy_ || unsent_.empty() || !socket_ || closed_) return;
    writing_.swap(unsent_);
    unsent_.clear();
    write_busy_ = true;
    write_start_ = std::chrono::steady_clock::now();
    asio::async_write(*socket_, asio::buffer(writing_), [this](const boost::system::error_code& ec, std::size_t) {
        write_busy_ = false;
        writing_.clear();
        if (ec) {
            closed_ = true;
            return;
        }
        flush();
    });
}

// A little time for the last reply to leave before the socket closes; a client that does not
// read gets no more.
void GdbStub::drain(std::chrono::milliseconds limit) {
    const auto until = std::chrono::steady_clock::now() + limit;
    while ((write_busy_ || !unsent_.empty()) && !closed_ && std::chrono::steady_clock::now() < until)
        wait_for(std::chrono::milliseconds(20));
}

bool GdbStub::write_stalled() const {
    return write_busy_ && std::chrono::steady_clock::now() - write_start_ > kMaxWriteStall;
}

void GdbStub::send(const std::string& payload) { send_raw(rsp_frame(payload)); }

bool GdbStub::on_step(void* self, const i8086::Cpu& cpu) {
    static_cast<GdbStub*>(self)->boundary(cpu);
    return false; // never end the core's slice: the run stays cycle-identical to one without gdb
}

void GdbStub::on_bus(void* self, const i8086::BusRecord& r) {
    auto* stub = static_cast<GdbStub*>(self);
    if (r.kind != i8086::Bus::mem_read && r.kind != i8086::Bus::mem_write) return;
    if (stub->watch_hit_ || !stub->session_.has_watchpoints()) return;
    stub->watch_hit_ = stub->session_.watch_hit(r.address, r.width, r.kind == i8086::Bus::mem_write);
}

void GdbStub::boundary(const i8086::Cpu& cpu) {
    if (waiting_first_) {
        // --gdb-wait: held until a debugger attaches; peers that are none are dropped meanwhile.
        log_ << "gdb: waiting for the debugger on " << endpoint() << std::endl;
        while (stop_signal() == 0 && !(socket_ && fresh_client_ && newcomer_attached())) {
            arm_read();
            wait_for(std::chrono::milliseconds(100));
        }
        waiting_first_ = false;
        if (pacer_) pacer_->rebase();
    }
    if (--countdown_ == 0) {
        countdown_ = kPollEvery;
        poll();
    }
    if (!socket_) return;
    if (fresh_client_) {
        if (!newcomer_attached()) return;
        fresh_client_ = false;
        connection_lines_.line("gdb: debugger attached");
        halt(StopReason{StopReason::Kind::step}, false); // gdb expects a stopped target: its packets are served there
        return;
    }
    if (closed_) {
        drop_client("the debugger disconnected");
        return;
    }
    if (running_input_ > kMaxRunningInput) {
        drop_client("dropped the debugger: it sent more than " + std::to_string(kMaxRunningInput) +
                    " bytes while the board ran (a debugger sends only Ctrl-C then)");
        return;
    }
    std::optional<StopReason> why;
    if (watch_hit_) {
        why = watch_hit_;
        watch_hit_.reset();
    } else if (stepping_) {
        why = StopReason{StopReason::Kind::step};
    } else if (const int b = session_.breakpoint_at(cpu.pc())) {
        why = StopReason{StopReason::Kind::breakpoint};
        why->hardware = b == 2;
    } else if (interrupt_) {
        why = StopReason{StopReason::Kind::interrupt};
    }
    if (why) halt(*why, true);
}

// Serves gdb until it resumes the target (or goes away); the kernel stands still meanwhile.
void GdbStub::halt(const StopReason& why, bool report) {
    held_ = true;
    stepping_ = false;
    interrupt_ = false; // a Ctrl-C that made (or raced) this stop is answered by it
    note_ignored();
    session_.set_last_stop(why);
    if (report) send(GdbSession::stop_reply(why));
    resume_ = false;
    while (!resume_) {
        serve_pending();
        if (resume_) break;
        if (closed_) {
            drop_client("the debugger disconnected");
            break;
        }
        if (stop_signal() != 0) {
            drop_client("the run was asked to stop while the debugger held it");
            break;
        }
        if (write_stalled()) {
            drop_client("dropped the debugger: it does not read its replies (" +
                        std::to_string(writing_.size() + unsent_.size()) + " bytes not taken for " +
                        std::to_string(kMaxWriteStall.count()) + " s)");
            break;
        }
        if (pending_.empty()) arm_read();
        wait_for(std::chrono::milliseconds(100));
    }
    held_ = false;
    // Packets sent after the resume packet, before its stop reply: not read while running.
    ignored_ += pending_.size();
    pending_.clear();
    if (bad_packets_ > kMaxNotes)
        log_ << "gdb: ignored " << bad_packets_ - kMaxNotes << " more bad packets from the debugger" << std::endl;
    bad_packets_ = 0;
    // Simulated time stood still: pace on from here. (Subtracting the hold from the pacer's wall
    // time counted a hold before its first check, at --gdb-wait's first instruction, twice: the
    // pacer then napped as long as the hold, SIGTERM unanswered meanwhile.)
    if (pacer_) pacer_->rebase();
}

// One packet at a time: the next once the reply to the last is in the socket, so what waits to
// be written is one reply at most.
void GdbStub::serve_pending() {
    while (!pending_.empty() && !resume_ && !write_busy_ && unsent_.empty() && socket_ && !closed_) {
        const auto e = std::move(pending_.front());
        pending_.pop_front();
        serve(e);
    }
}

void GdbStub::serve(const RspDecoder::Event& e) {
    using K = RspDecoder::Event::Kind;
    if (e.kind == K::interrupt) return; // already stopped
    if (e.kind == K::bad_packet) {
        // '-' asks for a retransmission; gdb resends, anything else is noise we outlast.
        if (++bad_packets_ <= kMaxNotes) log_ << "gdb: ignored " << e.payload << " from the debugger" << std::endl;
        send_raw("-");
        return;
    }
    const GdbSession::Reply r = session_.handle(e.payload);
    send_raw(r.silent ? std::string("+") : "+" + rsp_frame(r.payload)); // one write: a detach's OK goes out
    if (r.resume == GdbSession::Resume::detach || r.resume == GdbSession::Resume::kill) drain(kDrainAtEnd);
    switch (r.resume) {
    case GdbSession::Resume::none: return;
    case GdbSession::Resume::step: stepping_ = true; break;
    case GdbSession::Resume::cont: break;
    case GdbSession::Resume::detach: drop_client("the debugger detached"); break;
    case GdbSession::Resume::kill:
        // gdb's `kill`: the run ends here as on SIGTERM (stop_signal.h: every report written,
        // `interrupted`, exit 143). The handler rcsim run installed takes it.
        log_ << "gdb: the debugger killed the target: the run ends (as on SIGTERM)" << std::endl;
        drop_client("");
        std::raise(SIGTERM);
        break;
    }
    resume_ = true;
}

void GdbStub::finish(int exit_code) {
    connection_lines_.flush(true);
    if (!socket_) return;
    if (!closed_ && !fresh_client_) { // a peer that has not attached is no debugger to tell
        StopReason end;
        end.kind = StopReason::Kind::exited;
        end.exit_code = exit_code;
        send(GdbSession::stop_reply(end));
        log_ << "gdb: the run ended; told the debugger (exit code " << exit_code << ")" << std::endl;
        drain(kDrainAtEnd);
    }
    boost::system::error_code ec;
    socket_->close(ec);
    poll();
    socket_.reset();
}

} // namespace rcsim::debug
