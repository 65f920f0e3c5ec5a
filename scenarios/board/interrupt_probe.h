// rcsim — interrupt timing probe for the communication board.
//
// Measures every interrupt from bus cycles and pins, never from firmware cooperation:
//   ir_rise    the IR line of the 8259A rises (kernel event on the line)
//   inta1/2    T1 of the first and second INTA bus cycles (the second carries the vector)
//   first_isr  the first instruction of the handler is available: the end (T4) of the first code
//              fetch at the handler address read from the vector table
//   eoi        T1 of the I/O write of an EOI command (OCW2 with EOI=1) to the 8259A
//   iret_done  the interrupted code resumes: T1 of the first code fetch at the return address
//              that the entry pushed, after the handler popped it (IRET); or, when the CPU goes
//              from the IRET straight into the next pending interrupt, T1 of that INTA
// latency = first_isr - ir_rise; service = iret_done - first_isr. Nested interrupts are tracked
// with a stack. The handler address and return address come from the entry's own bus cycles
// (vector-table reads and the pushes of CS and IP).
//
// Memory stays flat over any run length: per level the probe keeps a count and the latency and
// service sample sets (models/stats.h), and hands each completed record to `on_record` instead
// of keeping it. Keeping every record (`keep_records`) is for short tests.
//
// Each latency has its cause (latency_cause.h): with the 8259A watched (watch_pic), what the chip
// did with the request from its rise; then, from the core's interrupt history, IF = 0, the
// instruction in progress, DP-RAM BUSY and the entry. Per level the probe keeps the records of
// the longest latencies with their causes (WorstLatencies, a fixed number).
#pragma once

#include "scenarios/board/latency_cause.h"
#include "comm_cpu/i8086/cpu.h"
#include "models/irq.h"
#include "models/stats.h"

