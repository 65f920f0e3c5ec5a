#include "models/plumbing/progress_line.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace rcsim {

bool ProgressLine::interactive_default() {
    const char* ci = std::getenv("CI");
    return isatty(STDERR_FILENO) && !(ci && *ci);
}

void ProgressLine::show(const std::string& text) {
    if (!interactive_) return;
    std::fprintf(stderr, "\r\033[K%s", text.c_str());
    std::fflush(stderr);
}

void ProgressLine::clear() {
    if (interactive_) std::fprintf(stderr, "\r\033[K");
}

std::string minutes_seconds(double seconds) {
    const long s = seconds > 0 ? static_cast<long>(seconds + 0.5) : 0;
    char text[32];
    std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
    return text;
}

} // namespace rcsim
