// rcsim — a raw serial host (see raw_host.h).
#include "scenarios/host/raw_host.h"

#include "models/config_error.h"
#include "models/frame_codec.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace rcsim {

void RawHostConfig::add(const sc_core::sc_time& at, const std::string& escaped) {
    sends.push_back(Send{at, proto::unescape(escaped)});
}

RawHost::RawHost(sc_core::sc_module_name name, const RawHostConfig& cfg) : sc_module(name), cfg_(cfg) {
    cfg_.format.validate();
    // Sends run in time order; equal times keep their given order.
    std::stable_sort(cfg_.sends.begin(), cfg_.sends.end(), [](const auto& x, const auto& y) { return x.at < y.at; });
    if (!cfg_.record_path.empty()) {
        record_.open(cfg_.record_path, std::ios::binary | std::ios::trunc);
        if (!record_) throw ConfigError(cfg_.record_path, 0, "cannot open the record file for writing");
    }
    if (!cfg_.log_path.empty()) {
        log_.open(cfg_.log_path, std::ios::trunc);
        if (!log_) throw ConfigError(cfg_.log_path, 0, "cannot open the log file for writing");
    }
    SC_HAS_PROCESS(RawHost);
    SC_THREAD(run);
}

void RawHost::end_of_elaboration() { require_connected(name()); }

void RawHost::run() {
    for (const auto& s : cfg_.sends) {
        const sc_core::sc_time now = sc_core::sc_time_stamp();
        if (s.at > now) wait(s.at - now);
        for (unsigned char b : s.bytes) {
            line_->transmit(side_, SerialWord::encode(b, cfg_.format));
            ++sent_;
            wait(cfg_.format.frame_time());
        }
    }
}

void RawHost::rx_char(const SerialRx& c) {
    const auto byte = static_cast<std::uint8_t>(c.data);
    received_.push_back(Received{c.stop, byte, c.parity_error, c.framing_error});
    if (record_.is_open()) record_.put(static_cast<char>(byte)).flush();
    if (log_.is_open())
        log_ << c.stop.value() << ' ' << proto::hex2(byte) << ' ' << (c.parity_error ? "P" : "")
             << (c.framing_error ? "F" : "") << '\n'
             << std::flush;
}

void RawHost::rx_break(bool active) {
    breaks_.emplace_back(sc_core::sc_time_stamp(), active);
    if (log_.is_open()) log_ << sc_core::sc_time_stamp().value() << " BREAK " << (active ? "on" : "off") << '\n' << std::flush;
}

void RawHost::finish_files() {
    for (auto [os, path] : {std::pair{&record_, &cfg_.record_path}, std::pair{&log_, &cfg_.log_path}}) {
        if (!os->is_open()) continue;
        os->flush();
        if (!*os) throw ConfigError(*path, 0, std::string("cannot write the file: ") + std::strerror(errno));
    }
}

std::string RawHost::text() const {
    std::string s;
    for (const auto& r : received_) s += static_cast<char>(r.byte);
    return s;
}

} // namespace rcsim
