// rcsim — what held an interrupt: its latency [IR rise, first handler instruction] cut into phases,
// each measured from the simulation (docs/scenarios.md "Latency causes"):
//   not_ready, masked, in_service, priority  the 8259A held the request (Pic8259::hold at every
//                                            change of the chip, from the IR rise on);
//   interrupts_disabled                      INT was up for it, the CPU's IF was 0 (the core's IF
//                                            history: since which change, until which one);
//   instruction                              INT up, IF = 1: the instruction in progress had to
//                                            end (the core's last instruction; HLT's wake-up; the
//                                            instruction after STI);
//   dpram_busy                               the Tw states of a DP-RAM cycle held by BUSY inside
//                                            those stretches or the entry (the core's held cycles);
//   entry                                    from the boundary where the CPU took it to the end
//                                            of the first handler fetch: INTA cycles, vector,
//                                            pushes.
// The phases partition the latency exactly; the cause is the phase kind (with its level) that
// took the most time. Everything is read when the interrupt is taken, from state the probe and
// the core keep anyway: nothing grows with the run.
#pragma once

#include "comm_cpu/i8086/history.h"
#include "pic8259/pic8259.h"

#include <systemc>

#include <array>
#include <cstdint>

namespace rcsim {

class Cpu8086;

/// One stretch [from, to) of a latency and what held the interrupt in it.
struct LatencyPhase {
    enum class Kind : std::uint8_t {
        not_ready,           // the 8259A was not initialised
        masked,              // the level's IMR bit was set
        in_service,          // `level` was in service in the 8259A: a higher priority, or the level itself
        priority,            // `level`, a higher-priority request, was presented first
        interrupts_disabled, // INT was up for it and the CPU's IF was 0
        instruction,         // INT up, IF = 1: the instruction in progress had to end
        dpram_busy,          // the bus held by DP-RAM BUSY wait states
        entry,               // the CPU took it: INTA cycles, vector fetch, pushes, first fetch
        presented,           // (while being measured only: INT up for it, not yet split by the CPU)
    };
    Kind kind = Kind::entry;
    int level = -1; // in_service, priority: the 8259A level
    sc_core::sc_time from, to;
    double us() const;
};
const char* to_string(LatencyPhase::Kind kind);

/// What held one interrupt. `known` only for an interrupt with an IR rise.
struct LatencyCause {
    static constexpr unsigned kMaxPhases = 16;
    bool known = false;
    std::array<LatencyPhase, kMaxPhases> phase{};
    unsigned phases = 0;
    bool truncated = false; // more changes than kMaxPhases: the last phase holds the rest

    /// The dominant cause: the kind (and level) whose phases took the most time, and that time.
    LatencyPhase::Kind cause = LatencyPhase::Kind::entry;
    int cause_level = -1;
    sc_core::sc_time cause_time;
    sc_core::sc_time boundary; // where the CPU took the interrupt (the entry's start)

    /// The longest stretch [from, to) of the latency with IF = 0 (interrupts_disabled): the change
    /// that cleared IF (`off`, at `since`; has_off false when the core's history does not reach
    /// back to it) and the one that set it again (`on`, the first after `from`; `until` when IF
    /// came back: the end of that instruction when the CPU took this interrupt right after it,
    /// else the boundary it began at). `to` is `until` unless the 8259A ended the stretch first
    /// (another request was taken): then the stretch's end, and IF came back later or earlier.
    struct IfOff {
        bool valid = false, has_off = false, has_on = false;
        i8086::IfChange off, on;
        sc_core::sc_time from, since, until, to;
    } if_off;

    /// The instruction the CPU had to finish (instruction): where and when it began, its bytes.
    struct Instruction {
        bool valid = false;
        bool halted = false;     // the CPU woke from HLT
        bool sti_shadow = false; // the instruction after the STI that enabled interrupts
        sc_core::sc_time start;
        std::uint16_t cs = 0, ip = 0;
        std::array<std::uint8_t, 6> bytes{};
        unsigned nbytes = 0;
    } instruction;

    /// DP-RAM BUSY inside the latency (dpram_busy): the Tw states of the held cycles (all of
    /// each, also before the IR rise) and the first address held.
    struct Busy {
        unsigned wait_states = 0;
        std::uint32_t address = 0;
    } busy;
};

/// What the 8259A did with one level's request from its IR rise to its INTA: the stretches it held
/// it (Pic8259::hold) and those it presented it. Kept by the interrupt probe per level.
class RequestTrack {
public:
    static constexpr unsigned kMaxPhases = 8;
    void open(const sc_core::sc_time& rise, const Pic8259::Hold& h);
    /// The chip's state changed (Pic8259::on_update); a new hold starts a new stretch.
    void update(const sc_core::sc_time& now, const Pic8259::Hold& h);
    void close() { open_ = false; }
    bool is_open() const { return open_; }

    /// The stretches so far, the running one ending at `end`.
    unsigned phases(const sc_core::sc_time& end, std::array<LatencyPhase, kMaxPhases>& out) const;

private:
    bool open_ = false;
    std::array<LatencyPhase, kMaxPhases> done_{};
    unsigned n_ = 0;
    LatencyPhase cur_;
};

/// The latency cause of the interrupt of `level` the CPU is entering now (called at its second
/// INTA): the request's stretches (a default track: presented since the rise), the CPU side from
/// the core's history. `finish_latency_cause` adds the entry once the first handler fetch ended.
LatencyCause explain_latency(const RequestTrack& track, const sc_core::sc_time& rise, Cpu8086& cpu);
void finish_latency_cause(LatencyCause& c, const sc_core::sc_time& rise, const sc_core::sc_time& first_isr,
                          Cpu8086& cpu, std::uint32_t dpram_base, std::uint32_t dpram_size);

} // namespace rcsim
