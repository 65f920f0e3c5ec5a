// rcsim — the whole controller on its lines: the real firmware ROM (RCSIM_COMM_FW_ROM) on the assembled
// communication board, the IDT7130 and the behavioural main CPU (rcsim::Controller), one RS-232C
// line per port with the controller's 82510 on side a and a simulated host on side b.
#pragma once

#include "comm_fw_symbols.h"
#include "scenarios/board/controller.h"
#include "models/serial_line.h"
#include "models/frame_codec.h"
#include "scenarios/host/protocol_host.h"
#include "scenarios/host/raw_host.h"
#include "tests/support/serial_times.h"

#include <systemc>
#include <tlm>

#include <array>
#include <cstdint>
#include <functional>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

namespace rcsim::systest {

using sc_core::sc_time;

/// The firmware has programmed its 82510s well before this (it is in the main loop after ~3 ms).
inline sc_time k_boot() { return ms(30); }

class Board {
public:
    static constexpr unsigned kPorts = 3;

    Controller ctl;
    sc_core::sc_vector<SerialLine> lines;

    /// Every character put on line p, either direction, in order (a wire tap on the line).
    struct Char {
        sc_time at; // START edge
        SerialLine::Side from;
        std::uint8_t byte;
    };
    std::array<std::vector<Char>, kPorts> wire;
    /// Called for every character on any line after it was recorded (e.g. to time a host's reaction).
    std::function<void(unsigned port, const Char&)> on_char;

    explicit Board(const ControllerConfig& cfg = ControllerConfig()) : ctl("ctl", cfg), lines("line", kPorts) {
        ctl.comm.load_rom(RCSIM_COMM_FW_ROM);
        for (unsigned p = 0; p < kPorts; ++p) {
            ctl.comm.uart[p].connect(lines[p], SerialLine::a);
            lines[p].on_transmit = [this, p](const SerialLine::Traced& t) {
                const Char c{t.start, t.from, static_cast<std::uint8_t>((t.word.cells >> 1) & 0xFF)};
                wire[p].push_back(c);
                if (on_char) on_char(p, c);
            };
        }
    }

    /// The bytes the controller (side a) or the host (side b) put on line p, in order.
    std::string sent_by(unsigned p, SerialLine::Side side) const {
        std::string s;
        for (const Char& c : wire[p])
            if (c.from == side) s.push_back(static_cast<char>(c.byte));
        return s;
    }
    std::string from_controller(unsigned p) const { return sent_by(p, SerialLine::a); }
    std::string from_host(unsigned p) const { return sent_by(p, SerialLine::b); }
    /// Line p as text, one character a line ("  31.431 ms  ctl> \x06"), for failure messages.
    std::string transcript(unsigned p) const {
        std::ostringstream os;
        for (const Char& c : wire[p])
            os << "  " << to_us(c.at) / 1000.0 << " ms  " << (c.from == SerialLine::a ? "ctl> " : "host> ")
               << proto::escape(std::string(1, static_cast<char>(c.byte))) << '\n';
        return os.str();
    }

    SerialLine& line(unsigned p) { return lines[p]; }

    /// pflag[p] as the IDT7130 holds it (side-effect free).
    std::uint8_t pflag(unsigned p) const { return ctl.dpram.peek(p * 340 + 339); }
    /// Writes one DP-RAM byte through the debug interface (no arbitration, no mailbox interrupt).
    void dpram_poke(unsigned addr, std::uint8_t v) {
        tlm::tlm_generic_payload gp;
        gp.set_command(tlm::TLM_WRITE_COMMAND);
        gp.set_address(addr);
        gp.set_data_ptr(&v);
        gp.set_data_length(1);
        gp.set_streaming_width(1);
        ctl.dpram.right.get_base_interface().transport_dbg(gp);
    }
    /// The firmware's step[p] (diagnosis only; the tests assert what the line and the main CPU see).
    unsigned step(unsigned p) { return ctl.comm.ram().at(comm_fw::data::step + p); }

    /// Runs the simulation until `pred` holds (checked every `poll`) or `limit` more time has passed.
    static bool run_until(const std::function<bool()>& pred, const sc_time& limit, const sc_time& poll = ms(1)) {
        const sc_time end = sc_core::sc_time_stamp() + limit;
        while (!pred()) {
            if (sc_core::sc_time_stamp() >= end) return false;
            sc_core::sc_start(poll);
        }
        return true;
    }
    static void run_to(const sc_time& t) {
        if (t > sc_core::sc_time_stamp()) sc_core::sc_start(t - sc_core::sc_time_stamp());
    }
};

/// A protocol host (scenarios/host) on port p, logging to a string for failure messages.
struct HostOn {
    ProtocolHost host;
    std::ostringstream log;
    HostOn(const char* name, Board& b, unsigned p, const ProtocolHostConfig& cfg = {}) : host(name, cfg) {
        host.connect(b.line(p), SerialLine::b);
        host.log_to(&log);
    }
};

/// The bytes a raw host received, as escaped text ("\x06\x04...").
inline std::string got(const RawHost& h) { return proto::escape(h.text()); }

inline std::string frame(const std::string& token, const std::string& data, std::uint8_t bch = 0) {
    return proto::encode(proto::Frame{token, bch, data});
}

/// `n` printable bytes, a deterministic pattern that is not periodic in 339.
inline std::string pattern(std::size_t n) {
    std::string s;
    s.reserve(n);
    for (std::size_t i = 0; i < n; ++i) s.push_back(static_cast<char>(0x20 + (i * 7 + i / 95) % 95));
    return s;
}

/// `s` with every trailing ENQ removed (the controller's own attempts to send a response to a raw
/// host, which never answers them); returns the count removed in `n`.
inline std::string strip_trailing_enqs(std::string s, unsigned& n) {
    n = 0;
    while (!s.empty() && s.back() == '\x05') {
        s.pop_back();
        ++n;
    }
    return s;
}

} // namespace rcsim::systest
