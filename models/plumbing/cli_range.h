// rcsim — a command-line number within a range, checked as CLI11 parses it, so that a bad value
// is bad input (exit 2, naming the option and the value) and never reaches a model as NaN, an
// infinity or a silently truncated fraction. CLI::Range alone lets NaN through: every comparison
// with it is false.
#pragma once

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>

namespace rcsim {

/// A real number in [lo, hi] (finite: "nan", "inf" and "1e999" are refused).
inline CLI::Validator real_in(double lo, double hi) {
    std::ostringstream range;
    range << lo << " .. " << hi;
    const std::string name = range.str();
    return CLI::Validator(
        [lo, hi, name](std::string& text) {
            char* end = nullptr;
            errno = 0;
            const double v = std::strtod(text.c_str(), &end);
            if (end == text.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(v))
                return "'" + text + "' is not a number";
            return v >= lo && v <= hi ? std::string() : "'" + text + "' is not in " + name;
        },
        name);
}

/// A whole number in [lo, hi], written in decimal ("2.7", "0x10", "-1" for an unsigned are refused).
inline CLI::Validator whole_in(long long lo, long long hi) {
    const std::string name = std::to_string(lo) + " .. " + std::to_string(hi);
    return CLI::Validator(
        [lo, hi, name](std::string& text) {
            char* end = nullptr;
            errno = 0;
            const long long v = std::strtoll(text.c_str(), &end, 10);
            if (end == text.c_str() || *end != '\0' || errno == ERANGE) return "'" + text + "' is not a whole number";
            return v >= lo && v <= hi ? std::string() : "'" + text + "' is not in " + name;
        },
        name);
}

} // namespace rcsim
