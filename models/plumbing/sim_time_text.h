// rcsim — a simulated time as the summaries print it: seconds, the decimals in groups of three
// (milliseconds, microseconds, nanoseconds), "1.466 138 750 s", so that a person reads the
// second, the millisecond and the microsecond at a glance (issue #51 item 3). Trailing groups
// that are all zeros are left out ("2.000 s", "0.000 382 s"); the millisecond group always shows.
//
// Plain C++ and header-only: every floor may use it.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

namespace rcsim {

/// `seconds` rounded to the nanosecond (the 8086's clock is 125 ns): sim_time_text(1.46613875)
/// == "1.466 138 750 s", sim_time_text(2) == "2.000 s", sim_time_text(0.000382) == "0.000 382 s".
/// Not a number or an infinity prints as "-" (a figure that was not measured).
inline std::string sim_time_text(double seconds) {
    if (!std::isfinite(seconds)) return "-";
    if (std::fabs(seconds) >= 1e9) { // past any run (one hour at most): no room for nanoseconds in 64 bits
        char text[64];
        std::snprintf(text, sizeof text, "%.3f s", seconds);
        return text;
    }
    const bool negative = seconds < 0;
    const auto ns = static_cast<std::uint64_t>(std::llround(std::fabs(seconds) * 1e9));
    const unsigned groups[3] = {static_cast<unsigned>(ns / 1000000 % 1000), static_cast<unsigned>(ns / 1000 % 1000),
                                static_cast<unsigned>(ns % 1000)};
    const unsigned shown = groups[2] != 0 ? 3 : groups[1] != 0 ? 2 : 1;
    std::string out = (negative && ns != 0 ? "-" : "") + std::to_string(ns / 1000000000) + ".";
    for (unsigned g = 0; g < shown; ++g) {
        char digits[4];
        std::snprintf(digits, sizeof digits, "%03u", groups[g]);
        out += (g > 0 ? " " : "") + std::string(digits);
    }
    return out + " s";
}

/// The same from microseconds, the unit report.json keeps its instants in (`time_us`, `ir_rise_us`).
inline std::string sim_time_text_us(double us) { return sim_time_text(us / 1e6); }

} // namespace rcsim
