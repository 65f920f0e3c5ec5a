#include "models/plumbing/stop_signal.h"

#include <csignal>
#include <utility>

namespace rcsim {

namespace {

volatile std::sig_atomic_t g_signal = 0;

extern "C" void on_stop_signal(int sig) { g_signal = sig; }

// Often enough that a stop feels immediate, rarely enough to cost nothing: a second of simulated
// time is a thousand polls next to millions of CPU cycles.
const sc_core::sc_time kPollPeriod(1, sc_core::SC_MS);

} // namespace

void install_stop_handlers() {
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART; // a host's blocking socket or file call resumes; the poll does the rest
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

int stop_signal() { return g_signal; }

StopPoller::StopPoller(sc_core::sc_module_name name, std::function<void()> each_poll)
    : sc_module(name), each_poll_(std::move(each_poll)) {
    SC_HAS_PROCESS(StopPoller);
    SC_METHOD(poll);
}

void StopPoller::poll() {
    if (each_poll_) each_poll_();
    if (g_signal != 0) sc_core::sc_pause();
    // Re-arm only while something else will happen: a run that ends when its events run out
    // (sc_start() without a time, the motion scenarios) must not be kept alive by this poll.
    if (sc_core::sc_pending_activity()) next_trigger(kPollPeriod);
}

} // namespace rcsim
