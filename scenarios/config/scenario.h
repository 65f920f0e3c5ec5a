// rcsim — a scenario file: what to simulate, for how long, with which hosts on which ports.
// The schema is documented in docs/scenarios.md; every error names the file and line.
#pragma once

#include "scenarios/board/controller.h"
#include "scenarios/host/protocol_host.h"
#include "scenarios/host/pty_host.h"
#include "scenarios/host/raw_host.h"
#include "scenarios/host/replay_host.h"
#include "scenarios/host/tcp_host.h"
#include "scenarios/config/monitor_section.h"
#include "scenarios/config/search_section.h"
#include "scenarios/config/motion_plan.h"
#include "scenarios/config/trajectory_options.h"
#include "main_cpu/motion/motion_controller.h"
#include "models/rom_image.h"

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace rcsim {

/// One fault the line applies to a character a side sends (FaultKind), or a BREAK.
struct LineFault {
    enum class From { host, controller } from = From::host;
    std::string kind;            // flip_data_bit, flip_cell, drop, corrupt_stop, break
    std::uint64_t index = 0;     // character number from that side (0-based)
    unsigned bit = 0;
    sc_core::sc_time at;         // break: when
    sc_core::sc_time duration;   // break: how long
};

struct PortScenario {
    enum class Host { none, protocol, raw, tcp, replay, pty } host = Host::none;
    ProtocolHostConfig protocol;
    RawHostConfig raw;
    TcpHostConfig tcp;       // host: tcp (docs/serial.md "Connecting your own tools")
    ReplayHostConfig replay; // host: replay (a session log recorded by a tcp host)
    PtyHostConfig pty;       // host: pty (docs/serial.md "A pty as the serial port")
    /// The host's line format (a replay host without `format:` uses the 9600,8E1 default here).
    SerialFormat format() const;
    std::string log_path; // protocol host: transaction log ("" = none)
    double noise_per_bit = 0;
    std::vector<LineFault> faults;
};

/// Limits of the pass/fail checks (docs/scenarios.md "Checks").
struct CheckLimits {
    std::uint64_t max_overruns = 0;
    std::uint64_t max_frames_failed = 0;
    std::uint64_t max_frame_mismatches = 0;  // host-delivered vs main-CPU-received frames
    std::uint64_t max_bus_errors = 0;        // 8086 cycles nothing answered (unmapped, ROM write, TLM error)
    double max_char_latency_us = -1;         // stop bit -> RXD read; < 0: per port, its RX FIFO's
                                             // depth in that port's character times
    double min_margin_us = 0;                // Table 3: budget - (RS-232 ISR mean + DP-RAM byte)
    double min_worst_margin_us = 0;          // the paper's rule: budget - (longest RS-232 ISR + DP-RAM byte)
    std::optional<std::uint64_t> min_frames_delivered; // all ports; unset: one per port whose host
                                                       // generates commands
    std::set<std::string> off;               // checks switched off by name (`NAME: off`)
    std::set<std::string> on;                // optional checks switched on by name (`NAME: on`)
    bool expect_motion_ok = true;
    // With main_cpu.motion (docs/scenarios.md "Motion over the serial protocol"):
    struct Circle {
        double center_x = 0, center_y = 0, radius = 0, max_radial_error = 1, max_end_error = 0;
    };
    std::optional<Circle> circle;             // the path of the last MC token must lie on it
    std::string motion_final_state;           // "" = no check
    std::optional<double> max_cycle_jitter_us; // control-cycle start jitter; no check if unset
    std::optional<double> max_command_latency_us; // host ETX -> first pulse; no check if unset
    std::uint64_t max_csp_missed_sync = 0;        // with main_cpu.csp: SYNCs whose set-point came late
};

struct Scenario {
    std::string file;
    std::string name;
    double duration_s = 1.0; // 0 (tcp/replay hosts only): until the client disconnects / the log ends
    double realtime = -1;    // pace simulated to wall time x this; < 0: 1.0 with a tcp or pty host, else off
    double drain_s = 1.0; // after duration_s: no new commands; what is in flight completes
    std::uint64_t seed = 1; // set_seed(): the hosts' and the lines' random streams derive from it
    RomSource rom; // file "" = the built firmware; `rom: {even, odd}`: an EPROM pair
    ControllerConfig board;
    double budget_us = -1; // < 0: the mean character arrival period of the active ports, from the
                           // format each port's 82510 is programmed with (docs/scenarios.md)
    std::vector<PortScenario> ports{3};
    CheckLimits checks;
    YAML::Node root;  // the whole document, for the motion section
    bool has_motion = false;   // a `motion:` section: a motion-only run (docs/motion.md)
    bool main_motion = false;  // main_cpu.motion: the motion layer in the main board's slot
    /// main_cpu.csp: a cyclic-position circle on axes 2/3 (docs/motion.md "Cyclic position").
    struct Csp {
        double radius = 2000, velocity = 10000, start_ms = 100, sync_offset_us = 250;
    };
    std::optional<Csp> csp;
    TrajectoryOptions trajectory; // main_cpu.trajectory: what the trajectory files hold
    /// main_cpu.program: a Structured Text program the main CPU runs once per control cycle
    /// (docs/st.md); RN, SP and ST over the serial protocol start, stop and report it. Compiled
    /// when the scenario is read, so that an error in it is bad input.
    struct Program {
        std::string path, text;
        std::uint64_t budget = 100000; // main_cpu.statement_budget
    };
    std::optional<Program> program;
    /// The `motion:` section (a motion-only run, has_motion), read with the rest of the file.
    std::optional<MotionPlan> motion;
    /// The `monitor:` section (docs/monitor.md); none without one.
    std::optional<monitor::MonitorOptions> monitor;
    /// The `search:` section (docs/search.md): what `rcsim search` varies; a run ignores it.
    std::optional<SearchSection> search;

    /// The files a run of this scenario writes besides its reports: host logs, records, port
    /// files. Relative as the file names them until place_outputs().
    std::vector<std::string*> output_files();
    /// Every relative output file goes under `out_dir` (the run's --out folder); an absolute path
    /// is honoured. Call once, before the world is built.
    void place_outputs(const std::filesystem::path& out_dir);

    /// Sets the run's seed and every seed derived from it (a --seed given on the command line
    /// goes through here too, so that no derived seed keeps the file's).
    void set_seed(std::uint64_t run_seed);
    /// The seed of port p's protocol host traffic, and of its line's noise: distinct streams per
    /// port, each a fixed function of the run's seed.
    std::uint64_t traffic_seed(unsigned p) const { return seed * 1000 + p; }
    std::uint64_t noise_seed(unsigned p) const { return seed * 7919 + p; }
};

/// The motion layer as the main CPU hosts it: CAMC-QI accesses on the main CPU's bus clock with
/// its access cycles, main_cpu.fb_call_us per block call, first pulses polled every 1 us.
motion::MotionConfig motion_config(const Scenario& s);

/// Reads and validates a scenario file. Throws ConfigError naming file and line.
Scenario load_scenario(const std::string& path);

} // namespace rcsim
