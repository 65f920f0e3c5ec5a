// rcsim — a raw serial host (see raw_host.h).
#include "scenarios/host/raw_host.h"

#include "models/plumbing/config_error.h"
#include "models/frame_codec.h"
#include "models/plumbing/output_file.h"

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
        record_.emplace(cfg_.record_path, "the record file");
    }
    if (!cfg_.log_path.empty()) {
        log_.emplace(cfg_.log_path, "the log file");
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
    if (record_) record_->stream().put(static_cast<char>(byte)).flush();
    if (log_)
        log_->stream() << c.stop.value() << ' ' << proto::hex2(byte) << ' ' << (c.parity_error ? "P" : "")
             << (c.framing_error ? "F" : "") << '\n'
             << std::flush;
}

void RawHost::rx_break(bool active) {
    breaks_.emplace_back(sc_core::sc_time_stamp(), active);
    if (log_) log_->stream() << sc_core::sc_time_stamp().value() << " BREAK " << (active ? "on" : "off") << '\n' << std::flush;
}

void RawHost::finish_files() {
    for (std::optional<OutputFile>* f : {&record_, &log_})
        if (*f) (*f)->check();
}

std::string RawHost::text() const {
    std::string s;
    for (const auto& r : received_) s += static_cast<char>(r.byte);
    return s;
}

} // namespace rcsim
