// rcsim — behavioural main CPU (see main_cpu.h and README.md).
#include "main_cpu/main_cpu.h"

#include <algorithm>
#include <stdexcept>

namespace rcsim {

using namespace dpram_layout;
using sc_core::sc_time;
using sc_core::sc_time_stamp;

namespace {

std::string time_text(const sc_time& t) { return t.to_string(); }

std::string port_text(unsigned p) { return "port " + std::to_string(p); }

} // namespace

// ---------------------------------------------------------------------------------------------
// configuration

void MainCpuConfig::validate() const {
    auto fail = [](const std::string& msg) { throw std::invalid_argument("main_cpu: " + msg); };
    if (bus_clock_hz == 0) fail("bus_clock_hz 0 must be > 0");
    if (access_cycles == 0) fail("access_cycles 0 must be >= 1 (every bus cycle takes time)");
    if (cycle_period == sc_core::SC_ZERO_TIME) fail("cycle_period 0 s must be > 0");
    if (cycle_time >= cycle_period)
        fail("cycle_time " + time_text(cycle_time) + " must be shorter than cycle_period " +
             time_text(cycle_period));
    if (ack_timeout == sc_core::SC_ZERO_TIME) fail("ack_timeout 0 s must be > 0");
    if (poll_interval == sc_core::SC_ZERO_TIME) fail("poll_interval 0 s must be > 0");
    if (mailbox_handshake && mailbox_poll == sc_core::SC_ZERO_TIME)
        fail("mailbox_poll 0 s must be > 0 with mailbox_handshake");
}

static const MainCpuConfig& validated(const MainCpuConfig& c) {
    c.validate();
    return c;
}

MainCpu::MainCpu(sc_core::sc_module_name name, const MainCpuConfig& config)
    : sc_module(name), dpram("dpram"), int_r("int_r"), config_(validated(config)),
      clock_(config.bus_clock_hz), cpu_("cpu") {
    SC_THREAD(irq_thread);
    SC_METHOD(on_int_r_rise);
    sensitive << int_r.pos();
    dont_initialize();
    SC_THREAD(dispatch_thread);
    SC_THREAD(tx_thread0);
    SC_THREAD(tx_thread1);
    SC_THREAD(tx_thread2);
    SC_THREAD(cycle_thread);
}

void MainCpu::check_port(unsigned port, const char* what) const {
    if (port >= ports)
        throw std::invalid_argument(std::string(name()) + ": " + what + ": port " +
                                    std::to_string(port) + " is not 0..2");
}

void MainCpu::log(const std::string& msg) const {
    SC_REPORT_INFO_VERB(name(), msg.c_str(), sc_core::SC_MEDIUM);
}

// ---------------------------------------------------------------------------------------------
// DP-RAM driver: one byte per bus cycle, stretched by the target's BUSY wait states

void MainCpu::access(BusCycle kind, std::uint16_t addr, std::uint8_t& value, unsigned extra_cycles) {
    const BusResult r = payload_.access(dpram, kind, addr, &value, 1, sc_time_stamp(), 1);
    if (!r.ok()) {
        const std::string msg = std::string(to_string(kind)) + " at DP-RAM offset " +
                                std::to_string(addr) + " failed (TLM response " +
                                std::to_string(int(r.status)) + ")";
        SC_REPORT_ERROR(name(), msg.c_str());
    }
    ++dpram_accesses_;
    busy_wait_ += clock_.cycles(r.wait_states);
    sc_core::wait(clock_.cycles(config_.access_cycles + r.wait_states + extra_cycles));
}

std::uint8_t MainCpu::read_byte(std::uint16_t addr, unsigned extra_cycles) {
    std::uint8_t v = 0;
    access(BusCycle::mem_read, addr, v, extra_cycles);
    return v;
}

void MainCpu::write_byte(std::uint16_t addr, std::uint8_t value, unsigned extra_cycles) {
    access(BusCycle::mem_write, addr, value, extra_cycles);
}

// int2ext is one byte for three ports: a word the comm CPU has not read yet is overwritten by
// the next. mailbox_gap spaces our words; the handshake waits until the comm CPU has cleared the
// previous one. While waiting the processor is free for other work.
void MainCpu::write_mailbox(std::uint8_t word, Processor::Priority prio) {
    if (config_.mailbox_handshake) wait_mailbox_empty(prio);
    if (config_.mailbox_gap > sc_core::SC_ZERO_TIME) {
        const sc_time slot = std::max(sc_time_stamp(), next_mailbox_slot_);
        next_mailbox_slot_ = slot + config_.mailbox_gap;
        if (slot > sc_time_stamp()) {
            cpu_.release();
            sc_core::wait(slot - sc_time_stamp());
            cpu_.acquire(prio);
        }
    }
    write_byte(int2ext, word);
}

// The read that finds 0 and our write follow each other in one busy period, so none of our own
// activities can slip a word in between; the comm CPU only ever writes 0 here.
void MainCpu::wait_mailbox_empty(Processor::Priority prio) {
    const sc_time deadline = sc_time_stamp() + config_.ack_timeout;
    while (read_byte(int2ext) != 0) {
        if (sc_time_stamp() >= deadline) {
            ++mailbox_overwrites_;
            log("int2ext still unread after " + time_text(config_.ack_timeout) + ", overwriting it");
            return;
        }
        cpu_.release();
        sc_core::wait(config_.mailbox_poll);
        cpu_.acquire(prio);
    }
}

// ---------------------------------------------------------------------------------------------
// INT_R handler

void MainCpu::on_int_r_rise() { int_r_rise_ = sc_time_stamp(); }

void MainCpu::irq_thread() {
    for (;;) {
        if (!int_r.read()) {
            sc_core::wait(int_r.posedge_event());
            int_r_rise_ = sc_time_stamp(); // the method may not have run yet in this delta
        }
        cpu_.acquire(Processor::Priority::interrupt);
        if (config_.irq_entry > sc_core::SC_ZERO_TIME) sc_core::wait(config_.irq_entry);
        irq_latency_us_.add(to_us(sc_time_stamp() - int_r_rise_));
        const std::uint8_t word = read_byte(int2rbt); // this read clears INT_R
        if (config_.mailbox_handshake) write_byte(int2rbt, 0); // "taken": the comm CPU may write again
        handle_word(word);
        cpu_.release();
    }
}

void MainCpu::handle_word(std::uint8_t word) {
    ++mailbox_words_;
    const unsigned p = word_port(word);
    const std::uint8_t kind = word_kind(word);
    if (p >= ports || kind < kind_chunk || kind > kind_gave_up_sent) {
        ++unknown_words_;
        log("ignored mailbox word 0x" + proto::hex2(word) + " (not 0x1p..0x5p with p 0..2)");
        return;
    }
    Port& port = ports_[p];
    if (kind == kind_chunk) {
        receive_chunk(p);
    } else if (kind == kind_ack) {
        if (port.awaiting_ack) {
            port.acked = true;
            port.wake.notify(sc_core::SC_ZERO_TIME);
        } else {
            ++port.stats.unexpected_acks;
            log(port_text(p) + ": ACK word while no chunk of ours was outstanding");
        }
    } else if (kind == kind_gave_up || kind == kind_gave_up_sent) {
        // One response dropped by the comm CPU; nothing of ours is in flight because of it.
        ++port.stats.responses_dropped;
        if (kind == kind_gave_up_sent) ++port.stats.responses_dropped_sent;
        log(port_text(p) + ": the comm CPU gave up on a response " +
            (kind == kind_gave_up_sent ? "that reached the line without EOT" : "that never reached the host"));
    } else {
        ++port.stats.resets_received;
        drop_partial(p);
        ++port.epoch; // aborts an outgoing frame in flight
        port.wake.notify(sc_core::SC_ZERO_TIME);
    }
}

// Copies data[p] up to and including ETX (or all 339 bytes), then answers with the ACK word. The
// reader of a frame's last chunk frees pflag[p] before the ACK, so the area is free when the
// writer sees it.
void MainCpu::receive_chunk(unsigned p) {
    Port& port = ports_[p];
    std::string chunk;
    bool last = false;
    for (unsigned i = 0; i < chunk_size && !last; ++i) {
        const std::uint8_t b = read_byte(data_addr(p) + i, config_.copy_loop_cycles);
        chunk += char(b);
        last = b == proto::ETX;
    }
    ++port.stats.chunks_received;
    if (!port.rx_overflow && port.rx.size() + chunk.size() > proto::max_frame) {
        port.rx_overflow = true; // keep ACKing until ETX so the comm CPU is not left hanging
        port.rx.clear();
    }
    if (!port.rx_overflow) port.rx += chunk;
    if (last) write_byte(pflag_addr(p), pflag_free);
    write_mailbox(word(kind_ack, p), Processor::Priority::interrupt);
    if (last) finish_frame(p);
}

void MainCpu::finish_frame(unsigned p) {
    Port& port = ports_[p];
    std::string reason;
    proto::Frame f;
    if (port.rx_overflow)
        reason = "frame longer than " + std::to_string(proto::max_frame) + " bytes";
    else
        reason = proto::decode(port.rx, f);
    if (!reason.empty()) {
        ++port.stats.malformed;
        malformed_.push_back(MalformedRecord{p, sc_time_stamp(), reason});
        log(port_text(p) + ": malformed frame dropped: " + reason);
    } else {
        ++port.stats.frames_received;
        port.stats.bytes_received += port.rx.size();
        const FrameRecord rec{p, sc_time_stamp(), f.token, f.bch, f.data};
        if (on_received) on_received(rec);
        if (keep_history_) received_.push_back(rec);
        rx_frames_.push_back(Received{p, f});
        rx_frame_event_.notify(sc_core::SC_ZERO_TIME);
    }
    port.rx.clear();
    port.rx_overflow = false;
}

void MainCpu::drop_partial(unsigned p) {
    Port& port = ports_[p];
    if (port.rx.empty() && !port.rx_overflow) return;
    ++port.stats.partial_dropped;
    port.rx.clear();
    port.rx_overflow = false;
}

// ---------------------------------------------------------------------------------------------
// command processing

void MainCpu::dispatch_thread() {
    for (;;) {
        while (rx_frames_.empty()) sc_core::wait(rx_frame_event_);
        const Received r = rx_frames_.front();
        rx_frames_.pop_front();
        cpu_.acquire(Processor::Priority::command);
        if (config_.command_time > sc_core::SC_ZERO_TIME) sc_core::wait(config_.command_time);
        const Outcome o = dispatcher_.execute(r.frame.token, r.frame.data);
        cpu_.release();
        if (!o.note.empty()) log(port_text(r.port) + ": " + o.note);
        try {
            enqueue(r.port, proto::Frame{r.frame.token, o.bch, o.data});
        } catch (const std::invalid_argument& e) {
            // Only a motion layer can produce such data; answer "bad data" rather than send junk.
            log(port_text(r.port) + ": " + r.frame.token + " response not sendable: " + e.what());
            enqueue(r.port, proto::Frame{r.frame.token, bch::bad_data, ""});
        }
    }
}

void MainCpu::enqueue(unsigned p, const proto::Frame& f) {
    Outgoing out{proto::encode(f), FrameRecord{p, sc_core::SC_ZERO_TIME, f.token, f.bch, f.data}};
    ports_[p].queue.push_back(std::move(out));
    ports_[p].wake.notify(sc_core::SC_ZERO_TIME);
}

void MainCpu::send(unsigned port, const std::string& token, const std::string& data, std::uint8_t status) {
    check_port(port, "send");
    enqueue(port, proto::Frame{token, status, data});
}

void MainCpu::request_port_reset(unsigned port) {
    check_port(port, "request_port_reset");
    Port& p = ports_[port];
    ++p.epoch;
    p.reset_request = true;
    p.wake.notify(sc_core::SC_ZERO_TIME);
}

// ---------------------------------------------------------------------------------------------
// response transmission, one thread per port

void MainCpu::tx_thread(unsigned p) {
    Port& port = ports_[p];
    for (;;) {
        while (port.queue.empty() && !port.reset_request) sc_core::wait(port.wake);
        if (port.reset_request) {
            port.reset_request = false;
            send_reset(p, false);
            continue;
        }
        Outgoing out = std::move(port.queue.front());
        port.queue.pop_front();
        const std::uint64_t epoch = port.epoch;
        bool complete = true;
        for (std::size_t off = 0; complete && off < out.bytes.size(); off += chunk_size) {
            const std::string chunk = out.bytes.substr(off, chunk_size);
            if (!claim_and_write_chunk(p, chunk, off == 0, epoch)) {
                ++port.stats.tx_aborted;
                complete = false;
                break;
            }
            switch (wait_ack(p, epoch)) {
            case AckResult::acked: ++port.stats.chunks_sent; break;
            case AckResult::reset:
                ++port.stats.tx_aborted;
                complete = false;
                break;
            case AckResult::timeout:
                ++port.stats.ack_timeouts;
                log(port_text(p) + ": no ACK within " + time_text(config_.ack_timeout) +
                    ", frame " + out.record.token + " abandoned, port reset");
                send_reset(p, true);
                complete = false;
                break;
            }
        }
        if (!complete) continue;
        ++port.stats.frames_sent;
        port.stats.bytes_sent += out.bytes.size();
        out.record.time = sc_time_stamp();
        if (on_sent) on_sent(out.record);
        if (keep_history_) sent_.push_back(out.record);
    }
}

// The first chunk claims the area: read pflag[p]; if free, write RBT_USE, all in one busy period
// so that our own activities cannot interleave. Otherwise retry every poll_interval (the comm CPU
// holds the area while a host frame arrives, which can take seconds at 9600 bps).
bool MainCpu::claim_and_write_chunk(unsigned p, const std::string& chunk, bool first, std::uint64_t epoch) {
    Port& port = ports_[p];
    for (;;) {
        if (port.epoch != epoch) return false;
        cpu_.acquire(Processor::Priority::transmit);
        if (first && read_byte(pflag_addr(p)) != pflag_free) {
            cpu_.release();
            sc_core::wait(config_.poll_interval, port.wake);
            continue;
        }
        if (first) write_byte(pflag_addr(p), pflag_rbt_use);
        for (std::size_t i = 0; i < chunk.size(); ++i)
            write_byte(static_cast<std::uint16_t>(data_addr(p) + i), std::uint8_t(chunk[i]),
                       config_.copy_loop_cycles);
        port.awaiting_ack = true; // before the word: the ACK may come at once
        port.acked = false;
        write_mailbox(word(kind_chunk, p), Processor::Priority::transmit);
        cpu_.release();
        return true;
    }
}

MainCpu::AckResult MainCpu::wait_ack(unsigned p, std::uint64_t epoch) {
    Port& port = ports_[p];
    const sc_time deadline = sc_time_stamp() + config_.ack_timeout;
    AckResult result = AckResult::acked;
    for (;;) {
        if (port.acked) break;
        if (port.epoch != epoch) {
            result = AckResult::reset;
            break;
        }
        if (sc_time_stamp() >= deadline) {
            result = AckResult::timeout;
            break;
        }
        sc_core::wait(deadline - sc_time_stamp(), port.wake);
    }
    port.awaiting_ack = false;
    port.acked = false;
    return result;
}

// Tells the comm CPU to reset port p. After an ACK timeout we also free the area we claimed:
// the main CPU only ever clears a pflag it set itself (or the one of a frame it finished reading).
void MainCpu::send_reset(unsigned p, bool release_area) {
    Port& port = ports_[p];
    cpu_.acquire(Processor::Priority::transmit);
    if (release_area) write_byte(pflag_addr(p), pflag_free);
    drop_partial(p);
    write_mailbox(word(kind_reset, p), Processor::Priority::transmit);
    ++port.stats.resets_sent;
    cpu_.release();
}

// ---------------------------------------------------------------------------------------------
// control cycle

// Ideal starts are k * cycle_period. The cycle starts when it gets the processor; the difference
// is the jitter. A cycle that ends after the next ideal start makes that start late; one that
// starts after its successor's ideal start skips the missed periods (counted as overruns).
void MainCpu::cycle_thread() {
    sc_time ideal = sc_core::SC_ZERO_TIME;
    for (;;) {
        if (ideal > sc_time_stamp()) sc_core::wait(ideal - sc_time_stamp());
        const std::string held_by = cpu_.busy() ? Processor::activity(cpu_.owner()) : "";
        cpu_.acquire(Processor::Priority::control_cycle);
        const sc_time start = sc_time_stamp();
        cycle_jitter_us_.add(to_us(start - ideal));
        ++control_cycles_;
        if (MotionInterface* m = dispatcher_.motion()) {
            m->cycle_context(ideal, held_by);
            m->control_cycle(start);
        }
        // A motion layer with a cost model spends its work inside control_cycle (wait()).
        if (ProgramInterface* p = dispatcher_.program()) run_program(*p, start);
        if (config_.cycle_time > sc_core::SC_ZERO_TIME) sc_core::wait(config_.cycle_time);
        cycle_duration_us_.add(to_us(sc_time_stamp() - start));
        cpu_.release();
        ideal += config_.cycle_period;
        while (ideal < start) {
            ideal += config_.cycle_period;
            ++cycle_overruns_;
        }
    }
}

// The program's work costs processor time in the cycle, as the motion layer's does: its
// statements, and the motion blocks it calls as the motion layer's own block calls (their CAMC-QI
// accesses the motion layer spends as they happen).
void MainCpu::run_program(ProgramInterface& p, const sc_time& start) {
    const ProgramWork w = p.cycle(start);
    program_work_.statements += w.statements;
    program_work_.motion_calls += w.motion_calls;
    const sc_time t = config_.statement_time * static_cast<double>(w.statements) +
                      config_.fb_call * static_cast<double>(w.motion_calls);
    program_time_ += t;
    if (t > sc_core::SC_ZERO_TIME) sc_core::wait(t);
}

// ---------------------------------------------------------------------------------------------
// report

nlohmann::json MainCpu::report() const {
    nlohmann::json ports_json = nlohmann::json::array();
    for (unsigned p = 0; p < ports; ++p) {
        const MainCpuPortStats& s = ports_[p].stats;
        ports_json.push_back({{"port", p},
                              {"frames_received", s.frames_received},
                              {"bytes_received", s.bytes_received},
                              {"chunks_received", s.chunks_received},
                              {"malformed", s.malformed},
                              {"frames_sent", s.frames_sent},
                              {"bytes_sent", s.bytes_sent},
                              {"chunks_sent", s.chunks_sent},
                              {"resets_received", s.resets_received},
                              {"resets_sent", s.resets_sent},
                              {"partial_dropped", s.partial_dropped},
                              {"tx_aborted", s.tx_aborted},
                              {"ack_timeouts", s.ack_timeouts},
                              {"unexpected_acks", s.unexpected_acks},
                              {"responses_dropped", s.responses_dropped},
                              {"responses_dropped_sent", s.responses_dropped_sent}});
    }
    nlohmann::json j = {{"cycle_jitter_us", to_json(cycle_jitter_us_.summary())},
            {"irq_latency_us", to_json(irq_latency_us_.summary())},
            {"control_cycles", control_cycles_},
            {"cycle_overruns", cycle_overruns_},
            {"mailbox_words", mailbox_words_},
            {"unknown_words", unknown_words_},
            {"mailbox_overwrites", mailbox_overwrites_},
            {"dpram_accesses", dpram_accesses_},
            {"busy_wait_us", to_us(busy_wait_)},
            {"cpu_busy_us", to_us(cpu_.busy_time())},
            {"ports", ports_json}};
    // Only with a motion layer or a program, whose work makes it vary (a run without keeps its
    // report as before).
    if (dispatcher_.motion() || dispatcher_.program())
        j["cycle_duration_us"] = to_json(cycle_duration_us_.summary());
    if (dispatcher_.program())
        j["program_cost"] = {{"statements", program_work_.statements},
                             {"motion_calls", program_work_.motion_calls},
                             {"statement_us", to_us(config_.statement_time)},
                             {"time_us", to_us(program_time_)}};
    return j;
}

} // namespace rcsim
