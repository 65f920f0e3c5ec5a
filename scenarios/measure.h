// rcsim — the figures of a communication run, from what the bench's probes saw (docs/scenarios.md
// "How each figure is measured"). The figures that need more than a count are gathered online
// while the run goes (DpramByteTime here, the sample sets of models/stats.h), in memory that does
// not grow with the run; the functions below read them from the finished bench and change nothing.
#pragma once

#include "scenarios/line_observer.h"
#include "models/dpram_layout.h"
#include "models/frame_codec.h"
#include "models/stats.h"

#include <systemc>

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <utility>
#include <vector>

namespace rcsim {

class Bench;
class MainCpu;
class ProtocolHost;
struct Scenario;

/// The firmware's DP-RAM time per byte (the paper's "DP-RAM (1 byte)"), gathered online. A chunk
/// is the data bytes the comm CPU writes into data[p], closed by its 0x1p mailbox word; its time
/// is the span of its data writes (T1 of the first to T1 of the last, so that waiting for the
/// mailbox is not processing) less every interrupt handler of depth 0 that ran inside the span
/// (nested handlers lie inside those). Per byte = the sum over chunks of two or more writes of
/// that time, over the sum of their gaps (writes - 1).
///
/// Online, an interrupt's share of a chunk is added when the interrupt completes, in completion
/// order, and a chunk is summed once no interrupt can reach into it any more, in the order the
/// chunks began: the same terms added in the same order as over the whole run's lists, so the
/// figure is the same to the last bit. Memory: the chunks not summed yet, those begun since the
/// oldest open one (a chunk is written in milliseconds). A chunk that gets no mailbox word (the
/// port was reset while it was copied) would hold all later ones back; once kMaxPending chunks
/// wait behind it, it is taken as ended at its last write.
class DpramByteTime {
public:
    static constexpr unsigned kPorts = dpram_layout::ports;
    static constexpr std::size_t kMaxPending = 1024;

    /// A data write into data[port] (T1 `t`, `width` bytes).
    void data_write(unsigned port, const sc_core::sc_time& t, unsigned width);
    /// The 0x1p mailbox word for `port`: its chunk is complete.
    void chunk_closed(unsigned port);
    /// An interrupt of depth 0 completed: [inta1, iret_done] was spent in handlers.
    void interrupt(const sc_core::sc_time& inta1, const sc_core::sc_time& iret_done);
    /// No interrupt is in progress: the chunks closed so far can take no more interrupt time.
    void settle();
    /// The end of the run: every chunk, open or closed, is final.
    void finish();

    /// Time per byte; none without a chunk of two or more writes.
    std::optional<double> per_byte_us() const;
    std::uint64_t bytes() const { return bytes_; }
    std::size_t chunks_pending() const { return chunks_.size(); }

private:
    struct Chunk {
        unsigned port = 0;
        sc_core::sc_time first, last; // T1 of the first and of the last data write
        std::uint64_t writes = 0, bytes = 0;
        bool closed = false;
        // Handler time inside the span, summed in completion order. An interrupt that completes
        // while the chunk is open lies inside it up to its IRET if another write follows, and
        // only up to the last write if none does: both sums are carried until a write or the
        // mailbox word tells which one it is.
        double isr_us = 0;      // the span ends at `last`
        double isr_more_us = 0; // another write follows
    };
    std::deque<Chunk> chunks_; // not summed yet, in the order they began
    std::array<Chunk*, kPorts> open_{};
    double time_us_ = 0;
    std::uint64_t gaps_ = 0, bytes_ = 0;

    void sum_front();
};

// The paper's Table 3 (HP 8086 emulator measurements).
constexpr double kPaperRs232IsrUs = 82.0;
constexpr double kPaperDpramByteUs = 52.553;

/// What the interrupt probe and the DP-RAM watch measured.
struct InterruptFigures {
    nlohmann::json interrupts = nlohmann::json::object(); // report.json "interrupts"
    Samples rs232_rx_service, rs232_rx_latency;
    std::optional<double> dpram_byte_us; // none: no chunk of two or more writes
    std::uint64_t dpram_bytes = 0;
};

/// Of the finished bench (Bench::finish()).
InterruptFigures measure_interrupts(const Bench& b);

/// One character time (START through STOP) of port p as its 82510 is programmed.
double controller_char_us(const Bench& b, unsigned p);

/// The Table 3 budget: the scenario's `budget_us`, else the mean character arrival period of all
/// active ports together, 1 / sum(1 / t_char_p) (= t_char / 3 for three equal ports), each t_char
/// from the format the port's 82510 is programmed with (docs/system.md §9). A port is active when
/// a host is attached; with none, all three count.
double budget_us(const Bench& b, const Scenario& s);

/// report.json "ports[p]": the host's counters, the 82510's, the main CPU's, and the line
/// observer's (call Bench::finish_observers() first).
nlohmann::json port_json(const Bench& b, unsigned p);

/// report.json "ports[p].line", ".commands", ".responses": what the observer of port p counted.
nlohmann::json observer_json(const LineObserver& o);

nlohmann::json samples_json(const Samples& s);

} // namespace rcsim
