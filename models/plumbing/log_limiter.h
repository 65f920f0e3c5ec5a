// rcsim — a log that a flood cannot flood: at most N lines per window of wall time, the rest
// counted in one summary line when the window is over. Used by the gdb stub's connection lines and
// the Modbus bridge's write lines (docs/tools.md "gdb", docs/monitor.md "Limits").
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <utility>

namespace rcsim {

class LogLimiter {
public:
    using Clock = std::chrono::steady_clock;
    /// `summary(n)`: the line that says n lines were left out of a window.
    LogLimiter(std::ostream& out, unsigned lines, Clock::duration window,
               std::function<std::string(std::uint64_t)> summary)
        : out_(out), max_lines_(lines), window_(window), summary_(std::move(summary)) {}

    /// Writes `text` as a line, or counts it when this window has had its lines.
    void line(const std::string& text) {
        const Clock::time_point now = Clock::now();
        if (now - start_ >= window_) {
            flush(true);
            start_ = now;
            shown_ = 0;
        }
        if (shown_ < max_lines_) {
            out_ << text << std::endl;
            ++shown_;
        } else {
            ++left_out_;
        }
    }

    /// The summary of the lines left out, once their window is over (or now, `at_end`).
    void flush(bool at_end = false) {
        if (left_out_ == 0) return;
        if (!at_end && Clock::now() - start_ < window_) return;
        out_ << summary_(left_out_) << std::endl;
        left_out_ = 0;
    }

private:
    std::ostream& out_;
    unsigned max_lines_;
    Clock::duration window_;
    std::function<std::string(std::uint64_t)> summary_;
    Clock::time_point start_;
    unsigned shown_ = 0;         // lines written in this window
    std::uint64_t left_out_ = 0; // and not written
};

} // namespace rcsim
