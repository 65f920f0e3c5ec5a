// rcsim — the telnet-style escape of a tcp host's byte stream (`telnet: true`, docs/serial.md).
//
// A plain TCP stream has no out-of-band way to say "BREAK". Telnet (RFC 854) has one: the IAC
// byte (255) introduces a command, IAC BRK (255 243) is "the BREAK key", and a data byte 255 is
// sent doubled (IAC IAC). `telnet`'s own `send brk` and a script's b"\xff\xf3" both use it.
// Option negotiation (IAC WILL/WONT/DO/DONT x, IAC SB ... IAC SE) is taken out of the stream and
// ignored (the host asks for no option and answers none); any other command is dropped.
#pragma once

#include <cstdint>
#include <vector>

namespace rcsim {

namespace telnet {
constexpr std::uint8_t IAC = 255, DONT = 254, DO = 253, WONT = 252, WILL = 251, SB = 250, BRK = 243, SE = 240;
} // namespace telnet

/// The client -> host direction, one byte at a time.
class TelnetDecoder {
public:
    enum class Out { none, byte, brk };

    /// Feeds one byte from the stream; returns what it completes (the byte in `data`).
    Out feed(std::uint8_t b, std::uint8_t& data) {
        using namespace telnet;
        switch (state_) {
        case State::data:
            if (b == IAC) {
                state_ = State::iac;
                return Out::none;
            }
            data = b;
            return Out::byte;
        case State::iac:
            state_ = State::data;
            if (b == IAC) {
                data = b;
                return Out::byte;
            }
            if (b == BRK) return Out::brk;
            if (b >= WILL && b <= DONT) state_ = State::option;
            else if (b == SB) state_ = State::sb;
            return Out::none;
        case State::option: state_ = State::data; return Out::none; // the option code
        case State::sb: state_ = b == IAC ? State::sb_iac : State::sb; return Out::none;
        case State::sb_iac: state_ = b == SE ? State::data : State::sb; return Out::none;
        }
        return Out::none;
    }

private:
    enum class State { data, iac, option, sb, sb_iac } state_ = State::data;
};

/// The host -> client direction: `bytes` with every 255 doubled.
inline std::vector<std::uint8_t> telnet_escape(const std::vector<std::uint8_t>& bytes) {
    std::vector<std::uint8_t> out;
    out.reserve(bytes.size());
    for (std::uint8_t b : bytes) {
        out.push_back(b);
        if (b == telnet::IAC) out.push_back(b);
    }
    return out;
}

} // namespace rcsim
