// rcsim — `rcsim run --trace FILE.json`: the run as a Trace Event Format file for ui.perfetto.dev
// and chrome://tracing (docs/tools.md "Perfetto trace").
//
// Tracks (process = a group in the viewer):
//   "8259A"            one thread track per IR level with a slice per ISR (first handler
//                      instruction to the interrupted code's resumption, as report.json's
//                      service_us) and instants IR rise, INTA, EOI; a track "ISR nesting" with every
//                      ISR as a slice nested in the one it interrupted.
//   "82510 port p"     counters RX FIFO and TX FIFO (characters), and the protocol state of each
//                      direction's sender (0 idle, 1 ENQ sent, 2 frame on the line, 3 awaiting EOT).
//   "IDT7130 DP-RAM"   counters BUSY per port (1 while the port is held off).
//   "host p"           a slice per frame on the line, one track per direction, named by its token.
//
// Nothing is observed twice: the ISRs are the interrupt probe's records, the protocol state and
// frames the line observer's decoding, the FIFO levels and BUSY the chips' own probe hooks. Each
// hook that was already set keeps working (the trace calls it first).
//
// Per-track time order: the counters and frames are sampled at kernel time as they change, so each
// track is in order as written. The probe hands its records over late (after the interrupted code
// resumes) and nested ones out of their start order, so the interrupt tracks' events wait in a
// queue ordered by time and are written up to the probe's horizon (InterruptProbe::on_settled:
// nothing handed over later starts before it). The queue holds only the interrupts of one nested
// episode: memory stays flat over the run.
#pragma once

#include "scenarios/trace/trace_events.h"

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>

namespace rcsim {

class World;
struct InterruptRecord;

namespace trace {

class PerfettoTrace {
public:
    /// Opens `path` and hooks the trace onto `world` (before sc_start). ConfigError if the file
    /// cannot be created.
    PerfettoTrace(World& world, const std::string& path);

    /// After World::finish(): writes what is still queued and closes the file; ConfigError naming
    /// the file if any write failed.
    void finish();

    std::uint64_t events() const { return out_.events(); }
    static constexpr unsigned ports() { return kPorts; }

private:
    static constexpr unsigned kPorts = 3;
    enum Pid : unsigned { pid_pic = 1, pid_uart = 10, pid_dpram = 20, pid_host = 30 };
    static constexpr unsigned kNestingTid = 100;

    World& world_;
    TraceEventWriter out_;

    // The interrupt tracks' events not yet written, by time (equal times keep their order).
    struct Queued {
        enum Kind : std::uint8_t { slice, instant } kind;
        unsigned tid;
        std::string name, args;
        std::uint64_t dur_ps;
    };
    std::multimap<std::uint64_t, Queued> queue_;
    std::array<bool, 8> level_named_{};

    // Last value written on each counter track (a counter is written only when it changes).
    struct PortCounters {
        std::int64_t rx = -1, tx = -1;
        std::array<std::int64_t, 2> state{{-1, -1}};
        std::array<std::uint64_t, 2> frame_start_ps{};
    };
    std::array<PortCounters, kPorts> ports_;

    void name_tracks();
    void on_record(const InterruptRecord& r);
    void flush_before(std::uint64_t horizon_ps);
    void sample_fifos(unsigned port);
    void sample_states(unsigned port);
    void on_frame(unsigned port, unsigned dir, bool valid, const std::string& token);
    void counter(unsigned pid, const std::string& name, std::int64_t& last, std::int64_t value, std::uint64_t ts_ps);
};

} // namespace trace
} // namespace rcsim
