// The project's line format in time: 9600 bps 8E1 on the 82510 (docs/system.md), derived from
// its definition rather than written out as a number in each test that needs it.
#pragma once

#include "models/clock.h"

#include <cstdint>

namespace rcsim::test {

/// The 82510's crystal, and its clocks per bit at 9600 bps: divisor 60 (BAL) x 32 (the baud
/// generator runs at clock / 2 and the receiver samples 16 times a bit).
constexpr std::uint64_t k_uart_crystal_hz = 18'432'000;
constexpr std::uint64_t k_clocks_per_bit_9600 = 32 * 60;
/// 8E1: START, 8 data bits, even parity, STOP.
constexpr std::uint64_t k_bits_8e1 = 11;
/// One 9600 8E1 character in picoseconds, rounded to the nearest as SerialLine's BitTime::span
/// rounds (1'145'833'333.3 ps).
constexpr std::uint64_t k_char_ps_9600_8e1 =
    (k_bits_8e1 * k_clocks_per_bit_9600 * 1'000'000'000'000 + k_uart_crystal_hz / 2) / k_uart_crystal_hz;
static_assert(k_uart_crystal_hz / k_clocks_per_bit_9600 == 9600, "divisor 60 is 9600 bps exactly");

/// One 9600 8E1 character: the time from a START edge to the end of its STOP bit.
inline sc_core::sc_time char_time_9600_8e1() { return ps(k_char_ps_9600_8e1); }

} // namespace rcsim::test
