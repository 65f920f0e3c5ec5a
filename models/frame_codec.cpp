// rcsim — the serial frame of docs/system.md §5.3 (see frame_codec.h).
#include "models/frame_codec.h"

#include "models/plumbing/hex.h"

#include <cctype>
#include <stdexcept>

namespace rcsim::proto {

namespace {
bool upper_hex(std::uint8_t c) { return (c >= '0' && c <= '9') || (c >= 'A' && c <= 'F'); }
unsigned hex_value(std::uint8_t c) { return c <= '9' ? c - '0' : c - 'A' + 10; }
// Frame layout offsets in the body (T1 T2 STX B1 B2 data... C1 C2).
constexpr std::size_t body_head = 5;
} // namespace

std::string hex2(std::uint8_t v) { return hex(v, 2); }

std::uint8_t sum8(const std::string& bytes) {
    unsigned s = 0;
    for (unsigned char c : bytes) s += c;
    return static_cast<std::uint8_t>(s);
}

std::string encode(const Frame& f) {
    if (f.token.size() != 2 || !printable(f.token[0]) || !printable(f.token[1]))
        throw std::invalid_argument("frame token '" + escape(f.token) + "' is not two printable characters");
    if (f.data.size() > max_data)
        throw std::invalid_argument("frame data of " + std::to_string(f.data.size()) + " bytes exceeds " +
                                    std::to_string(max_data));
    for (std::size_t i = 0; i < f.data.size(); ++i)
        if (!printable(static_cast<std::uint8_t>(f.data[i])))
            throw std::invalid_argument("frame data byte " + escape(f.data.substr(i, 1)) + " at offset " +
                                        std::to_string(i) + " is not printable ASCII");
    std::string body = f.token;
    body += static_cast<char>(STX);
    body += hex2(f.bch);
    body += f.data;
    std::string out(1, static_cast<char>(SOH));
    out += body;
    out += hex2(sum8(body));
    out += static_cast<char>(ETX);
    return out;
}

void FrameDecoder::reset() {
    count_ = 0;
    body_.clear();
    frame_ = Frame{};
    error_.clear();
}

void FrameDecoder::fault(const std::string& why) {
    if (error_.empty()) error_ = why;
}

FrameDecoder::Result FrameDecoder::feed(std::uint8_t byte, bool line_error) {
    const std::size_t at = count_++;
    if (line_error) fault("byte " + std::to_string(at) + " arrived with a parity or framing error");
    if (at == 0) {
        if (byte != SOH) fault("frame starts with " + escape(std::string(1, static_cast<char>(byte))) + ", not SOH");
        return Result::more;
    }
    if (byte == ETX) return finish(); // judged now; a line error on it is already recorded
    const std::size_t pos = at - 1; // position in the body
    if (pos == 2) {
        if (byte != STX) fault("byte 3 is " + escape(std::string(1, static_cast<char>(byte))) + ", not STX");
    } else if (!printable(byte)) {
        fault("byte " + std::to_string(at) + " (" + escape(std::string(1, static_cast<char>(byte))) +
              ") is outside the printable set");
    }
    // Keep at most the longest legal body (+1 to notice an overlong one).
    if (body_.size() <= body_head + max_data + 2) body_ += static_cast<char>(byte);
    else fault("frame longer than " + std::to_string(max_data) + " data bytes");
    return Result::more;
}

FrameDecoder::Result FrameDecoder::finish() {
    if (body_.size() < body_head + 2) fault("frame of " + std::to_string(count_) + " bytes is too short");
    else if (body_.size() > body_head + max_data + 2)
        fault("frame longer than " + std::to_string(max_data) + " data bytes");
    if (error_.empty()) {
        const auto b1 = static_cast<std::uint8_t>(body_[3]), b2 = static_cast<std::uint8_t>(body_[4]);
        const std::size_t n = body_.size();
        const auto c1 = static_cast<std::uint8_t>(body_[n - 2]), c2 = static_cast<std::uint8_t>(body_[n - 1]);
        if (!upper_hex(b1) || !upper_hex(b2)) fault("BCH '" + body_.substr(3, 2) + "' is not two uppercase hex digits");
        else if (!upper_hex(c1) || !upper_hex(c2))
            fault("checksum '" + body_.substr(n - 2) + "' is not two uppercase hex digits");
        else {
            const std::uint8_t want = sum8(body_.substr(0, n - 2));
            const auto got = static_cast<std::uint8_t>(hex_value(c1) << 4 | hex_value(c2));
            if (got != want) fault("checksum " + body_.substr(n - 2) + ", expected " + hex2(want));
            else {
                frame_.token = body_.substr(0, 2);
                frame_.bch = static_cast<std::uint8_t>(hex_value(b1) << 4 | hex_value(b2));
                frame_.data = body_.substr(body_head, n - 2 - body_head);
            }
        }
    }
    return error_.empty() ? Result::good : Result::bad;
}

std::string decode(const std::string& bytes, Frame& out) {
    FrameDecoder d;
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        const auto r = d.feed(static_cast<std::uint8_t>(bytes[i]));
        if (r == FrameDecoder::Result::more) continue;
        if (i + 1 != bytes.size()) return "bytes after ETX at offset " + std::to_string(i + 1);
        if (r == FrameDecoder::Result::bad) return d.error();
        out = d.frame();
        return "";
    }
    return "no ETX";
}

std::string escape(const std::string& bytes) {
    std::string s;
    for (unsigned char c : bytes) {
        if (c == '\\') s += "\\\\";
        else if (printable(c)) s += static_cast<char>(c);
        else s += "\\x" + hex2(c);
    }
    return s;
}

std::string unescape(const std::string& text) {
    static const struct {
        const char* name;
        std::uint8_t value;
    } names[] = {{"SOH", SOH}, {"STX", STX}, {"ETX", ETX}, {"EOT", EOT}, {"ENQ", ENQ}, {"ACK", ACK}, {"NAK", NAK}};
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] != '\\') {
            out += text[i];
            continue;
        }
        const std::size_t at = i;
        auto bad = [&](const std::string& seq) {
            return std::invalid_argument("bad escape '" + seq + "' at offset " + std::to_string(at) + " in \"" +
                                         text + "\"");
        };
        if (i + 1 >= text.size()) throw bad("\\");
        const char e = text[++i];
        switch (e) {
        case 'n': out += '\n'; continue;
        case 'r': out += '\r'; continue;
        case 't': out += '\t'; continue;
        case '0': out += '\0'; continue;
        case '\\': out += '\\'; continue;
        case 'x': {
            if (i + 2 >= text.size() || !std::isxdigit(static_cast<unsigned char>(text[i + 1])) ||
                !std::isxdigit(static_cast<unsigned char>(text[i + 2])))
                throw bad(text.substr(at, 4));
            out += static_cast<char>(std::stoi(text.substr(i + 1, 2), nullptr, 16));
            i += 2;
            continue;
        }
        default: break;
        }
        bool named = false;
        for (const auto& n : names) {
            const std::string name = n.name;
            if (text.compare(i, name.size(), name) == 0) {
                out += static_cast<char>(n.value);
                i += name.size() - 1;
                named = true;
                break;
            }
        }
        if (!named) throw bad(text.substr(at, 2));
    }
    return out;
}

} // namespace rcsim::proto