#include <systemc>

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace rcsim {

class Cpu8086;

struct InterruptRecord {
    unsigned level = 0;
    std::uint8_t vector = 0;
    sc_core::sc_time ir_rise, inta1, inta2, first_isr, eoi, iret_done;
    bool has_rise = false, has_eoi = false, done = false;
    unsigned depth = 0;            // nesting depth at entry (0 = interrupted the main program)
    /// Requested during the firmware's start-up: the IR line rose before the CPU could first take
    /// an interrupt (i8086::Cpu::interrupts_enabled_at). Its figures are reported apart and judged
    /// by no check (docs/scenarios.md "Start-up").
    bool startup = false;
    std::uint32_t handler = 0;     // physical address of the first handler instruction
    std::uint64_t dpram_reads = 0; // DP-RAM data-area bytes the handler read (left port)
    std::uint64_t dpram_writes = 0;
    LatencyCause cause;            // what held it (known with an IR rise)

    /// The part of its own service [first_isr, iret_done] (the interrupts nested in it left out) that
    /// kept other requests waiting: IF = 0, or its level still in service in the 8259A (before its
    /// EOI; the whole service when it sends none). IF changes count from the boundary of the
    /// instruction that made them (i8086::IfChange::cycle).
    sc_core::sc_time blocking;
    double blocking_us() const;
    /// What ran while it blocked: the call path to the deepest routine that ran while the service
    /// was blocking (linear code addresses, outermost first: [0] the handler's entry, then one
    /// address inside each routine called, the last inside the deepest routine). path_len 0: unknown.
    static constexpr unsigned kMaxPath = 8;
    std::array<std::uint32_t, kMaxPath> path{};
    unsigned path_len = 0;
    /// Where it interrupted: the return address its entry pushed (CS:IP).
    std::uint16_t ret_cs = 0, ret_ip = 0;
    /// The boundary at which the CPU took it (the cycle of its entry's IF change).
    i8086::cycles_t boundary_cycle = 0;
    /// RS-232 sources: the RX FIFO level of the level's port at first_isr (InterruptProbe::fifo_level).
    unsigned rx_fifo_level = 0;
    /// What held it (its cause's dominant phase): for interrupts_disabled the service whose entry
    /// cleared IF, for in_service the service of the level in service: that service's level, call
    /// path and the location it interrupted. Main-program code that cleared IF (CLI, POPF):
    /// holder_service false, holder_path the routines on its stack when this one was taken, then
    /// the routine of the clearing instruction. holder_path_len 0: unknown.
    int holder_level = -1;
    std::array<std::uint32_t, kMaxPath> holder_path{};
    unsigned holder_path_len = 0;
    bool holder_service = false; // an interrupt service held it (else main-program code)
    std::uint16_t holder_ret_cs = 0, holder_ret_ip = 0;

    double latency_us() const;
    double service_us() const;
    bool entered_before(const sc_core::sc_time& t) const { return inta1 < t; }
};

/// The source name of an 8259A level on the communication board: rs232_0..2 (IR0..IR2), dpram
/// (IR3), irN otherwise.
std::string source_name(unsigned level);
/// A simulated time in microseconds with every picosecond kept (sc_time counts picoseconds).
double exact_us(const sc_core::sc_time& t);

/// The longest latencies of a set of interrupts with their causes, in bounded memory: the `keep`
/// longest so far, longest first (on a tie the one added first).
class WorstLatencies {
public:
    static constexpr std::size_t kKeep = 20;
    WorstLatencies() = default;
    explicit WorstLatencies(std::size_t keep) : keep_(keep) {}
    /// A completed record (one without an IR rise has no latency and is left out).
    void add(const InterruptRecord& r);
    const std::vector<InterruptRecord>& records() const { return kept_; }

private:
    std::size_t keep_ = kKeep;
    std::vector<InterruptRecord> kept_;
};

/// Where a run sends every completed record besides its own figures (the report's interrupt log,
/// scenarios/report/interrupt_log.h), so that the world that measures does not depend on what
/// renders: `record` in entry order, with whether the interrupt took a character out of its port's
/// RX FIFO (the world tells that from the RXD reads); `settle`: no record told later starts before
/// `horizon`; `finish`: no more records.
class InterruptSink {
public:
    virtual ~InterruptSink() = default;
    virtual void record(const InterruptRecord& r, bool rx) = 0;
    virtual void settle(const sc_core::sc_time& horizon) = 0;
    virtual void finish() = 0;
};

class InterruptProbe : public sc_core::sc_module {
public:
    /// Watches `cpu`'s bus cycles; `ir` are the 8259A's request lines (index = level);
    /// `pic_io_base` the 8259A's A0=0 I/O address; DP-RAM data bytes are counted in
    /// [dpram_base, dpram_base + dpram_data_size).
    SC_HAS_PROCESS(InterruptProbe);
    InterruptProbe(sc_core::sc_module_name name, Cpu8086& cpu, std::vector<IrqLine*> ir,
                   std::uint16_t pic_io_base, std::uint32_t dpram_base, std::uint32_t dpram_data_size);

    /// Completed interrupts of one level after start-up, and their latency (those with an IR
    /// rise) and service. Start-up interrupts are counted apart (startup_records()).
    std::uint64_t count(unsigned level) const { return level < 8 ? count_[level] : 0; }
    /// The completed start-up interrupts (at most one per level: a level's request stays pending
    /// until it is taken), in completion order.
    const std::vector<InterruptRecord>& startup_records() const { return startup_; }
    /// When the CPU could first take an interrupt; none before it could.
    std::optional<sc_core::sc_time> interrupts_enabled() const;
    const Samples& latency_us(unsigned level) const { return latency_[level & 7]; }
    const Samples& service_us(unsigned level) const { return service_[level & 7]; }
    /// The blocking time of every service of the level after start-up (InterruptRecord::blocking).
    const Samples& blocking_us(unsigned level) const { return blocking_[level & 7]; }
    /// The level's service with the longest blocking time (the first of equals; start-up
    /// excluded), nullptr when none.
    const InterruptRecord* longest_blocking(unsigned level) const {
        return longest_[level & 7].done ? &longest_[level & 7] : nullptr;
    }
    /// The RX FIFO level of the port of an 8259A level, read at each first_isr (unset: 0).
    std::function<unsigned(unsigned level)> fifo_level;
    /// The records of the level's longest latencies, with their causes.
    const WorstLatencies& worst(unsigned level) const { return worst_[level & 7]; }

    /// The 8259A the IR lines go to: what it did with each request (Pic8259::hold) becomes part
    /// of the latency's cause. Takes the chip's on_update hook. Without it the time before the
    /// CPU took an interrupt is the CPU's alone.
    void watch_pic(Pic8259& pic);

    /// Every completed record, in completion order, and those of one level: kept only while
    /// `keep_records` is on (the default, for tests of a few seconds; a long run turns it off and
    /// listens to `on_record`).
    void keep_records(bool on) { keep_ = on; }
    const std::vector<InterruptRecord>& records() const { return done_; }
    std::vector<const InterruptRecord*> of_level(unsigned level) const;

    /// Completed records, in entry order (first INTA), each once it and every interrupt entered
    /// before it have completed: the probe holds a record back while an interrupt it is nested
    /// in still runs (the nested one completes first), and hands the lot over when the CPU is
    /// back in the main program. `on_settled(h)` follows each such batch: every record handed over
    /// later starts (IR rise, or first INTA without one) at h or after.
    std::function<void(const InterruptRecord&)> on_record;
    std::function<void(const sc_core::sc_time&)> on_settled;
    /// The end of the run: hands over the completed records still held back (their outer
    /// interrupt never returned) and settles at the end of time. Records still open stay out.
    void flush();

    /// Called for every memory write into the DP-RAM window [dpram_base, dpram_base + 1 KB) with
    /// the write's T1 time (for per-byte DP-RAM measurements). Other cycles are not passed on, so
    /// the hook costs nothing on the hot path of code fetches and RAM accesses.
    std::function<void(const i8086::BusRecord&, const sc_core::sc_time&)> on_dpram_write;

    /// Another observer of every bus cycle (the CPU has one observer slot and the probe holds
    /// it): called for each cycle before the probe looks at it; nullptr (the default) for none.
    void forward_cycles(i8086::BusHook hook, void* context) {
        forward_ = hook;
        forward_ctx_ = context;
        watch_kinds();
    }

private:
    Cpu8086& cpu_;
    i8086::BusHook forward_ = nullptr;
    void* forward_ctx_ = nullptr;
    std::vector<IrqLine*> ir_;
    std::uint16_t pic_io_base_;
    std::uint32_t dpram_base_, dpram_size_;

    std::array<sc_core::sc_time, 8> rise_{};
    std::array<bool, 8> rise_pending_{};
    std::array<bool, 8> last_level_{};
    Pic8259* pic_ = nullptr;
    std::array<RequestTrack, 8> track_{}; // the request of each level with a rise pending
    std::array<WorstLatencies, 8> worst_{};
    void pic_update();

    // Entry in progress: INTA cycles seen, vector-table reads and pushes to collect.
    struct Open {
        InterruptRecord rec;
        unsigned ivt_reads = 0;
        std::uint16_t new_ip = 0, new_cs = 0;
        unsigned pushes = 0;
        bool half_pending = false;          // low byte of a word pushed at an odd address
        std::uint32_t half_address = 0;
        std::uint8_t half_low = 0;
        std::uint32_t ip_slot = 0;          // stack address where the return IP was pushed
        std::uint16_t ret_ip = 0, ret_cs = 0;
        bool entered = false;               // first handler fetch seen
        bool popped = false;                // the return IP was read back
        sc_core::sc_time eoi_if_off;        // IfClock::off_until at its EOI
        sc_core::sc_time nested_before_eoi; // wall time of nested services before its EOI
        sc_core::sc_time nested_if_off;     // IF = 0 time of nested services after its EOI
        sc_core::sc_time begin_if_off;      // IfClock::off_until at its entry's boundary
        std::uint32_t deepest_sp = ~0u;     // lowest stack address of a walk while blocking
    };
    /// The running total of IF = 0 time, fed by the core's IF changes (i8086::Cpu::set_if_hook):
    /// the IF = 0 part of any window [a, b] is off_until(b) - off_until(a).
    struct IfClock {
        bool off = true; // IF = 0 from the reset
        sc_core::sc_time last, total;                   // the last change, IF = 0 time up to it
        bool prev_off = true;
        sc_core::sc_time prev, prev_total;              // the change before it
        void change(const sc_core::sc_time& t, bool enabled);
        sc_core::sc_time off_until(const sc_core::sc_time& t) const;
    } if_clock_;
    static void if_hook(void* self, const i8086::IfChange& c);
    /// The last services closed, for the holder of a later latency's IF = 0 stretch.
    static constexpr unsigned kRecent = 4;
    std::array<InterruptRecord, kRecent> recent_{};
    unsigned recent_n_ = 0;
    /// At the first handler fetch of `entering`, its latency's cause complete: who held it.
    void name_holder(Open& entering);
    /// The routines called by the return addresses on the stack in [from, to) (near: in code
    /// segment `cs`), outermost first, into `out` (at most `max`); `here` is the code running now
    /// (inside the deepest); the word at `skip` is left out (being written now).
    unsigned walk_stack(std::uint32_t from, std::uint32_t to, std::uint16_t cs, std::uint32_t skip,
                        std::uint32_t here, std::uint32_t* out, unsigned max);
    void sample_path(Open& o, const i8086::BusRecord& r);
    std::array<Samples, 8> blocking_;
    std::array<InterruptRecord, 8> longest_{};
    std::vector<Open> stack_;
    std::vector<InterruptRecord> held_; // completed, some interrupt entered before them still open
    std::array<std::uint64_t, 8> count_{};
    std::array<Samples, 8> latency_, service_;
    std::vector<InterruptRecord> startup_;
    bool keep_ = true;
    std::vector<InterruptRecord> done_;

    void sample_lines();
    /// The cycles the probe needs from the CPU, told to it after each cycle it sees: outside
    /// interrupts only INTA and memory writes (DP-RAM writes); inside one every kind, but code
    /// fetches only until the handler's first fetch and after the return IP is popped; every
    /// cycle with a forward observer. So the main program's fetches and reads, and a handler's
    /// own fetches, keep the core's direct path. (ProfileRun's test compares a run whose probe
    /// sees every cycle: the reports are identical.)
    void watch_kinds();
    i8086::BusKinds watched_ = i8086::bus_kind_bit(i8086::Bus::int_ack) | i8086::bus_kind_bit(i8086::Bus::mem_write);
    static void bus_hook(void* self, const i8086::BusRecord& r);
    void on_cycle(const i8086::BusRecord& r);
    void on_inta(const i8086::BusRecord& r, const sc_core::sc_time& t);
    bool on_entry_cycle(Open& o, const i8086::BusRecord& r);
    void on_handler_cycle(const i8086::BusRecord& r);
    void close_top(const sc_core::sc_time& iret_done);
    void hand_over(const sc_core::sc_time& horizon);
    sc_core::sc_time start_horizon() const;
};

} // namespace rcsim
