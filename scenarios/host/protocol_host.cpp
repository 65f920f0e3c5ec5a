// rcsim — the simulated external system, protocol side (see protocol_host.h).
#include "scenarios/host/protocol_host.h"

#include "models/clock.h"

#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace rcsim {

using namespace proto;

namespace {
std::string byte_name(std::uint8_t b) {
    switch (b) {
    case SOH: return "SOH";
    case STX: return "STX";
    case ETX: return "ETX";
    case EOT: return "EOT";
    case ENQ: return "ENQ";
    case ACK: return "ACK";
    case NAK: return "NAK";
    default: return escape(std::string(1, static_cast<char>(b)));
    }
}
std::string ms(const sc_core::sc_time& t) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(3) << to_us(t) / 1000.0 << " ms";
    return os.str();
}
} // namespace

HostTraffic::Pattern HostTraffic::parse_pattern(const std::string& s) {
    if (s == "none") return Pattern::none;
    if (s == "fixed") return Pattern::fixed;
    if (s == "poisson") return Pattern::poisson;
    if (s == "burst") return Pattern::burst;
    if (s == "saturate") return Pattern::saturate;
    if (s == "script") return Pattern::script;
    throw std::invalid_argument("unknown traffic pattern '" + s + "' (none, fixed, poisson, burst, saturate, script)");
}

void ProtocolHostConfig::validate() const {
    format.validate();
    const HostTraffic& t = traffic;
    if ((t.pattern == HostTraffic::Pattern::fixed || t.pattern == HostTraffic::Pattern::poisson) &&
        !(t.rate > 0 && t.rate <= 1e6))
        throw std::invalid_argument("traffic rate " + std::to_string(t.rate) + " commands/s (0 < rate <= 1e6)");
    if (t.pattern == HostTraffic::Pattern::burst && (t.burst_size == 0 || t.burst_period == sc_core::SC_ZERO_TIME))
        throw std::invalid_argument("burst of " + std::to_string(t.burst_size) + " every " + t.burst_period.to_string() +
                                    " (both must be non-zero)");
    if (t.data_size > max_data)
        throw std::invalid_argument("data size " + std::to_string(t.data_size) + " exceeds " + std::to_string(max_data));
    if ((t.pattern == HostTraffic::Pattern::script) != !t.script.empty())
        throw std::invalid_argument(t.script.empty() ? "traffic 'script' needs a non-empty 'script' list"
                                                     : "a 'script' list needs 'traffic: script'");
    for (const ScriptStep& st : t.script) {
        if (st.kind != ScriptStep::Kind::command) continue;
        encode(Frame{st.token, 0, st.data}); // throws naming the bad token or byte
        if (st.expect_bch > 255) throw std::invalid_argument("expect_bch " + std::to_string(st.expect_bch) + " is not 0..255");
    }
    if (t.pattern != HostTraffic::Pattern::none && t.tokens.empty())
        throw std::invalid_argument("empty token mix");
    for (const auto& [token, weight] : t.tokens) {
        if (token.size() != 2 || !printable(static_cast<std::uint8_t>(token[0])) ||
            !printable(static_cast<std::uint8_t>(token[1])))
            throw std::invalid_argument("token '" + escape(token) + "' is not two printable characters");
        if (!(weight > 0)) throw std::invalid_argument("token '" + token + "' weight " + std::to_string(weight));
    }
    if (timing.t1 == sc_core::SC_ZERO_TIME || timing.t2 == sc_core::SC_ZERO_TIME)
        throw std::invalid_argument("T1 " + timing.t1.to_string() + " / T2 " + timing.t2.to_string() +
                                    " must be non-zero");
}

ProtocolHost::ProtocolHost(sc_core::sc_module_name name, const ProtocolHostConfig& cfg)
    : sc_module(name), cfg_(cfg), rng_(cfg.traffic.seed), nak_enqs_left_(cfg.nak_enqs) {
    cfg_.validate();
    SC_HAS_PROCESS(ProtocolHost);
    SC_THREAD(run);
    SC_THREAD(generate);
}

