// rcsim — the application frame of SYSTEM.md §3, as the main CPU sees it after reassembly.
//
//     SOH T1 T2 STX B1 B2 data... C1 C2 ETX
//
// token: two printable characters; BCH: two uppercase hex digits (00 in a command, the status in
// a response); data: printable ASCII 0x20..0x7E, at most 8192 bytes; checksum: two uppercase hex
// digits of the 8-bit sum of every byte from T1 through the last data byte (STX included).
//
// The comm CPU already validated the frame on the serial side; the main CPU checks it again
// because a frame crosses the DP-RAM in chunks and a lost or overwritten byte there must not
// reach the dispatcher.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace rcsim::frame {

constexpr std::uint8_t SOH = 0x01;
constexpr std::uint8_t STX = 0x02;
constexpr std::uint8_t ETX = 0x03;
constexpr std::size_t max_data = 8192;
/// Bytes around the data: SOH T1 T2 STX B1 B2 ... C1 C2 ETX.
constexpr std::size_t overhead = 9;
constexpr std::size_t max_frame = max_data + overhead;

struct Frame {
    std::string token; // two printable characters
    std::uint8_t bch = 0;
    std::string data;
};

inline bool printable(std::uint8_t c) { return c >= 0x20 && c <= 0x7E; }

/// The 8-bit sum of `bytes` (the checksum covers T1 through the last data byte).
std::uint8_t checksum(const std::string& bytes);

/// Builds the wire bytes of a frame. Throws std::invalid_argument naming the offending value for
/// a token that is not two printable characters, a non-printable data byte, or data over 8192.
std::string encode(const Frame& f);

/// Parses `bytes` (SOH through ETX). On success fills `out` and returns ""; otherwise returns one
/// line saying what is wrong and where (and leaves `out` unspecified).
std::string decode(const std::string& bytes, Frame& out);

/// Two uppercase hex digits of v.
std::string hex2(std::uint8_t v);

} // namespace rcsim::frame
