// rcsim — one status line on stderr rewritten in place, for a human watching a terminal: the
// sweep's progress (scenarios/sweep/process_pool.h) and a run's (scenarios/run/run_progress.h).
//
// Nothing at all goes out when stderr is not a terminal or CI is set: logs and CI output get no
// carriage returns, and no file a run or a sweep writes ever depends on it.
#pragma once

#include <string>

namespace rcsim {

class ProgressLine {
public:
    explicit ProgressLine(bool interactive) : interactive_(interactive) {}
    /// stderr is a terminal and CI is unset.
    static bool interactive_default();
    bool interactive() const { return interactive_; }
    /// Replaces the line with `text` ("\r", erase to the end of the line, no newline).
    void show(const std::string& text);
    /// Erases the line: before a line that must stay, or at the end.
    void clear();

private:
    bool interactive_;
};

/// A duration as M:SS (an ETA): 31.4 -> "0:31", 3725 -> "62:05".
std::string minutes_seconds(double seconds);

} // namespace rcsim
