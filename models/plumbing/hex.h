// rcsim — an unsigned value as hexadecimal digits, for messages, traces and generated files.
//
// Plain C++ and header-only, so that every floor may use it, the SystemC-free 8086 core
// included (tests/layout allows the core models/memory.h and this header only). The digits are
// those of printf's "%0*X": at least `digits` of them, zero-padded on the left, more when the
// value needs more (never truncated), upper case unless asked otherwise; no "0x" prefix, each
// caller adds its own.
#pragma once

#include <cstdint>
#include <string>

namespace rcsim {

enum class HexCase { upper, lower };

/// `value` in hexadecimal, zero-padded to at least `digits` digits: hex(0xAB) == "AB",
/// hex(0x5, 3) == "005", hex(0x1234, 2) == "1234", hex(0xAB, 2, HexCase::lower) == "ab".
inline std::string hex(std::uint64_t value, unsigned digits = 2, HexCase letters = HexCase::upper) {
    const char* symbols = letters == HexCase::upper ? "0123456789ABCDEF" : "0123456789abcdef";
    char buf[16]; // a 64-bit value has at most 16 digits; filled from the right
    unsigned n = 0;
    do {
        buf[sizeof buf - 1 - n++] = symbols[value & 0xF];
        value >>= 4;
    } while (value != 0);
    std::string out;
    if (digits > n) out.assign(digits - n, '0');
    out.append(buf + sizeof buf - n, n);
    return out;
}

} // namespace rcsim
