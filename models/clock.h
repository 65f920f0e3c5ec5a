// rcsim — clock and time helpers.
//
// Integer cycle accounting for a configurable clock, with precomputed sc_time constants:
// building an sc_time from a double is slow and its rounding drifts (docs/architecture.md "Time model").
// The kernel resolution is SystemC's default 1 ps, so 8 MHz (125 ns) and 18.432 MHz
// derived character times stay integral or are rounded in exactly one documented place.
#pragma once

#include <systemc>

#include <array>
#include <cstdint>

namespace rcsim {

using cycles_t = std::uint64_t;

/// Picoseconds as an sc_time, without going through double.
inline sc_core::sc_time ps(std::uint64_t value) { return sc_core::sc_time::from_value(value); }
/// Nanoseconds, microseconds and milliseconds as an sc_time, without going through double.
inline sc_core::sc_time ns(std::uint64_t value) { return ps(value * 1000); }
inline sc_core::sc_time us(std::uint64_t value) { return ps(value * 1000000); }
inline sc_core::sc_time ms(std::uint64_t value) { return ps(value * 1000000000); }
/// sc_time to integer picoseconds (the kernel's resolution).
inline std::uint64_t to_ps(const sc_core::sc_time& t) { return t.value(); }
/// sc_time to microseconds as a double, for reports only.
inline double to_us(const sc_core::sc_time& t) { return static_cast<double>(t.value()) / 1e6; }

/// A clock of a fixed frequency. Converts between cycle counts and sc_time exactly when the
/// period is an integral number of picoseconds (8 MHz: 125000 ps), otherwise rounds the period
/// to the nearest picosecond (documented by `exact()`).
class Clock {
public:
    explicit Clock(std::uint64_t hz = 8'000'000);

    std::uint64_t hz() const { return hz_; }
    std::uint64_t period_ps() const { return period_ps_; }
    sc_core::sc_time period() const { return table_[1]; }
    /// True when the period is an exact number of picoseconds.
    bool exact() const { return 1'000'000'000'000ULL % hz_ == 0; }

    /// n cycles as sc_time; a table lookup for the small counts of one instruction or bus cycle.
    sc_core::sc_time cycles(cycles_t n) const {
        return n < table_.size() ? table_[n] : ps(n * period_ps_);
    }
    /// Whole cycles elapsed in t (floor).
    cycles_t to_cycles(const sc_core::sc_time& t) const { return t.value() / period_ps_; }
    /// Cycles needed to cover t (ceiling): the number of clock edges a wait must span.
    cycles_t to_cycles_ceil(const sc_core::sc_time& t) const {
        return (t.value() + period_ps_ - 1) / period_ps_;
    }

private:
    std::uint64_t hz_;
    std::uint64_t period_ps_;
    std::array<sc_core::sc_time, 512> table_;
};

} // namespace rcsim