void ProtocolHost::end_of_elaboration() { require_connected(name()); }

void ProtocolHost::send(const Frame& f) {
    encode(f); // reject a bad frame here, where the caller can see it
    commands_.push_back(f);
    cmd_ev_.notify(sc_core::SC_ZERO_TIME);
}

// ---------------------------------------------------------------------------------------------
// Line side

void ProtocolHost::rx_char(const SerialRx& c) {
    const bool error = c.parity_error || c.framing_error;
    if (error) ++counters_.line_errors;
    rx_.push_back(RxByte{static_cast<std::uint8_t>(c.data), error, c.stop});
    rx_ev_.notify(sc_core::SC_ZERO_TIME);
}

void ProtocolHost::rx_break(bool active) { note(active ? "< BREAK detected" : "< BREAK ended"); }

bool ProtocolHost::wait_byte(const sc_core::sc_time& timeout, RxByte& out) {
    // Loop: a notification left over from a byte already taken must not end the wait early.
    const sc_core::sc_time deadline = sc_core::sc_time_stamp() + timeout;
    while (rx_.empty()) {
        const sc_core::sc_time now = sc_core::sc_time_stamp();
        if (now >= deadline) return false;
        wait(deadline - now, rx_ev_);
    }
    out = rx_.front();
    rx_.pop_front();
    return true;
}

void ProtocolHost::send_bytes(const std::string& bytes) {
    for (unsigned char b : bytes) {
        line_->transmit(side_, SerialWord::encode(b, cfg_.format));
        wait(cfg_.format.frame_time());
    }
}

void ProtocolHost::note(const std::string& text) {
    last_step_ = LogEntry{sc_core::sc_time_stamp(), text};
    if (keep_history_) log_.push_back(LogEntry{sc_core::sc_time_stamp(), text});
    if (log_os_) *log_os_ << std::setw(14) << ms(sc_core::sc_time_stamp()) << "  " << name() << ": " << text << '\n';
}

// ---------------------------------------------------------------------------------------------
// Protocol thread

void ProtocolHost::run() {
    for (;;) {
        RxByte b{};
        if (wait_byte(sc_core::SC_ZERO_TIME, b)) {
            if (b.byte == ENQ && !b.error) serve_controller();
            else note("< " + byte_name(b.byte) + (b.error ? " (line error)" : "") + " ignored while idle");
            continue;
        }
        const sc_core::sc_time now = sc_core::sc_time_stamp();
        if (awaiting_response_ && now >= response_deadline_) {
            awaiting_response_ = false;
            ++counters_.response_timeouts;
            last_response_timed_out_ = true;
            idle_ev_.notify(sc_core::SC_ZERO_TIME);
            note("no response frame within " + ms(cfg_.traffic.response_timeout));
        }
        const bool saturate = cfg_.traffic.pattern == HostTraffic::Pattern::saturate && may_generate();
        if (!awaiting_response_ && commands_.empty() && saturate && now >= cfg_.traffic.start)
            commands_.push_back(make_command());
        if (!awaiting_response_ && !commands_.empty()) {
            const Frame f = commands_.front();
            commands_.pop_front();
            cmd_taken_ev_.notify(sc_core::SC_ZERO_TIME);
            do_command(f);
            continue;
        }
        // Sleep until a byte or a command arrives, the response times out, or traffic starts.
        sc_core::sc_time wake = sc_core::SC_ZERO_TIME;
        if (awaiting_response_) wake = response_deadline_ - now;
        if (saturate && now < cfg_.traffic.start && (wake == sc_core::SC_ZERO_TIME || cfg_.traffic.start - now < wake))
            wake = cfg_.traffic.start - now;
        if (wake != sc_core::SC_ZERO_TIME) wait(wake, rx_ev_ | cmd_ev_);
        else wait(rx_ev_ | cmd_ev_);
    }
}

