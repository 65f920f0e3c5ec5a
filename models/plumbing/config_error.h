// rcsim — one error type for bad input (scenario files, ROM images, CLI values), carrying the
// file and line so every message names where the offending value is.
#pragma once

#include <stdexcept>
#include <string>

namespace rcsim {

class ConfigError : public std::runtime_error {
public:
    explicit ConfigError(const std::string& what) : std::runtime_error(what) {}
    /// "file:line: message" (line is 1-based; 0 = no line).
    ConfigError(const std::string& file, int line, const std::string& message)
        : std::runtime_error(line > 0 ? file + ":" + std::to_string(line) + ": " + message
                                      : file + ": " + message) {}
};

} // namespace rcsim
