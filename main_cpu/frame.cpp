// rcsim — frame codec of SYSTEM.md §3 (see frame.h).
#include "main_cpu/frame.h"

#include <stdexcept>

namespace rcsim::frame {

namespace {

/// Value of one uppercase hex digit, or -1.
int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

/// Value of the two uppercase hex digits at s[pos], or -1.
int hex_pair(const std::string& s, std::size_t pos) {
    const int hi = hex_digit(s[pos]);
    const int lo = hex_digit(s[pos + 1]);
    return (hi < 0 || lo < 0) ? -1 : hi * 16 + lo;
}

std::string byte_text(std::uint8_t c) { return "0x" + hex2(c); }

} // namespace

std::string hex2(std::uint8_t v) {
    static const char digits[] = "0123456789ABCDEF";
    return {digits[v >> 4], digits[v & 0xF]};
}

std::uint8_t checksum(const std::string& bytes) {
    unsigned sum = 0;
    for (unsigned char c : bytes) sum += c;
    return static_cast<std::uint8_t>(sum & 0xFF);
}

std::string encode(const Frame& f) {
    if (f.token.size() != 2 || !printable(f.token[0]) || !printable(f.token[1]))
        throw std::invalid_argument("frame token '" + f.token + "' is not two printable characters");
    if (f.data.size() > max_data)
        throw std::invalid_argument("frame data of " + std::to_string(f.data.size()) +
                                    " bytes is over the limit of 8192");
    for (std::size_t i = 0; i < f.data.size(); ++i)
        if (!printable(static_cast<std::uint8_t>(f.data[i])))
            throw std::invalid_argument("frame data byte " + std::to_string(i) + " is " +
                                        byte_text(static_cast<std::uint8_t>(f.data[i])) +
                                        ", not printable ASCII");
    std::string out;
    out.reserve(f.data.size() + overhead);
    out += char(SOH);
    out += f.token;
    out += char(STX);
    out += hex2(f.bch);
    out += f.data;
    // "Every byte from T1 through the last data byte" includes the STX between token and BCH.
    out += hex2(checksum(out.substr(1)));
    out += char(ETX);
    return out;
}

std::string decode(const std::string& b, Frame& out) {
    if (b.size() < overhead)
        return "frame of " + std::to_string(b.size()) + " bytes is shorter than the 9-byte minimum";
    if (b.size() > max_frame)
        return "frame of " + std::to_string(b.size()) + " bytes is over the limit of " +
               std::to_string(max_frame);
    if (std::uint8_t(b[0]) != SOH) return "byte 0 is " + byte_text(b[0]) + ", expected SOH";
    if (std::uint8_t(b[3]) != STX) return "byte 3 is " + byte_text(b[3]) + ", expected STX";
    if (std::uint8_t(b.back()) != ETX)
        return "last byte is " + byte_text(b.back()) + ", expected ETX";
    for (std::size_t i : {1u, 2u})
        if (!printable(b[i])) return "token byte " + byte_text(b[i]) + " is not printable";
    const int bch = hex_pair(b, 4);
    if (bch < 0) return "BCH '" + b.substr(4, 2) + "' is not two uppercase hex digits";
    const std::size_t data_end = b.size() - 3; // C1 C2 ETX follow the data
    for (std::size_t i = 6; i < data_end; ++i)
        if (!printable(b[i]))
            return "data byte " + std::to_string(i - 6) + " is " + byte_text(b[i]) +
                   ", not printable ASCII";
    const int sum = hex_pair(b, data_end);
    if (sum < 0) return "checksum '" + b.substr(data_end, 2) + "' is not two uppercase hex digits";
    const std::string summed = b.substr(1, data_end - 1); // T1 through the last data byte
    if (checksum(summed) != sum)
        return "checksum " + b.substr(data_end, 2) + " does not match the computed " +
               hex2(checksum(summed));
    out.token = b.substr(1, 2);
    out.bch = static_cast<std::uint8_t>(bch);
    out.data = b.substr(6, data_end - 6);
    return "";
}

} // namespace rcsim::frame
