// rcsim — the simulated world of one communication run: the controller, three serial lines, the
// host attached to each, and the probes that watch them (docs/scenarios.md "How each figure is
// measured"). It assembles the world and feeds the online figures as the probes report (the
// interrupt records, the DP-RAM time per byte, the characters' latency: nothing here grows with
// the length of the run); verdict/measure.h reads the figures, verdict/checks.h judges them.
#pragma once

#include "scenarios/board/controller.h"
#include "scenarios/board/dpram_byte_time.h"
#include "scenarios/board/interrupt_probe.h"
#include "scenarios/board/line_observer.h"
#include "scenarios/config/scenario.h"
#include "scenarios/host/protocol_host.h"
#include "scenarios/host/pty_host.h"
#include "scenarios/host/raw_host.h"
#include "scenarios/host/replay_host.h"
#include "scenarios/host/tcp_host.h"
#include "main_cpu/motion/motion_controller.h"
#include "main_cpu/st/program.h"
#include "models/plumbing/output_file.h"
#include "models/serial_line.h"
#include "models/stats.h"

#include <systemc>

#include <array>
#include <deque>
#include <memory>
#include <optional>
#include <vector>

namespace rcsim {

class World : public sc_core::sc_module {
public:
    static constexpr unsigned kPorts = CommBoard::kPorts;

    Controller ctl;
    sc_core::sc_vector<SerialLine> lines;
    std::array<std::unique_ptr<ProtocolHost>, kPorts> protocol;
    std::array<std::unique_ptr<RawHost>, kPorts> raw;
    std::array<std::unique_ptr<TcpHost>, kPorts> tcp;
    std::array<std::unique_ptr<ReplayHost>, kPorts> replay;
    std::array<std::unique_ptr<PtyHost>, kPorts> pty;
    std::unique_ptr<RealtimePacer> pacer; // with a tcp or pty host, or `realtime:` set
    InterruptProbe probe;
    std::array<Samples, kPorts> char_latency_us; // stop bit -> RXD read
    /// The longest wait of each port's characters in the RX FIFO (the first of them), with its
    /// stop bit and its read: what a failed char-latency check names.
    struct CharWait {
        double wait_us = 0;
        sc_core::sc_time stop, read;
    };
    std::array<CharWait, kPorts> char_latency_worst{};
    /// The independent observer of each line, fed by the line's receivers and the main CPU's
    /// DP-RAM side (line_observer.h).
    std::array<LineObserver, kPorts> observers;
    std::unique_ptr<motion::MotionController> motion;
    /// main_cpu.program: the Structured Text program the main CPU runs (docs/st.md).
    std::unique_ptr<st::StProgram> program;

    SC_HAS_PROCESS(World);
    World(sc_core::sc_module_name name, const Scenario& s);

    /// The name of the host kind on port p ("protocol", "raw", "tcp", "replay", "pty", "none").
    const char* host_kind(unsigned p) const;
    const Scenario& scenario() const { return scenario_; }

    /// The drain phase: the hosts start no new command; the run goes on in 10 ms steps until
    /// nothing is in flight — every host idle (its last command answered), every response the
    /// main CPU owes handed and finished by the comm CPU — or `drain_s` has passed, so that frames
    /// in flight at the end are not counted as lost.
    void drain(double drain_s);
    /// sc_start(d), its end an event the comm CPU's slices stop at (Cpu8086::end_slices_at): every
    /// run of the world's kernel goes through here, so the report does not depend on the syncs.
    void start_for(const sc_core::sc_time& d) {
        ctl.comm.cpu.end_slices_at(sc_core::sc_time_stamp() + d);
        sc_core::sc_start(d);
    }
    /// Hands the observers what the main CPU received and sent since the last call, then closes
    /// their comparisons. Call once, after the run.
    void finish_observers();

    /// A BREAK on port p's line from `from` for `duration`, starting now, that the scenario makes
    /// (its `faults:`, the monitor's inject_fault): the observer takes it as a cause (docs/scenarios.md
    /// "Expected drops").
    void inject_break(unsigned p, SerialLine::Side from, const sc_core::sc_time& duration);

    /// After the run: ends the hosts' logs and record files and throws ConfigError naming the
    /// first that could not be written completely (a full disk), so a truncated file never
    /// passes as a complete one.
    void finish_files();

    /// The end of the run: the records the probe still holds, the open DP-RAM chunks and the
    /// timeline windows become final. Call once, before reading the figures.
    void finish();

    /// RS-232 interrupts that took a character out of the RX FIFO (the `rs232_rx` set).
    const Samples& rs232_rx_service_us() const { return rx_service_; }
    const Samples& rs232_rx_latency_us() const { return rx_latency_; }
    /// The longest of those (the first of equals): the worst case of Table 3. Valid when
    /// rs232_rx_service_us() has samples.
    const InterruptRecord& rs232_rx_longest() const { return rx_longest_; }
    /// Their longest latencies with their causes.
    const WorstLatencies& rs232_rx_worst() const { return rx_worst_; }
    const DpramByteTime& dpram_time() const { return dpram_; }

    /// Hands every completed interrupt record to `sink` as well (the report's interrupt log);
    /// nullptr: none. Set before the simulation starts.
    void set_interrupt_sink(InterruptSink* sink) { sink_ = sink; }

private:
    const Scenario& scenario_;
    std::array<std::optional<OutputFile>, kPorts> logs_; // models/plumbing/output_file.h
    // RXD reads of each port since the probe last settled: enough to tell whether an interrupt
    // read a character, since its handler ran after that (see on_record).
    std::array<std::deque<sc_core::sc_time>, kPorts> recent_reads_;
    Samples rx_service_, rx_latency_;
    InterruptRecord rx_longest_;
    WorstLatencies rx_worst_;
    DpramByteTime dpram_;
    InterruptSink* sink_ = nullptr;

    void attach_host(unsigned p, const PortScenario& ps);
    void load_program(const Scenario::Program& p);
    void inject_breaks();
    void watch_dpram(const i8086::BusRecord& r, const sc_core::sc_time& t);

    // Port resets the main CPU asked for that the observers have been told of.
    std::array<std::uint64_t, kPorts> main_resets_seen_{};
    // Each line's counters (per side) when the observers were last told of its faults.
    std::array<std::array<SerialLine::Stats, 2>, kPorts> line_stats_seen_{};
    void observe_line(unsigned p, const SerialLine::Delivered& d);
    void sync_main_side();
    void sync_line_faults();
    /// `sent`: the character being put on the line now, when called for it (the one a fault hit).
    void sync_line_faults(unsigned p, const SerialLine::Traced* sent = nullptr);
    void on_record(const InterruptRecord& r);
    void on_settled(const sc_core::sc_time& horizon);
};

} // namespace rcsim
