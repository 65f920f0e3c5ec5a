// A motion loop: a MotionController and a checked thread that runs the test body with 1 ms control
// cycles.
#pragma once

#include "main_cpu/motion/motion_controller.h"
#include "tests/support/sc_test.h"

#include <functional>

namespace rcsim::motion::test {

struct MotionLoop : sc_core::sc_module {
    MotionController mc;
    std::function<void(MotionLoop&)> body;
    MotionLoop(sc_core::sc_module_name n, const MotionConfig& cfg) : sc_module(n), mc("mc", cfg) {
        rcsim::test::spawn_checked([this] { run(); }, "run");
    }
    void run() {
        body(*this);
        sc_core::sc_stop();
    }
    /// n control cycles of 1 ms.
    void cycles(int n) {
        for (int i = 0; i < n; ++i) {
            mc.control_cycle(sc_core::sc_time_stamp());
            wait(sc_core::sc_time(1, sc_core::SC_MS));
        }
    }
    /// Cycles until pred() or the limit; returns the cycles used (-1 on timeout).
    int until(const std::function<bool()>& pred, int limit = 20000) {
        for (int i = 0; i < limit; ++i) {
            if (pred()) return i;
            cycles(1);
        }
        return -1;
    }
    void power_on() {
        mc.command("SV", "1");
        cycles(6);
    }
};

inline void run_motion(const std::function<void(MotionLoop&)>& body, MotionConfig cfg = {}) {
    cfg.drive.following_lag_s = cfg.drive.following_lag_s;
    MotionLoop b("loop", cfg);
    b.body = body;
    sc_core::sc_start();
}

} // namespace rcsim::motion::test