// Called when the ENQ or ETX has left the line (send_bytes returns at the end of its last stop
// bit): T1 runs from here to the START bit of the answer, which a receiver has one character
// later (docs/serial.md "Protocol timers"; the firmware counts it the same way).
sc_core::sc_time ProtocolHost::t1_deadline() const {
    return sc_core::sc_time_stamp() + cfg_.timing.t1 + cfg_.format.receive_time();
}

ProtocolHost::Reply ProtocolHost::await_reply(std::uint8_t positive, const char* what) {
    const sc_core::sc_time deadline = t1_deadline();
    for (;;) {
        RxByte b{};
        const sc_core::sc_time now = sc_core::sc_time_stamp();
        if (now >= deadline || !wait_byte(deadline - now, b)) {
            ++counters_.timeouts;
            note(std::string("no ") + what + " within T1");
            return Reply::timeout;
        }
        if (b.error) {
            note("< " + byte_name(b.byte) + " with a line error, ignored");
            continue;
        }
        if (b.byte == positive) {
            note("< " + byte_name(b.byte));
            return Reply::positive;
        }
        if (b.byte == NAK) {
            ++counters_.naks;
            note("< NAK");
            return Reply::nak;
        }
        if (b.byte == ENQ && positive == ACK) {
            ++counters_.collisions;
            note("< ENQ: collision, the external system wins; ignored");
            continue;
        }
        note("< " + byte_name(b.byte) + " unexpected, ignored");
    }
}

void ProtocolHost::do_command(const Frame& f) {
    busy_ = true;
    ++counters_.frames_sent;
    const std::string bytes = encode(f);
    command_start_ = sc_core::sc_time_stamp();
    note("command " + f.token + " with " + std::to_string(f.data.size()) + " data bytes");
    bool need_enq = true;
    for (unsigned attempt = 0;; ++attempt) {
        Reply r = Reply::positive;
        if (need_enq) {
            note("> ENQ");
            send_bytes(std::string(1, static_cast<char>(ENQ)));
            r = await_reply(ACK, "ACK/NAK");
        }
        if (r == Reply::positive) {
            need_enq = false;
            note("> frame " + escape(bytes.size() <= 40 ? bytes : bytes.substr(0, 36) + "...") + " (" +
                 std::to_string(bytes.size()) + " bytes)");
            send_bytes(bytes);
            last_etx_ = sc_core::sc_time_stamp();
            r = await_reply(EOT, "EOT/NAK");
            if (r == Reply::positive) {
                ++counters_.frames_delivered;
                if (keep_history_) delivered_.push_back(f);
                if (on_delivered) on_delivered(f);
                delivery_us_.add(to_us(sc_core::sc_time_stamp() - command_start_));
                awaiting_response_ = scripted() ? script_await_ : cfg_.traffic.wait_response;
                response_deadline_ = sc_core::sc_time_stamp() + cfg_.traffic.response_timeout;
                busy_ = false;
                last_failed_ = false;
                idle_ev_.notify(sc_core::SC_ZERO_TIME);
                return;
            }
            // After a NAK or a timeout the receiver has dropped the frame and is idle again, so
            // the retry is a new transfer: ENQ, then the whole frame (docs/serial.md).
            need_enq = true;
        }
        if (attempt == cfg_.timing.max_retries) {
            ++counters_.frames_failed;
            if (!first_failure_) first_failure_ = Failure{sc_core::sc_time_stamp(), f.token};
            note("command " + f.token + " failed after " + std::to_string(attempt) + " retries");
            busy_ = false;
            last_failed_ = true;
            idle_ev_.notify(sc_core::SC_ZERO_TIME);
            return;
        }
        ++counters_.retries;
        wait(cfg_.timing.backoff * static_cast<double>(attempt + 1));
        note("retry " + std::to_string(attempt + 1) + (need_enq ? " (ENQ)" : " (frame)"));
    }
}

