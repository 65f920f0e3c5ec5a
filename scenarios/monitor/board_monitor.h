// rcsim — the remote monitor's simulation side (docs/monitor.md): runs the board's simulated time
// in slices and, between two slices, serves the clients of a MonitorServer: takes their requests
// (pause, resume, step, real-time factor, frames, motion commands, line faults), answers them, and
// sends each subscriber the state when its period (simulated or wall time) is due.
//
// Everything here runs on the simulation thread, outside any SystemC process: the board is only
// read and changed while sc_start() is not running. Pausing simply calls no sc_start(), so
// simulated time stands still for the whole board; resuming rebases the real-time pacer.
#pragma once

#include "scenarios/config/monitor_section.h"
#include "scenarios/world/world.h"
#include "scenarios/monitor/monitor_server.h"
#include "scenarios/verdict/judge.h"

#include <systemc>
#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace rcsim::monitor {

class Args; // a request's arguments and its refusal (board_monitor.cpp)

/// A frame's data for JSON: printable ASCII kept, anything else as \xHH, cut after 64 characters.
std::string printable_frame_data(const std::string& s);

class BoardMonitor {
public:
    /// Starts the server (none with `http` false: a run that only serves Modbus TCP drives its
    /// slices through the monitor too) and hooks the world's callbacks. Call before the first
    /// sc_start(). A world without a real-time pacer gets one, unpaced, for set_rtf.
    BoardMonitor(World& world, const MonitorOptions& opt, std::ostream& log, bool http = true);

    /// "" without the HTTP server.
    std::string url() const { return server_ ? server_->url() : std::string(); }

    /// Called between two slices, after the monitor's own clients were served: another endpoint
    /// (scenarios/modbus) takes its requests here, on the simulation thread.
    void between_slices(std::function<void()> serve) { between_slices_ = std::move(serve); }

    // ---- control, for the requests of any endpoint (simulation thread, between slices) ----
    World& world() { return world_; }
    bool paused() const { return paused_; }
    /// True when the run was not paused (resume: was paused). `announce`: logs it as "monitor:";
    /// another endpoint logs in its own words (scenarios/modbus) and passes false.
    bool pause(bool announce = true);
    bool resume(bool announce = true);
    /// What a step did: where it stopped, and whether the run's end cut it short.
    struct StepResult {
        sc_core::sc_time at;
        bool at_end = false;
    };
    /// Runs `t` of simulated time, unpaced, and leaves the run paused; never past the run's end
    /// (the scenario's duration_s, at most the one-hour cap): a step asked to go further stops
    /// there and says so on the log as `who` (once), and run_until() then ends the run. Between
    /// its slices no request is taken (one could step again) but what clients read is refreshed
    /// (snapshot, wall-time updates, while_stepping()).
    StepResult step(const sc_core::sc_time& t, const char* who = "monitor");
    /// Called between two slices of a step, in place of between_slices(): the endpoint refreshes
    /// what its clients read, and takes no request.
    void while_stepping(std::function<void()> refresh) { while_stepping_ = std::move(refresh); }
    /// A motion command as the main CPU's token dispatcher executes it (the "motion" op).
    Outcome motion(const std::string& token, const std::string& data);
    /// The measured real-time factor (0 while paused) and the pacer's target (0 = unpaced).
    double rtf() const { return rtf_measured_; }
    double rtf_target() const { return rtf_target_; }

    /// Runs simulated time up to `end` (at most the one-hour cap), serving the clients, until
    /// `end` is reached (by running or by a step), a stop signal came, or a host ended the
    /// session (sc_pause from a tcp or replay host; true).
    bool run_until(const sc_core::sc_time& end);

    /// The state as the API's "snapshot" (docs/monitor.md "Snapshot").
    nlohmann::json snapshot();
    /// The verdict and its figures so far (scenarios/verdict/judge.h, Moment::so_far): what the
    /// page, the JSON API and the Modbus registers show. Judged again only when simulated time
    /// moved since the last call.
    const Judgement& judgement();

private:
    using Clock = std::chrono::steady_clock;
    struct Subscription {
        bool sim_clock = false;        // period in simulated time, else wall time
        sc_core::sc_time sim_period, next_sim;
        Clock::duration wall_period{};
        Clock::time_point next_wall;
        std::size_t path_sent = 0;     // trajectory samples already sent to this client
    };
    struct LastFrame {
        bool seen = false;
        double t_s = 0;
        std::string token, data;
        unsigned bch = 0;
    };

    World& world_;
    std::unique_ptr<MonitorServer> server_; // none without http
    std::function<void()> between_slices_, while_stepping_;
    std::ostream& log_;
    std::vector<ScriptedCommand> commands_;
    std::size_t next_command_ = 0;
    std::map<std::uint64_t, Subscription> subs_;
    bool paused_ = false;
    double rtf_target_ = 0; // 0 = as fast as the host goes
    // The run's end (run_until's, capped) and what sets it, in the words of the step's log line.
    sc_core::sc_time end_;
    std::string end_reason_;
    bool end_announced_ = false;  // the step cut at the end is logged once
    bool host_ended_ = false;     // sc_pause: a tcp or replay host ended the session
    sc_core::sc_time slice_{1, sc_core::SC_MS}; // adapted: one slice takes 2..8 ms of wall time

    // What the hooks collect.
    std::array<LastFrame, World::kPorts> last_rx_, last_tx_;
    std::array<std::uint64_t, 8> irq_count_{};
    // Rates: counts and times at the start of the current window.
    std::array<std::uint64_t, 8> irq_base_{};
    sc_core::sc_time rate_base_sim_;
    std::array<double, 8> irq_rate_hz_{};
    // Measured real-time factor over the last half second of running wall time.
    Clock::time_point rtf_base_wall_;
    sc_core::sc_time rtf_base_sim_;
    double rtf_measured_ = 0;
    Clock::time_point wall0_, last_publish_;

    void hook_bench();
    void serve();
    bool advance(const sc_core::sc_time& most);
    void handle(std::uint64_t client, const nlohmann::json& m);
    nlohmann::json execute(std::uint64_t client, const std::string& op, Args& a);
    void run_due_commands();
    void send_updates();
    void update_rates();
    std::string path_json(Subscription& s, std::size_t max_points);
    nlohmann::json motion_json();
    nlohmann::json ports_json();
    std::optional<Judgement> judged_;
    sc_core::sc_time judged_at_;
    std::uint64_t judged_delta_ = 0;
    nlohmann::json interrupts_json(std::optional<double> budget_us);
    nlohmann::json interrupt_figures(std::optional<double> budget_us);
    nlohmann::json irq_cache_;                 // interrupt_figures() as of irq_cache_completed_ interrupts
    std::uint64_t irq_cache_completed_ = 0;
    std::optional<double> irq_cache_budget_;
    void reply(std::uint64_t client, nlohmann::json msg);
};

} // namespace rcsim::monitor
