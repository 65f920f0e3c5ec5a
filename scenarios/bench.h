// rcsim — the simulated world of one communication run: the controller, three serial lines, the
// host attached to each, and the probes that watch them (docs/scenarios.md "How each figure is
// measured"). Assembling it is all this file does; scenarios/measure.h turns what the probes saw
// into figures, scenarios/checks.h judges them.
#pragma once

#include "scenarios/controller.h"
#include "scenarios/interrupt_probe.h"
#include "scenarios/line_observer.h"
#include "scenarios/scenario.h"
#include "scenarios/host/protocol_host.h"
#include "scenarios/host/raw_host.h"
#include "scenarios/host/replay_host.h"
#include "scenarios/host/tcp_host.h"
#include "main_cpu/motion/motion_controller.h"
#include "models/serial_line.h"
#include "models/stats.h"

#include <systemc>

#include <array>
#include <fstream>
#include <memory>
#include <vector>

namespace rcsim {

/// One chunk the comm CPU wrote into DP-RAM: its data-byte writes, closed by its 0x1p mailbox
/// word. The time per byte is measured over the data writes only (first to last), so waiting for
/// the mailbox to be free is not counted as processing.
struct DpramChunk {
    unsigned port = 0;
    sc_core::sc_time first, last; // T1 of the first and of the last data write
    std::uint64_t writes = 0, bytes = 0;
};

class Bench : public sc_core::sc_module {
public:
    static constexpr unsigned kPorts = CommBoard::kPorts;

    Controller ctl;
    sc_core::sc_vector<SerialLine> lines;
    std::array<std::unique_ptr<ProtocolHost>, kPorts> protocol;
    std::array<std::unique_ptr<RawHost>, kPorts> raw;
    std::array<std::unique_ptr<TcpHost>, kPorts> tcp;
    std::array<std::unique_ptr<ReplayHost>, kPorts> replay;
    std::unique_ptr<RealtimePacer> pacer; // with a tcp host, or `realtime:` set
    InterruptProbe probe;
    std::array<std::vector<sc_core::sc_time>, kPorts> char_reads; // each RXD read of a character
    std::array<Samples, kPorts> char_latency_us;                  // stop bit -> RXD read
    std::vector<DpramChunk> chunks;
    /// The independent observer of each line, fed by the line's receivers and the main CPU's
    /// DP-RAM side (line_observer.h).
    std::array<LineObserver, kPorts> observers;
    std::unique_ptr<motion::MotionController> motion;

    SC_HAS_PROCESS(Bench);
    Bench(sc_core::sc_module_name name, const Scenario& s);

    /// The name of the host kind on port p ("protocol", "raw", "tcp", "replay", "none").
    const char* host_kind(unsigned p) const;
    const Scenario& scenario() const { return scenario_; }

    /// The drain phase: the hosts start no new command; the run goes on in 10 ms steps until
    /// nothing is in flight — every host idle (its last command answered), every response the
    /// main CPU owes handed and finished by the comm CPU — or `drain_s` has passed, so that frames
    /// in flight at the end are not counted as lost.
    void drain(double drain_s);
    /// Hands the observers what the main CPU received and sent since the last call, then closes
    /// their comparisons. Call once, after the run.
    void finish_observers();

    /// After the run: ends the hosts' logs and record files and throws ConfigError naming the
    /// first that could not be written completely (a full disk), so a truncated file never
    /// passes as a complete one.
    void finish_files();

private:
    const Scenario& scenario_;
    std::array<int, kPorts> open_chunk_{-1, -1, -1};
    std::array<std::ofstream, kPorts> logs_;

    void attach_host(unsigned p, const PortScenario& ps);
    void inject_breaks();
    void watch_dpram(const i8086::BusRecord& r, const sc_core::sc_time& t);

    // The main CPU's side for the observers, read incrementally: frames past these cursors and
    // port resets it asked for since the last look are new.
    std::size_t main_received_seen_ = 0, main_sent_seen_ = 0;
    std::array<std::uint64_t, kPorts> main_resets_seen_{};
    void observe_line(unsigned p, const SerialLine::Delivered& d);
    void sync_main_side();
};

} // namespace rcsim