void ProtocolHost::serve_controller() {
    ++counters_.enqs_received;
    note("< ENQ");
    if (cfg_.timing.reply_delay != sc_core::SC_ZERO_TIME) wait(cfg_.timing.reply_delay);
    if (nak_enqs_left_ > 0) {
        --nak_enqs_left_;
        ++counters_.naks_sent;
        note("> NAK (refusing)");
        send_bytes(std::string(1, static_cast<char>(NAK)));
        return;
    }
    note("> ACK");
    send_bytes(std::string(1, static_cast<char>(ACK)));
    decoder_.reset();
    // The frame must start within T1 of the ACK; a repeated ENQ (our ACK was lost) is answered.
    const sc_core::sc_time deadline = t1_deadline();
    RxByte b{};
    for (;;) {
        const sc_core::sc_time now = sc_core::sc_time_stamp();
        if (now >= deadline || !wait_byte(deadline - now, b)) {
            ++counters_.frames_dropped;
            note("no frame within T1 after ACK");
            return;
        }
        if (b.byte == SOH) break;
        if (b.byte == ENQ && !b.error) {
            note("< ENQ again; > ACK");
            send_bytes(std::string(1, static_cast<char>(ACK)));
            continue;
        }
        note("< " + byte_name(b.byte) + " before SOH, ignored");
    }
    for (;;) {
        const FrameDecoder::Result r = decoder_.feed(b.byte, b.error);
        if (r == FrameDecoder::Result::more) {
            if (!wait_byte(cfg_.timing.t2, b)) {
                ++counters_.frames_dropped;
                note("T2 gap after " + std::to_string(decoder_.bytes()) + " bytes: partial frame dropped");
                return;
            }
            continue;
        }
        if (cfg_.timing.reply_delay != sc_core::SC_ZERO_TIME) wait(cfg_.timing.reply_delay);
        if (r == FrameDecoder::Result::bad) {
            ++counters_.naks_sent;
            note("bad frame (" + decoder_.error() + "); > NAK");
            send_bytes(std::string(1, static_cast<char>(NAK)));
            return;
        }
        const Frame& f = decoder_.frame();
        note("frame " + f.token + " BCH " + hex2(f.bch) + " with " + std::to_string(f.data.size()) +
             " data bytes; > EOT");
        ++counters_.responses_received;
        if (keep_history_) responses_.push_back(f);
        if (awaiting_response_) {
            awaiting_response_ = false;
            response_us_.add(to_us(b.at - command_start_));
            last_response_ = f;
            idle_ev_.notify(sc_core::SC_ZERO_TIME);
        }
        send_bytes(std::string(1, static_cast<char>(EOT)));
        return;
    }
}

// ---------------------------------------------------------------------------------------------
// Traffic generation

