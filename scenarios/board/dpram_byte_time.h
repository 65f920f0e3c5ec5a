// rcsim — the firmware's DP-RAM time per byte (the paper's Table 3 "DP-RAM (1 byte)"), gathered
// online from the 8086's bus cycles while the run goes, in memory that does not grow with the run
// (docs/scenarios.md "How each figure is measured").
#pragma once

#include "models/dpram_layout.h"

#include <systemc>

#include <array>
#include <cstdint>
#include <deque>
#include <optional>

namespace rcsim {

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

} // namespace rcsim
