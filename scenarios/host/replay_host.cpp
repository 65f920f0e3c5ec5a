// rcsim — session logs and the replay host (see replay_host.h).
#include "scenarios/host/replay_host.h"

#include "models/clock.h"
#include "models/plumbing/config_error.h"
#include "models/frame_codec.h"

#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace rcsim {

namespace {

const char* kind_word(SessionEvent::Kind k) {
    switch (k) {
    case SessionEvent::Kind::in: return "in";
    case SessionEvent::Kind::out: return "out";
    case SessionEvent::Kind::connect: return "connect";
    case SessionEvent::Kind::disconnect: return "disconnect";
    case SessionEvent::Kind::listen: return "listen";
    case SessionEvent::Kind::end: return "end";
    }
    return "?";
}

std::string describe_out(std::uint8_t byte, bool p, bool f, const sc_core::sc_time& at) {
    std::string s = proto::hex2(byte);
    if (p) s += " P";
    if (f) s += " F";
    return s + " at " + std::to_string(at.value()) + " ps";
}

/// A log time: decimal digits only (no sign, no spaces, no exponent), at most kMaxSessionTimePs.
bool parse_time_ps(const std::string& text, std::uint64_t& out) {
    if (text.empty() || text.size() > 20) return false;
    for (char c : text)
        if (c < '0' || c > '9') return false;
    const char* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, out);
    return r.ec == std::errc() && r.ptr == end && out <= kMaxSessionTimePs;
}

/// Opens a log for reading: a regular file of at most kMaxSessionLogBytes (a device such as
/// /dev/zero would be read forever, a huge file into memory).
std::ifstream open_log(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (fs::is_directory(st)) throw ConfigError(path, 0, "is a directory, not a session log");
    if (fs::exists(st) && !fs::is_regular_file(st)) throw ConfigError(path, 0, "is not a regular file (a session log)");
    std::ifstream is(path);
    if (!is) throw ConfigError(path, 0, "cannot open the session log");
    const std::uintmax_t size = fs::file_size(path, ec);
    if (!ec && size > kMaxSessionLogBytes)
        throw ConfigError(path, 0, "session log is " + std::to_string(size) + " bytes; at most " +
                                       std::to_string(kMaxSessionLogBytes) + " are read");
    return is;
}

} // namespace

// ---- writer ----

void SessionLogWriter::open(const std::string& path, const SerialFormat& f) {
    path_ = path;
    os_.open(path, std::ios::trunc);
    if (!os_) throw ConfigError(path, 0, "cannot open the session log for writing");
    os_ << "# rcsim serial session log v1: <time ps> in|out <hex> [P][F] | connect | disconnect | end\n"
        << "format " << f.describe() << '\n'
        << std::flush;
    note_failure();
}

void SessionLogWriter::note_failure() {
    // errno is the failed write's: every line is flushed right before this check.
    if (!os_ && error_.empty()) error_ = errno ? std::strerror(errno) : "write error";
}

void SessionLogWriter::check() const {
    if (!error_.empty()) throw ConfigError(path_, 0, "cannot write the session log: " + error_);
}

void SessionLogWriter::in(const sc_core::sc_time& at, std::uint8_t byte) {
    if (!os_.is_open()) return;
    os_ << at.value() << " in " << proto::hex2(byte) << '\n' << std::flush;
    note_failure();
}

void SessionLogWriter::out(const sc_core::sc_time& at, std::uint8_t byte, bool parity_error, bool framing_error) {
    if (!os_.is_open()) return;
    os_ << at.value() << " out " << proto::hex2(byte);
    if (parity_error || framing_error) os_ << ' ' << (parity_error ? "P" : "") << (framing_error ? "F" : "");
    os_ << '\n' << std::flush;
    note_failure();
}

void SessionLogWriter::event(const sc_core::sc_time& at, SessionEvent::Kind k, const std::string& text) {
    if (!os_.is_open()) return;
    os_ << at.value() << ' ' << kind_word(k);
    if (!text.empty()) os_ << ' ' << text;
    os_ << '\n' << std::flush;
    note_failure();
}

// ---- reader ----