std::uint64_t ProtocolHost::next_random() {
    // splitmix64: a fixed sequence per seed on every platform
    std::uint64_t z = (rng_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

Frame ProtocolHost::make_command() {
    const HostTraffic& t = cfg_.traffic;
    ++generated_;
    double total = 0;
    for (const auto& tw : t.tokens) total += tw.second;
    double pick = next_uniform() * total;
    Frame f;
    f.token = t.tokens.back().first;
    for (const auto& [token, weight] : t.tokens) {
        if (pick < weight) {
            f.token = token;
            break;
        }
        pick -= weight;
    }
    std::size_t n = t.random_size ? static_cast<std::size_t>(next_random() % (t.data_size + 1)) : t.data_size;
    if (f.token == "ST" || f.token == "HT") n = 0; // docs/system.md §7.2: no data
    f.data.resize(n);
    for (auto& c : f.data) c = static_cast<char>(0x20 + next_random() % 95); // printable ASCII
    return f;
}

// The queue is the external system's command buffer: when the line cannot carry what the
// traffic pattern generates, it fills, and generation waits for the protocol thread to take the
// oldest command. Memory stays bounded whatever rate or burst a scenario asks for.
void ProtocolHost::queue_generated() {
    while (commands_.size() >= kMaxQueuedCommands) wait(cmd_taken_ev_);
    commands_.push_back(make_command());
    cmd_ev_.notify(sc_core::SC_ZERO_TIME);
}

void ProtocolHost::generate() {
    const HostTraffic& t = cfg_.traffic;
    using P = HostTraffic::Pattern;
    if (t.pattern == P::script) return run_script();
    if (t.pattern == P::none || t.pattern == P::saturate) return; // saturate: run() makes them
    wait(t.start);
    const sc_core::sc_time period = ps(static_cast<std::uint64_t>(std::llround(1e12 / t.rate)));
    while (may_generate()) {
        if (t.pattern == P::burst) {
            for (unsigned i = 0; i < t.burst_size && may_generate(); ++i) queue_generated();
            wait(t.burst_period);
            continue;
        }
        queue_generated();
        if (t.pattern == P::fixed) wait(period);
        else wait(ps(static_cast<std::uint64_t>(std::llround(-std::log(1.0 - next_uniform()) / t.rate * 1e12))));
    }
}

// ---------------------------------------------------------------------------------------------
// Script

void ProtocolHost::transact(const Frame& f, bool wait_response) {
    last_failed_ = last_response_timed_out_ = false;
    last_response_.reset();
    script_await_ = wait_response;
    send(f);
    // send() only queued it: wait until run() has taken it, finished it and had its answer.
    do wait(idle_ev_);
    while (!idle());
}

void ProtocolHost::fail_step(const ScriptStep& s, const std::string& why) {
    script_.failed = true;
    script_.failed_step = script_.completed;
    script_.failed_line = s.line;
    script_.failure = why;
    note("script step " + std::to_string(script_.completed) + " (line " + std::to_string(s.line) + ") failed: " + why);
}

void ProtocolHost::script_step(const ScriptStep& s) {
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    if (s.at > now) wait(s.at - now);
    switch (s.kind) {
    case ScriptStep::Kind::delay: wait(s.duration); return;
    case ScriptStep::Kind::command: {
        transact(Frame{s.token, 0, s.data}, s.wait_response);
        if (last_failed_) return fail_step(s, s.token + " was not delivered (given up after the retries)");
        script_.commands.push_back({s.token, last_etx_, last_response_ ? last_response_->bch : -1});
        if (!s.wait_response) return;
        if (!last_response_) return fail_step(s, "no response to " + s.token + " within the response timeout");
        if (s.expect_bch >= 0 && last_response_->bch != s.expect_bch)
            return fail_step(s, s.token + " answered BCH " + hex2(last_response_->bch) + " '" +
                                    escape(last_response_->data) + "', expected " +
                                    hex2(static_cast<std::uint8_t>(s.expect_bch)));
        return;
    }
    case ScriptStep::Kind::wait_state: {
        // docs/system.md §7.2: the ST reply starts with the robot state, up to the first comma.
        const sc_core::sc_time deadline = sc_core::sc_time_stamp() + s.timeout;
        std::string seen = "(no reply)";
        for (;;) {
            transact(Frame{"ST", 0, ""}, true);
            if (last_response_ && last_response_->bch == 0) {
                seen = last_response_->data.substr(0, last_response_->data.find(','));
                if (seen == s.state) return;
            }
            if (sc_core::sc_time_stamp() + s.poll > deadline)
                return fail_step(s, "state " + s.state + " not reached within " + ms(s.timeout) + " (last ST: " +
                                        escape(seen) + ")");
            wait(s.poll);
        }
    }
    }
}

// One step at a time; a step that goes wrong stops the script (what follows assumed it worked).
void ProtocolHost::run_script() {
    script_.steps = cfg_.traffic.script.size();
    for (const ScriptStep& s : cfg_.traffic.script) {
        if (stopped_) return;
        script_step(s);
        if (script_.failed) return;
        ++script_.completed;
    }
    script_.finished_at = sc_core::sc_time_stamp();
    note("script done");
}

} // namespace rcsim
