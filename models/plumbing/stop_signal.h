// rcsim — SIGINT/SIGTERM during a run: stop at the current simulated time, not in the middle of
// writing files.
//
// The signal handler only stores the signal number (the one thing a handler may safely do); a
// SystemC method polls it every simulated millisecond and calls sc_pause(), so sc_start()
// returns at a consistent simulated time. The runner then skips the drain, writes every report
// file with `interrupted: true` and the time reached, and exits 128 + the signal number (130 for
// SIGINT, 143 for SIGTERM), the shell's convention for "ended by a signal".
#pragma once

#include <systemc>

#include <functional>

namespace rcsim {

/// Installs the SIGINT and SIGTERM handlers for the rest of the process.
void install_stop_handlers();

/// The signal that asked the run to stop, 0 when none.
int stop_signal();

/// Pauses the simulation (sc_pause) at the first simulated millisecond boundary after a stop
/// signal. `each_poll`, when given, is called at every poll too: the run's progress line
/// (scenarios/run/run_progress.h). It rides on this process rather than a second periodic one
/// because two would keep each other alive: each re-arms while anything else is pending.
class StopPoller : public sc_core::sc_module {
public:
    explicit StopPoller(sc_core::sc_module_name name, std::function<void()> each_poll = {});

private:
    void poll();
    std::function<void()> each_poll_;
};

} // namespace rcsim
