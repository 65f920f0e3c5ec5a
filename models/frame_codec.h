// rcsim — the serial frame of docs/system.md §5.3, encoder and incremental decoder. Plain C++ (no
// SystemC), so the hosts, the main CPU model and tools can share one definition.
//
//     SOH T1 T2 STX B1 B2 data... C1 C2 ETX
//
// token T1 T2: two printable characters; BCH B1 B2: two uppercase hex digits; data: printable
// ASCII 0x20..0x7E, 0..8192 bytes (so ETX never appears inside a frame); checksum C1 C2: two
// uppercase hex digits of the 8-bit sum of every byte from T1 through the last data byte (STX and
// BCH included). Control bytes SOH 0x01, STX 0x02, ETX 0x03, EOT 0x04, ENQ 0x05, ACK 0x06, NAK 0x15.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace rcsim::proto {

constexpr std::uint8_t SOH = 0x01, STX = 0x02, ETX = 0x03, EOT = 0x04, ENQ = 0x05, ACK = 0x06, NAK = 0x15;
constexpr std::size_t max_data = 8192;
constexpr std::size_t overhead = 9;                     // SOH T1 T2 STX B1 B2 C1 C2 ETX
constexpr std::size_t max_frame = max_data + overhead;

struct Frame {
    std::string token; // two printable characters
    std::uint8_t bch = 0;
    std::string data;
    bool operator==(const Frame& o) const { return token == o.token && bch == o.bch && data == o.data; }
};

inline bool printable(std::uint8_t c) { return c >= 0x20 && c <= 0x7E; }
/// Two uppercase hex digits.
std::string hex2(std::uint8_t v);
/// The 8-bit sum of `bytes`.
std::uint8_t sum8(const std::string& bytes);

/// The wire bytes of `f`, SOH through ETX. Throws std::invalid_argument naming the offending
/// value: a token that is not two printable characters, a non-printable data byte (and its
/// offset), data longer than 8192 bytes.
std::string encode(const Frame& f);

/// Byte-by-byte frame receiver: feed it every byte from SOH on. Errors are remembered and the
/// frame is judged when ETX arrives, as the protocol answers only then (EOT or NAK).
class FrameDecoder {
public:
    enum class Result { more, good, bad };

    /// `line_error`: the byte arrived with a parity or framing error.
    Result feed(std::uint8_t byte, bool line_error = false);
    void reset();
    bool started() const { return count_ > 0; }
    std::size_t bytes() const { return count_; }
    /// The decoded frame after Result::good.
    const Frame& frame() const { return frame_; }
    /// Why the frame was bad (the first fault found), after Result::bad.
    const std::string& error() const { return error_; }

private:
    std::size_t count_ = 0; // bytes fed, SOH included
    std::string body_;      // T1 .. last byte before ETX
    Frame frame_;
    std::string error_;
    void fault(const std::string& why);
    Result finish();
};

/// Decodes a whole frame (SOH through ETX). Returns "" and fills `out`, or the reason it is bad.
std::string decode(const std::string& bytes, Frame& out);

/// Bytes as text for logs and files: printable ASCII as is, others as \xHH (and \\ for '\').
std::string escape(const std::string& bytes);
/// The inverse, for users' byte strings: \xHH, \n, \r, \t, \0, \\, and names \SOH \STX \ETX
/// \EOT \ENQ \ACK \NAK. Throws std::invalid_argument naming the bad escape and its offset.
std::string unescape(const std::string& text);

} // namespace rcsim::proto