SessionLog read_session_log(const std::string& path) {
    std::ifstream is = open_log(path);
    SessionLog log;
    std::string line;
    int n = 0;
    std::uint64_t last = 0;
    while (std::getline(is, line)) {
        ++n;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty() || line[0] == '#') continue;
        std::istringstream ls(line);
        std::string first;
        ls >> first;
        if (first == "format") {
            std::string f;
            ls >> f;
            try {
                log.format = SerialFormat::parse(f);
            } catch (const std::exception& e) {
                throw ConfigError(path, n, "bad format '" + f + "': " + e.what());
            }
            continue;
        }
        std::uint64_t t = 0;
        if (!parse_time_ps(first, t)) {
            const bool digits = !first.empty() && first.find_first_not_of("0123456789") == std::string::npos;
            throw ConfigError(path, n, digits ? "time " + first + " ps is beyond " + std::to_string(kMaxSessionTimePs) +
                                                    " ps (3600 s, the longest run)"
                                              : ("expected '<time ps> <event>' or 'format ...', got '" +
                                                               line.substr(0, 80) + "'"));
        }
        if (t < last) throw ConfigError(path, n, "time " + std::to_string(t) + " ps goes backwards");
        last = t;
        SessionEvent ev;
        ev.at = ps(t);
        std::string word;
        ls >> word;
        if (word == "in" || word == "out") {
            ev.kind = word == "in" ? SessionEvent::Kind::in : SessionEvent::Kind::out;
            std::string hex, flags;
            ls >> hex >> flags;
            unsigned v = 0;
            const char* end = hex.data() + hex.size();
            const auto r = std::from_chars(hex.data(), end, v, 16);
            if (hex.empty() || hex.size() > 2 || r.ec != std::errc() || r.ptr != end)
                throw ConfigError(path, n, "bad byte '" + hex.substr(0, 40) + "' (two hex digits)");
            ev.byte = static_cast<std::uint8_t>(v);
            for (char c : flags) {
                if (c == 'P') ev.parity_error = true;
                else if (c == 'F') ev.framing_error = true;
                else throw ConfigError(path, n, "bad flags '" + flags.substr(0, 40) + "' (P, F)");
            }
        } else if (word == "connect") {
            ev.kind = SessionEvent::Kind::connect;
        } else if (word == "disconnect") {
            ev.kind = SessionEvent::Kind::disconnect;
        } else if (word == "end") {
            ev.kind = SessionEvent::Kind::end;
        } else if (word == "listen") {
            ev.kind = SessionEvent::Kind::listen;
            ls >> ev.text;
        } else {
            throw ConfigError(path, n, ("unknown event '" + word.substr(0, 40) +
                                                      "' (in, out, connect, disconnect, listen, end)"));
        }
        std::string extra;
        if (ls >> extra) throw ConfigError(path, n, ("unexpected '" + extra.substr(0, 40) + "' at the end of the line"));
        log.events.push_back(ev);
    }
    return log;
}

// ---- replay host ----

ReplayHost::ReplayHost(sc_core::sc_module_name name, const ReplayHostConfig& cfg) : sc_module(name), cfg_(cfg) {
    SessionLog log = read_session_log(cfg_.file);
    format_ = cfg_.format ? *cfg_.format : log.format ? *log.format : SerialFormat::rs232(9600);
    format_.validate();
    bool has_end = false;
    for (const SessionEvent& e : log.events) {
        if (e.kind == SessionEvent::Kind::in) in_.push_back(e);
        if (e.kind == SessionEvent::Kind::out) out_.push_back(e);
        if (e.kind == SessionEvent::Kind::end && !has_end) {
            end_ = e.at;
            has_end = true;
        }
        if (!has_end) end_ = e.at;
    }
    counters_.out_expected = out_.size();
    if (!cfg_.record_path.empty()) rec_.open(cfg_.record_path, format_);
    SC_HAS_PROCESS(ReplayHost);
    SC_THREAD(run);
}

void ReplayHost::end_of_elaboration() { require_connected(name()); }

void ReplayHost::run() {
    sc_core::sc_time free_at = sc_core::SC_ZERO_TIME; // the transmitter is busy until then
    for (const SessionEvent& e : in_) {
        sc_core::sc_time at = e.at;
        if (at < free_at) {
            at = free_at;
            ++counters_.bytes_late;
        }
        const sc_core::sc_time now = sc_core::sc_time_stamp();
        if (at > now) wait(at - now);
        line_->transmit(side_, SerialWord::encode(e.byte, format_));
        rec_.in(sc_core::sc_time_stamp(), e.byte);
        ++counters_.bytes_sent;
        free_at = sc_core::sc_time_stamp() + format_.frame_time();
    }
    if (cfg_.end_at_log_end) {
        const sc_core::sc_time now = sc_core::sc_time_stamp();
        if (end_ > now) wait(end_ - now);
        rec_.event(sc_core::sc_time_stamp(), SessionEvent::Kind::end);
        sc_core::sc_pause();
    }
}

void ReplayHost::rx_char(const SerialRx& c) {
    const auto byte = static_cast<std::uint8_t>(c.data);
    rec_.out(c.stop, byte, c.parity_error, c.framing_error);
    const std::uint64_t k = counters_.bytes_received++;
    const bool ok = k < out_.size() && out_[k].byte == byte && out_[k].parity_error == c.parity_error &&
                    out_[k].framing_error == c.framing_error && out_[k].at == c.stop;
    if (ok) {
        ++counters_.out_matched;
        return;
    }
    ++counters_.out_mismatched;
    if (first_mismatch_.empty()) {
        first_mismatch_ = "out #" + std::to_string(k) + ": expected " +
                          (k < out_.size() ? describe_out(out_[k].byte, out_[k].parity_error, out_[k].framing_error,
                                                          out_[k].at)
                                           : std::string("nothing")) +
                          ", got " + describe_out(byte, c.parity_error, c.framing_error, c.stop);
    }
}

std::uint64_t ReplayHost::out_missing() const {
    return counters_.bytes_received < out_.size() ? out_.size() - counters_.bytes_received : 0;
}

} // namespace rcsim
