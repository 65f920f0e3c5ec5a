// rcsim — Intel 8086-2 CPU as a SystemC module around the plain C++ core (i8086.h).
//
// Documentation: Intel 8086 data sheet (231455); time-decoupling rules: docs/architecture.md
// "Time model".
//
// The core runs ahead of kernel time in an SC_THREAD. RAM/ROM regions are reached by direct
// pointer (map_memory); I/O, memory outside the map (the DP-RAM) and INTA go through TLM after
// the thread has synced to the cycle's T1. A slice never runs past the next pending kernel event
// (sc_time_to_pending_activity(), bounded by the quantum), so an INTR/NMI change scheduled at
// time T is seen at the first instruction boundary whose clock edge is later than T, exactly as
// a cycle-by-cycle run would see it (the 8086 samples INTR in the clock before the boundary).
#pragma once

#include "comm_cpu/i8086/cpu.h"
#include "models/bus.h"
#include "models/bus_error_log.h"
#include "models/clock.h"
#include "models/memory.h"

#include <systemc>
#include <tlm>
#include <tlm_utils/simple_initiator_socket.h>

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace rcsim {

class Cpu8086 : public sc_core::sc_module, private i8086::BusHandler {
public:
    tlm_utils::simple_initiator_socket<Cpu8086> io;   // I/O space (local offsets via a Router)
    tlm_utils::simple_initiator_socket<Cpu8086> mem;  // memory outside the direct map (DP-RAM)
    tlm_utils::simple_initiator_socket<Cpu8086> inta; // the two INTA cycles (8259A)
    sc_core::sc_in<bool> intr;
    sc_core::sc_in<bool> nmi;

    /// The default quantum, the board's too (CommBoardConfig::quantum): 100 us. The lookahead
    /// already ends a slice at every pending kernel event, so the quantum only bounds how far
    /// the core runs ahead when nothing is scheduled; 100 us gives the same reports as 10 us
    /// in fewer slices (docs/performance.md). Microseconds rather than an sc_time: a static
    /// sc_time would be built before sc_main, and building one fixes the kernel's resolution.
    static constexpr std::uint64_t kDefaultQuantumUs = 100;

    explicit Cpu8086(sc_core::sc_module_name name, const Clock& clock = Clock(8'000'000));

    /// A RAM/ROM region reached by direct pointer with its wait states (before simulation).
    void map_memory(const MemRegion& region) { core_.map_memory(region); }
    /// Upper bound of one decoupled slice (default kDefaultQuantumUs). Must be at least one clock.
    void set_quantum(const sc_core::sc_time& q);
    const sc_core::sc_time& quantum() const { return quantum_; }
    /// With lookahead off, every slice is one quantum regardless of pending events.
    void set_lookahead(bool on) { lookahead_ = on; }
    /// With fast sync on (the default), a slice goes on after a TLM access unless the access
    /// left kernel activity at the current time (a signal or event it changed, which may move
    /// INTR/NMI); the slice limit is lowered to any event the access scheduled. Off: every
    /// access ends the slice (the reference behaviour; the results are the same).
    void set_fast_sync(bool on) { fast_sync_ = on; }
    /// The core's exact idle fast-forward (i8086::Cpu::set_fast_forward): a loop whose state
    /// repeats is advanced along its recorded path to where the slice would end clock by clock
    /// (its limit, or the last boundary before the next pending kernel event). Off: every
    /// instruction is executed.
    void set_fast_forward(bool on) { core_.set_fast_forward(on); }
    /// The current sc_start() ends at `t`: the kernel is told (an event), so a slice stops
    /// there and the core stands at the first boundary at or after it, whichever syncs the
    /// speed-ups saved (a run cut between a read's kernel time and its T1 would leave the core
    /// wherever its next sync is).
    void end_slices_at(const sc_core::sc_time& t) {
        run_end_.cancel(); // one left by a run sc_pause() ended early would win over a later time
        if (t > sc_core::sc_time_stamp()) run_end_.notify(t - sc_core::sc_time_stamp());
    }
    /// Where the I/O and memory targets declare their stable reads (models/bus.h StableReads;
    /// the board's routers), nullptr: none.
    void set_stable_reads(const StableReads* io_space, const StableReads* memory) {
        io_stable_ = io_space;
        mem_stable_ = memory;
    }
    /// With stable reads on (the default), a read its target declares stable whose T1 lies
    /// before the next pending kernel event is made without the kernel sync (nothing can run
    /// before T1 that the sync would let run first). Off: every access syncs first (the
    /// reference behaviour; the results are the same).
    void set_stable_reads_enabled(bool on) { stable_reads_on_ = on; }
    /// With the slice chain on (the default), a slice that ends before the next pending kernel
    /// event, nothing left to run at the current time, is followed by the next one inside the
    /// core, without the kernel round trip whose only effect would be to move kernel time
    /// (docs/architecture.md "Slice chain"). Off: every slice returns to the kernel (the
    /// reference behaviour; the results are the same).
    void set_slice_chain(bool on) { slice_chain_ = on; }

    i8086::Cpu& core() { return core_; }
    const Clock& clock() const { return clock_; }
    i8086::cycles_t cycles() const { return core_.cycles(); }
    std::uint64_t instructions() const { return core_.instructions(); }
    /// Absolute simulated time of a core cycle number.
    sc_core::sc_time time_of(i8086::cycles_t c) const { return clock_.cycles(c); }

    /// Bus-cycle observation: called once per bus cycle with the cycle's record; convert the
    /// start cycle with time_of(). nullptr turns it off (the default; free when unused).
    void set_bus_observer(i8086::BusHook hook, void* context, i8086::BusKinds kinds = i8086::kAllBusKinds) {
        bus_observer_ = {hook, context, kinds};
        install_bus_observers();
    }
    /// The kinds of cycle the observer is called for from now on (i8086::Cpu::set_bus_hook_kinds);
    /// a debug observer still sees every cycle.
    void set_bus_observer_kinds(i8086::BusKinds kinds) {
        bus_observer_.kinds = kinds;
        core_.set_bus_hook_kinds(debug_bus_observer_.hook ? i8086::kAllBusKinds : kinds);
    }
    /// A second bus-cycle observer beside set_bus_observer's, called after it (the debugger's
    /// watchpoints, while the interrupt probe keeps the first). nullptr removes it.
    void set_debug_bus_observer(i8086::BusHook hook, void* context) {
        debug_bus_observer_ = {hook, context, i8086::kAllBusKinds};
        install_bus_observers();
    }
    /// Instruction-boundary hook of the core (debugger, profiler; a counter with `skipped`, which
    /// keeps the fast-forward on); see i8086::Cpu::set_step_hook.
    void set_step_observer(i8086::StepHook hook, void* context, i8086::SkipHook skipped = nullptr) {
        step_observer_ = {hook, context};
        core_.set_step_hook(hook, context, skipped);
    }
    /// The hook set_step_observer installed last and its context, for an observer that chains
    /// in front of it (coverage beside the profiler or the debugger).
    std::pair<i8086::StepHook, void*> step_observer() const { return step_observer_; }
    /// Records the cycle number of every instruction boundary into `log` (nullptr: off).
    void set_boundary_log(std::vector<i8086::cycles_t>* log) { boundary_log_ = log; }

    /// Slices run, chained ones included (set_slice_chain).
    std::uint64_t slices() const { return slices_; }
    /// The times this thread handed control to the kernel (wait()): kernel time catching up
    /// with the core at a slice start or before a bus access, and HLT's sleep. Each is a
    /// kernel round trip, the floor of a run's host time (`rcsim bench system`).
    std::uint64_t kernel_waits() const { return kernel_waits_; }
    /// Of kernel_waits(), those before a bus access (the sync the access needs; the others end
    /// a slice or sleep in HLT).
    std::uint64_t access_waits() const { return access_waits_; }
    /// Reads made ahead of kernel time under a stable-read declaration (each a wait saved).
    std::uint64_t stable_reads() const { return stable_reads_; }

    /// Debugger memory access (no bus cycle, no time, no device side effect): RAM and ROM
    /// through the direct map (ROM writable here), everything else through the memory socket's
    /// debug transport (the DP-RAM's array). False when a byte of the range is neither.
    bool debug_read(std::uint32_t linear, std::uint8_t* out, std::size_t n);
    bool debug_write(std::uint32_t linear, const std::uint8_t* in, std::size_t n);

    /// The bus cycles nothing answered: a TLM access answered TLM_ADDRESS_ERROR_RESPONSE (no
    /// device decodes the address: unmapped; the read gives 0xFFFF) or another error response
    /// (tlm_error), and writes into a read-only mapped region (rom_write, dropped).
    const BusErrorLog& bus_errors() const { return bus_errors_; }

private:
    void run();
    void track_inputs();
    bool sampled(bool now, bool prev, const sc_core::sc_time& changed, const sc_core::sc_time& at) const {
        return changed < at ? now : prev;
    }
    void sample_inputs(const sc_core::sc_time& at);
    static constexpr std::uint64_t kNoEvent = ~std::uint64_t{0};
    /// The time of the next pending kernel activity in ps (now, with activity at the current
    /// time), kNoEvent with none pending: one kernel query.
    static std::uint64_t next_activity_ps();
    void plan_slice(std::uint64_t now_ps, i8086::cycles_t start, bool fresh_change, std::uint64_t event_ps,
                    i8086::cycles_t& limit, i8086::cycles_t& horizon) const;
    bool next_slice(i8086::cycles_t at, i8086::cycles_t& limit, i8086::cycles_t& horizon) override;
    void after_access();
    bool may_read_early(i8086::Bus kind, std::uint32_t address, unsigned width, const sc_core::sc_time& t1) const;
    unsigned bus_access(i8086::Bus kind, std::uint32_t address, std::uint16_t& data, unsigned width,
                        i8086::cycles_t start) override;
    void write_ignored(std::uint32_t address, unsigned width, i8086::cycles_t start) override;
    bool debug_access(std::uint32_t linear, std::uint8_t* data, std::size_t n, bool write);
    struct Observer {
        i8086::BusHook hook = nullptr;
        void* context = nullptr;
        i8086::BusKinds kinds = i8086::kAllBusKinds;
    };
    /// The core has one hook: the first observer directly, or both through bus_fanout.
    void install_bus_observers();
    static void bus_fanout(void* self, const i8086::BusRecord& record);
    Observer bus_observer_, debug_bus_observer_;
    std::pair<i8086::StepHook, void*> step_observer_{nullptr, nullptr};

    i8086::Cpu core_;
    Clock clock_;
    sc_core::sc_time quantum_;
    bool lookahead_ = true;
    bool fast_sync_ = true;
    bool stable_reads_on_ = true;
    bool slice_chain_ = true;
    sc_core::sc_event run_end_{"run_end"}; // end_slices_at(): nothing waits on it, it bounds slices
    const StableReads* io_stable_ = nullptr;
    const StableReads* mem_stable_ = nullptr;
    std::uint64_t stable_reads_ = 0;
    std::vector<i8086::cycles_t>* boundary_log_ = nullptr;
    std::uint64_t slices_ = 0;
    std::uint64_t kernel_waits_ = 0;
    std::uint64_t access_waits_ = 0;
    BusErrorLog bus_errors_;
    BusPayload payload_; // every access of the core's (one at a time: the core waits in it)
    bool slice_end_ = false; // a TLM access happened: recompute the lookahead at the boundary
    i8086::cycles_t slice_limit_ = 0; // the cycle the current slice runs to

    // INTR/NMI with the time of their last change: a boundary at time t sees the level that
    // held before t.
    bool intr_now_ = false, intr_prev_ = false, nmi_now_ = false, nmi_prev_ = false;
    sc_core::sc_time intr_changed_, nmi_changed_;
};

} // namespace rcsim
