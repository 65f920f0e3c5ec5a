#include "scenarios/run/run_progress.h"

#include <systemc>

#include <cstdio>

namespace rcsim {

namespace {
// Often enough to see it move, rarely enough that a terminal does not scroll through redraws.
constexpr std::chrono::milliseconds kRedrawPeriod(250);
} // namespace

void RunProgress::poll() {
    const Clock::time_point now = Clock::now();
    if (!start_) {
        start_ = now;
        shown_ = now;
        return;
    }
    if (now - shown_ < kRedrawPeriod) return;
    shown_ = now;
    const double sim_s = sc_core::sc_time_stamp().to_seconds();
    const double wall_s = std::chrono::duration<double>(now - *start_).count();
    const double rtf = wall_s > 0 ? sim_s / wall_s : 0;
    char text[128];
    if (total_s_ > 0) {
        const double left_s = rtf > 0 && total_s_ > sim_s ? (total_s_ - sim_s) / rtf : 0;
        std::snprintf(text, sizeof text, "run %.1f/%.1f s  RTF %.2f  ETA %s", sim_s, total_s_, rtf,
                      minutes_seconds(left_s).c_str());
    } else {
        std::snprintf(text, sizeof text, "run %.1f s  RTF %.2f", sim_s, rtf);
    }
    line_.show(text);
    showing_ = true;
}

void RunProgress::finish() {
    if (showing_) line_.clear();
    showing_ = false;
}

} // namespace rcsim
