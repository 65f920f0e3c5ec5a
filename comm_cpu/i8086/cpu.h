// rcsim — Intel 8086 (8086-2) CPU core, bus-cycle exact, plain C++ (no SystemC).
//
// Documentation: Intel 8086 16-bit HMOS Microprocessor data sheet (231455), iAPX 86/88 User's
// Manual (1981) for instruction semantics and clock counts; the BIU timing rules (queue
// policy, EU/prefetch bus arbitration delays) follow the behaviour captured from a real
// P80C86A-2 in the SingleStepTests 8086 suite and the published facts in docs/cpu8086.md.
//
// Structure (docs/cpu8086.md):
// - The core is stepped one CLK at a time (clk()). Each clock advances the bus interface unit
//   (T1-T4, Tw, Ti, the 6-byte prefetch queue) and optionally records a per-cycle trace row.
// - The execution unit is straight-line C++ per opcode that consumes clocks by reading the
//   queue, asking the BIU for bus cycles, or spending internal cycles.
// - RAM/ROM are reached by direct pointer through a MemoryMap; everything else (I/O, memory
//   outside the map such as the DP-RAM, the two INTA cycles) goes through a BusHandler which is
//   told the absolute start cycle (T1) and answers with the Tw wait states it inserts.
#pragma once

#include "comm_cpu/i8086/history.h"
#include "comm_cpu/i8086/types.h"
#include "models/memory.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <utility>
#include <vector>

namespace rcsim::i8086 {

class Cpu {
public:
    Cpu();

    // --- configuration ---
    void map_memory(const MemRegion& region);
    const MemoryMap& memory() const { return mem_; }
    void set_bus_handler(BusHandler* handler) { handler_ = handler; }
    /// The bus-cycle observer, called for every cycle of a kind in `kinds` (nullptr: none).
    void set_bus_hook(BusHook hook, void* context, BusKinds kinds = kAllBusKinds) {
        hook_ = hook;
        hook_ctx_ = context;
        set_bus_hook_kinds(kinds);
    }
    /// The kinds the hook is called for from now on. An observer that ignores most cycles in
    /// some state (the interrupt probe outside interrupts: all but INTA and memory writes)
    /// narrows it, so those cycles keep the direct path and a fast-forward does not replay
    /// them to it one by one.
    void set_bus_hook_kinds(BusKinds kinds) { hook_kinds_ = hook_ ? kinds : 0; }
    BusKinds bus_hook_kinds() const { return hook_kinds_; }
    /// Instruction-boundary observer (nullptr turns it off). Without `skipped` (debuggers,
    /// profilers: they need each instruction's time, and may stop) the fast-forward is off while
    /// it is set, so the hook sees every boundary. With `skipped` (counters) the fast-forward
    /// stays on: the boundaries it goes past are told to `skipped` (same context) instead.
    void set_step_hook(StepHook hook, void* context, SkipHook skipped = nullptr) {
        step_hook_ = hook;
        step_hook_ctx_ = context;
        skip_hook_ = hook ? skipped : nullptr;
    }
    /// Per-cycle trace into `out` (nullptr turns it off).
    void set_cycle_trace(std::vector<CycleRecord>* out) {
        trace_ = out;
        last_qop_ = qop_at_ + 1 == cycle_ ? qop_ : QueueOp::idle; // the lines of the first row
        last_qbyte_ = qbyte_;
    }

    // --- reset and state ---
    /// Hardware reset: CS=FFFF, IP=0, flags cleared, queue empty.
    void reset();
    /// Puts the CPU at cs:ip with `queue` already prefetched (the SingleStepTests set-up): the
    /// fetch pointer is ip + queue size and the BIU idles until the queue has room.
    void load_state(const Registers& regs, const std::uint8_t* queue, unsigned queue_len);
    Registers& regs() { return r_; }
    const Registers& regs() const { return r_; }

    // --- inputs (levels) ---
    void set_intr(bool level) {
        if (level != intr_) ff_recording_ = false; // a recorded period holds its inputs constant
        intr_ = level;
    }
    void set_nmi(bool level);
    bool halted() const { return halted_; }

    // --- running ---
    /// Reads the first byte of the next instruction from the queue (one clock). Execution starts
    /// with this; afterwards step() keeps one byte pre-read as the hardware does.
    void start();
    /// Executes one instruction (with its prefixes, or a whole REP string run, or an interrupt
    /// entry) and reads the first byte of the following instruction.
    void step();
    /// Steps until cycles() >= limit or stop_run() is called (e.g. by a bus handler that needs
    /// the caller to sync). While halted, the remaining cycles are consumed as idle clocks
    /// only if `burn_halt`; otherwise it returns at once. `horizon` (>= limit; default: limit)
    /// is the first cycle at which an input may change: the idle fast-forward never stops
    /// past the last boundary at or before it (nor past the first one at `limit`). At the
    /// limit, a next slice the BusHandler chains (BusHandler::next_slice) continues the run.
    void run_until(cycles_t limit, bool burn_halt = true, cycles_t horizon = 0);
    void stop_run() { stop_ = true; }
    /// Lowers the limit and the horizon of the run_until() in progress (never raises them).
    void shorten_run(cycles_t limit) {
        if (limit < limit_) limit_ = limit;
        if (limit < horizon_) horizon_ = limit;
    }

    /// Exact idle fast-forward (docs/cpu8086.md "Idle fast-forward"; off by default): inside
    /// run_until(), when the whole state (registers, flags, queue, BIU phase, the RAM the loop
    /// wrote) returns to the same value at the same instruction after a period of clocks, the
    /// period is kept with the state at each of its instruction boundaries, and from any later
    /// boundary with one of those states the clocks are not executed one by one: the bus
    /// cycles are replayed (the bus hook sees each one; I/O and non-RAM memory still go to the
    /// BusHandler, at the same start cycle), the RAM writes made and the recorded state put
    /// back at the boundary where the run would stop clock by clock (the first at the limit,
    /// or the last at or before the horizon). A handler answer that differs from the recorded
    /// one (data, wait states) or that ends the run falls back to executing. Never used while a
    /// cycle trace or a step hook without a SkipHook is attached (every instruction and clock
    /// is then executed); with a SkipHook, the boundaries gone past are told to it.
    void set_fast_forward(bool on);
    /// Clocks advanced by the fast-forward so far (included in cycles()).
    cycles_t forwarded_cycles() const { return ff_cycles_; }
    /// Instructions advanced by the fast-forward so far (included in instructions()): the
    /// others were executed.
    std::uint64_t forwarded_instructions() const { return ff_instructions_; }
    /// One step() that parks a REP run between elements once `limit` is reached.
    void step_within(cycles_t limit) {
        limit_ = limit;
        step();
        limit_ = ~cycles_t(0);
    }
    /// Moves the cycle counter forward without simulating clocks (only while halted: bus idle).
    void skip_to(cycles_t c);
    /// Debugger: the next instruction is the one at cs:ip. Call only from the step hook (an
    /// instruction boundary): the queue is flushed and the opcode read from cs:ip, as a far
    /// jump would (the refetch takes its bus cycles; nothing else of a jump happens).
    void debug_jump(std::uint16_t cs, std::uint16_t ip) {
        jump_far(cs, ip);
        opcode_ = q_read(QueueOp::first);
    }

    cycles_t cycles() const { return cycle_; }
    std::uint64_t instructions() const { return instructions_; }
    /// The first instruction boundary (cycle) at which an INTR could be taken (IF = 1, nothing
    /// inhibiting it), kNever until then: the end of start-up (docs/scenarios.md "Start-up").
    static constexpr cycles_t kNever = ~cycles_t{0};
    cycles_t interrupts_enabled_at() const { return interrupts_enabled_at_; }
    /// Linear address of CS:IP of the next instruction to execute.
    std::uint32_t pc() const { return linear(r_.s[CS], r_.ip); }
    static std::uint32_t linear(std::uint16_t seg, std::uint16_t off) { return ((std::uint32_t(seg) << 4) + off) & 0xFFFFF; }

    // --- why an interrupt waited (history.h): read by the interrupt probe ---
    static constexpr unsigned kIfHistory = 8, kHeldHistory = 8;
    /// The k-th newest change of IF (0 = the last), k < if_changes().
    const IfChange& if_change(unsigned k) const { return if_ring_[(if_count_ - 1 - k) % kIfHistory]; }
    unsigned if_changes() const { return if_count_ < kIfHistory ? unsigned(if_count_) : kIfHistory; }
    /// The k-th newest memory cycle the BusHandler answered with wait states, k < held_cycles().
    const HeldCycle& held_cycle(unsigned k) const { return held_ring_[(held_count_ - 1 - k) % kHeldHistory]; }
    unsigned held_cycles() const { return held_count_ < kHeldHistory ? unsigned(held_count_) : kHeldHistory; }
    /// An observer of every change of IF as it is recorded (CLI, STI, POPF, IRET, an entry, the
    /// reset, the fast-forward's replayed changes), in the order the core records them: a probe
    /// that measures how long IF was 0 over any window needs each one, not only the last
    /// kIfHistory. nullptr (the default) for none; unset it costs one test per change.
    using IfHook = void (*)(void* context, const IfChange& change);
    void set_if_hook(IfHook hook, void* context) {
        if_hook_ = hook;
        if_hook_ctx_ = context;
    }
    /// The hook set_if_hook installed, and its context: a second observer chains to it.
    IfHook if_hook() const { return if_hook_; }
    void* if_hook_context() const { return if_hook_ctx_; }
    /// The last instruction executed (or in progress): its boundary and CS:IP (first prefix).
    cycles_t instruction_start() const { return instr_start_; }
    std::uint16_t instruction_cs() const { return instr_cs_; }
    std::uint16_t instruction_ip() const { return instr_ip_; }
    /// The boundary the last INTR/NMI/trap was taken at, and whether the CPU was halted there.
    cycles_t interrupt_boundary() const { return intr_boundary_; }
    bool interrupt_from_halt() const { return intr_from_halt_; }

private:
    // ---- BIU ----
    struct BusOp {
        Bus kind = Bus::passive;
        SegStatus seg = SegStatus::none;
        std::uint32_t addr = 0;
        std::uint16_t data = 0;
        std::uint8_t width = 1;
        bool fetch = false;
        bool discard = false; // a prefetch overtaken by a queue flush
        bool inta_first = false; // the first of the two INTA cycles: LOCK from its T2
    };

    /// One CLK: the T-state transition of the BIU and the scheduled prefetch. Nothing here
    /// counts down: a scheduled prefetch and the last queue operation carry the cycle they
    /// belong to (fetch_t1_, qop_at_), so a clock without a transition costs a switch.
    void clk() {
        if (trace_) trace_clock();
        switch (t_) {
        case TState::Ti:
            if (fetch_sched_) fetch_tick();
            break;
        case TState::T1:
            // LOCK runs from T2 of the first INTA cycle to T2 of the second (data sheet).
            if (cur_.kind == Bus::int_ack) lock_pin_ = cur_.inta_first;
            t_ = TState::T2;
            break;
        case TState::T2:
            // The decision to prefetch right after this cycle is taken in T2.
            fetch_next_ = !eu_claim_ && !fetch_suspended_ && q_len_ + (cur_.fetch ? cur_.width : 0) <= 4;
            t_ = TState::T3;
            break;
        case TState::T3:
        case TState::Tw:
            if (waits_left_) {
                --waits_left_;
                t_ = TState::Tw;
            } else {
                t_ = TState::T4;
            }
            break;
        case TState::T4: clk_t4(); break;
        }
        ++cycle_;
    }
    /// A named one-clock step of microcode.h (kJump, kSuspLine, ...) spent as one clk(),
    /// where the EU has always taken its one clock with clk() rather than clks(1): the same
    /// clock, and the cheaper code on those paths. `step` only names it (one of the steps the
    /// header checks to be 1).
    void clk(unsigned /*step*/) { clk(); }
    /// With a trace: the row of this clock, then the QS lines for the next one (the queue
    /// operation made in this clock, if any).
    void trace_clock() {
        record_cycle();
        last_qop_ = qop_at_ == cycle_ ? qop_ : QueueOp::idle;
        last_qbyte_ = qbyte_;
    }
    void clk_t4();
    void fetch_tick();
    /// Every bus cycle at its T1 decision: the fast-forward's record, then the bus hook.
    /// Call sites test observed(kind) first. A re-execution mutes the cycles the hook was
    /// already handed (counted whatever their kind: the kinds may have changed since).
    void observe(const BusRecord& r) {
        if (ff_recording_) ff_note_cycle(r);
        if (ff_hook_mute_) --ff_hook_mute_;
        else if (hook_kinds_ & bus_kind_bit(r.kind)) hook_(hook_ctx_, r);
    }
    bool observed(Bus kind) const { return ff_recording_ || ff_hook_mute_ || (hook_kinds_ & bus_kind_bit(kind)); }
    /// n clocks of the EU's own (no queue read, no bus request of its own). Without a trace,
    /// runs of clocks in which the BIU only counts down are taken in one step (clks_quiet).
    void clks(unsigned n) {
        while (n) {
            if (t_ == TState::Ti && !trace_) {
                // On an idle bus nothing happens until a scheduled prefetch starts: in the clock
                // its delay runs out (at once when none is left), never while the EU claims the bus.
                if (!fetch_sched_ || eu_claim_) {
                    quiet(n);
                    return;
                }
                const unsigned starts = fetch_t1_ > cycle_ ? unsigned(fetch_t1_ - cycle_) : 1;
                if (n < starts) {
                    quiet(n);
                    return;
                }
                quiet(starts - 1);
                n -= starts - 1;
            }
            clk();
            --n;
        }
    }
    /// k idle clocks at once (trace off, bus idle, no prefetch starting within them): the same
    /// state as k calls of clk().
    void quiet(unsigned k) { cycle_ += k; }
    void eu_cycle_untraced(bool last);
    void to_t4();
    void to_last_transfer();
    void wait_queue();
    void record_cycle();
    void bus_start(Bus kind, SegStatus seg, std::uint32_t addr, std::uint16_t data, std::uint8_t width, bool fetch,
                   cycles_t t1);
    [[gnu::always_inline]] inline void start_fetch();
    [[gnu::noinline]] void observe_fetch(const MemRegion* r, const std::uint8_t* p, std::uint16_t d);
    [[gnu::noinline]] void fetch_from_handler(std::uint32_t addr, std::uint8_t width);
    /// One queue read (one clock; reported on the QS lines in the next one). Inline: every
    /// opcode, ModR/M and immediate byte passes here.
    std::uint8_t q_read(QueueOp op) {
        if (q_len_ == 0) wait_queue();
        const std::uint8_t b = q_[q_head_];
        q_head_ = q_head_ == 5 ? 0 : q_head_ + 1;
        --q_len_;
        qop_ = op;
        qbyte_ = b;
        qop_at_ = cycle_;
        // Two free bytes wake an idle BIU; it starts the fetch three clocks after this one. A
        // cycle still before its T2 decision will take the room into account itself.
        if (q_len_ <= 4 && !fetch_sched_ && !fetch_next_) {
            if (t_ == TState::Ti) {
                fetch_sched_ = true;
                fetch_t1_ = cycle_ + 3;
            } else if (t_ != TState::T1 && t_ != TState::T2) {
                fetch_after_t4_ = true; // decided after this cycle's T4
            }
        }
        clk();
        return b;
    }
    /// At the limit of run_until(): the next slice, when the handler chains one.
    bool next_slice() { return handler_ && handler_->next_slice(cycle_, limit_, horizon_); }
    void flush_queue();
    void suspend_fetch();
    void susp();
    void reljmp(std::uint16_t target);
    std::uint16_t eu_bus(Bus kind, SegStatus seg, std::uint32_t addr, std::uint16_t data, unsigned width,
                         bool last);
    unsigned direct_or_handler(Bus kind, std::uint32_t addr, std::uint16_t& data, unsigned width,
                               cycles_t start);
    [[gnu::noinline]] unsigned direct_noted(const MemRegion* r, std::uint8_t* p, bool write, std::uint32_t addr,
                                            std::uint16_t& data, unsigned width, cycles_t start);
    [[gnu::noinline]] unsigned handler_access(Bus kind, std::uint32_t addr, std::uint16_t& data, unsigned width,
                                              cycles_t start);

    // ---- memory operand access (byte-lane splits) ----
    std::uint8_t read8(int seg, std::uint16_t off);
    std::uint16_t read16(int seg, std::uint16_t off);
    void write8(int seg, std::uint16_t off, std::uint8_t v, bool last = false);
    void write16(int seg, std::uint16_t off, std::uint16_t v, bool last = false);
    std::uint16_t in(std::uint16_t port, bool word);
    void out(std::uint16_t port, std::uint16_t v, bool word, bool last);
    void push(std::uint16_t v, bool last = false);
    std::uint16_t pop();

    // ---- EU ----
    // dispatch by instruction group (exec.cpp): one handler per opcode
    using Handler = void (Cpu::*)(std::uint8_t op);
    static std::array<Handler, 256> make_handlers();
    static const std::array<Handler, 256> kHandlers;
    void execute(std::uint8_t op) { (this->*kHandlers[op])(op); }
    void exec_group5(std::uint8_t op);
    void exec_aam(std::uint8_t op);
    void exec_aad(std::uint8_t op);
    // ALU group (ops_alu.cpp)
    void exec_alu(std::uint8_t op);
    void exec_alu_imm(std::uint8_t op);
    void exec_test(std::uint8_t op);
    void exec_incdec_r16(std::uint8_t op);
    void exec_incdec_rm(std::uint8_t op);
    void exec_group3(std::uint8_t op);
    void exec_shift(std::uint8_t op);
    void exec_bcd(std::uint8_t op);
    // moves, stack, I/O, strings (ops_move.cpp)
    void exec_move(std::uint8_t op);
    void exec_stack(std::uint8_t op);
    void exec_io(std::uint8_t op);
    void exec_string(std::uint8_t op);
    void string_element(std::uint8_t op, bool last);
    // control transfer (ops_control.cpp)
    void exec_jump(std::uint8_t op);
    void exec_jump_rm(std::uint8_t op);
    void exec_return(std::uint8_t op);
    void farret();
    // flag operations, HLT, WAIT, SALC, ESC (exec.cpp)
    void exec_misc(std::uint8_t op);
    void decode_modrm();
    void calc_ea();
    std::uint8_t rm_read8();
    std::uint16_t rm_read16();
    void rm_write8(std::uint8_t v, bool last = true);
    void rm_write16(std::uint16_t v, bool last = true);
    std::uint8_t reg8(unsigned n) const { return n < 4 ? r_.r[n] & 0xFF : r_.r[n - 4] >> 8; }
    void set_reg8(unsigned n, std::uint8_t v) {
        if (n < 4) r_.r[n] = (r_.r[n] & 0xFF00) | v;
        else r_.r[n - 4] = (r_.r[n - 4] & 0x00FF) | (v << 8);
    }
    std::uint8_t imm8() {
        ++r_.ip;
        return q_read(QueueOp::subsequent);
    }
    std::uint16_t imm16() {
        r_.ip = static_cast<std::uint16_t>(r_.ip + 2);
        const std::uint16_t lo = q_read(QueueOp::subsequent);
        return static_cast<std::uint16_t>(lo | (q_read(QueueOp::subsequent) << 8));
    }
    int data_seg(int def) const { return seg_override_ >= 0 ? seg_override_ : def; }

    // ALU
    std::uint16_t alu(unsigned op, std::uint16_t a, std::uint16_t b, bool word);
    std::uint16_t shift(unsigned op, std::uint16_t v, unsigned count, bool word);
    void set_szp(std::uint16_t v, bool word);
    void set_flag(std::uint16_t f, bool on) { r_.flags = on ? (r_.flags | f) : (r_.flags & ~f); }
    bool get_flag(std::uint16_t f) const { return r_.flags & f; }
    bool condition(unsigned cc) const;
    // mul/div group (muldiv.cpp)
    void multiply(bool word, bool sign);
    bool divide(bool word, bool sign);
    void aam(std::uint8_t base);
    void aad(std::uint8_t base);

    // control transfer
    void jump_near(std::uint16_t ip);
    void jump_far(std::uint16_t cs, std::uint16_t ip);
    void call_near(std::uint16_t ip);
    void call_far(std::uint16_t cs, std::uint16_t ip);
    void interrupt(std::uint8_t vector, bool hardware_inta = false);
    bool check_interrupts();
    /// A change of IF by the instruction executing now, or by the entry at intr_boundary_.
    void note_if(bool enabled, IfChange::How how, std::uint8_t opcode, std::uint8_t vector = 0);
    void push_if(const IfChange& c) {
        if_ring_[if_count_++ % kIfHistory] = c;
        if (if_hook_) if_hook_(if_hook_ctx_, c);
    }
    void note_held(Bus kind, std::uint32_t addr, cycles_t start, unsigned waits);

    // ---- idle fast-forward (idle.cpp) ----
    /// The state a boundary's future depends on besides memory and the cycle number, packed.
    using Snapshot = std::array<std::uint8_t, 128>;
    Snapshot snapshot() const;
    struct LoopCycle {
        BusRecord rec;          // start: cycle number as recorded
        std::uint16_t sent;     // the data value handed to the handler (reads: as initialised)
        bool handler;           // answered by the BusHandler (else RAM/ROM or open bus)
        cycles_t at;            // cycles() and instructions() when the cycle was asked for (the
        std::uint64_t instructions_at; // handler may suspend the caller there)
    };
    struct LoopWrite {
        std::uint8_t* at;       // a RAM byte the recorded run wrote (at linear address addr) ...
        std::uint32_t addr;
        std::uint8_t before;    // ... and its value before that write
    };
    /// A boundary while recording: the state there, its cycle and instruction count, and the
    /// positions in the logs (ff_log_ / ff_writes_ / ff_reads_). In a learned Loop the same,
    /// relative to the period's start: the points the forwarding can stop at inside a period.
    struct LoopPoint {
        Snapshot state;
        cycles_t cycle;
        std::uint64_t instructions;
        std::size_t cycles_at, writes_at, reads_at;
        std::uint32_t pc;
        // boundaries_ there; in a Loop, relative: the position in Loop::boundaries of the
        // point's boundary (or of the next one the step hook sees, if it sees none here).
        std::uint64_t boundaries;
    };
    struct LoopMark {           // a boundary at the candidate instruction while recording
        Snapshot state;
        cycles_t cycle;
        std::uint64_t instructions;
        std::size_t cycles_at, writes_at, reads_at; // positions in ff_log_ / ff_writes_ / ff_reads_
        std::size_t points_at;                      // ... and in ff_points_
    };
    /// A period found: its bus cycles (start relative to the period's first clock), every
    /// boundary in it (LoopPoint, relative), the RAM it wrote (in order, the value before and
    /// after each write) and read (the value read). It repeats from any later boundary whose
    /// state is that of one of its points, when every RAM byte the period reads before writing
    /// it (counted from that point, around the period) holds the value it read.
    struct Loop {
        bool valid = false;
        cycles_t period = 0;
        std::uint64_t instructions = 0;
        std::vector<LoopCycle> cycles;
        std::vector<LoopPoint> points;          // points[0]: the period's start, offset 0
        std::vector<LoopWrite> writes, reads;
        std::vector<std::uint8_t> written;      // writes[i]'s value
        std::vector<IfChange> if_changes;       // IF changes, cycle and instructions relative
        // The points at which step() calls the step hook (not an interrupt entry), in order:
        // what a forwarding tells the SkipHook it went past.
        std::vector<Boundary> boundaries;
        std::vector<std::pair<std::uint32_t, std::uint32_t>> by_pc; // (pc, point index), sorted
        // Per point, once asked: the RAM bytes read before written from there, with the value
        // read (ff_holds_at); `needs_known` says which lists are filled.
        std::vector<std::vector<LoopWrite>> needs;
        std::vector<bool> needs_known;
        // For the replay: notable[i] is the first cycle at or after i that goes to the handler
        // or is of a kind in notable_kinds (the hook's); the others need no work at all. Empty
        // until the first replay of this loop.
        std::vector<std::uint32_t> notable;
        BusKinds notable_kinds = 0;
    };
    /// At a boundary inside run_until(): the cheap tests, inline; the rest in ff_try_forward()
    /// (a boundary of the learned loop) and ff_boundary() (recording).
    bool ff_visit() {
        if (rep_suspended_) return false; // parked inside a REP run: not an instruction boundary
        const std::uint32_t here = pc();
        const bool backward = here < ff_last_pc_;
        ff_last_pc_ = here;
        if (ff_loop_.valid && (ff_pc_bits_[here >> 6] >> (here & 63) & 1) && ff_try_forward(here)) return true;
        if (!ff_recording_ && !backward) return false;
        return ff_boundary(here, backward);
    }
    bool ff_boundary(std::uint32_t here, bool backward);
    void ff_start();
    bool ff_ram_restored(std::size_t writes_at);
    void ff_learn(const LoopMark& m);
    void ff_drop_loop();
    bool ff_try_forward(std::uint32_t here);
    bool ff_holds_at(std::size_t k);
    bool ff_forward(std::size_t k);
    bool ff_replay(std::size_t from, std::size_t to, cycles_t base, std::uint64_t instructions_base, cycles_t end);
    void ff_apply_writes(std::size_t from, std::size_t to);
    void ff_index_notable();
    void ff_restore(const LoopPoint& p, cycles_t at);
    void ff_reexecute(unsigned delivered);
    void ff_record_point(const Snapshot& s);
    /// Tells the SkipHook that Loop::boundaries [from, to) were passed `times` more times.
    void ff_tell_skipped(std::size_t from, std::size_t to, std::uint64_t times) {
        if (skip_hook_ && to > from && times) skip_hook_(step_hook_ctx_, ff_loop_.boundaries.data() + from, to - from, times);
    }
    /// The forwarding committed the loop's clocks [from, to) of a period that began at `base`
    /// (instructions at instructions_base): the IF changes made there, into the history.
    void ff_replay_if(cycles_t from, cycles_t to, cycles_t base, std::uint64_t instructions_base);
    /// The forwarding landed at a boundary whose previous instruction began at loop point `prev`
    /// of a period that began at `base`: instruction_start() and instruction_cs() from it.
    void ff_landed_after(const LoopPoint& prev, cycles_t base) {
        instr_start_ = base + prev.cycle;
        instr_cs_ = std::uint16_t(((prev.pc - instr_ip_) & 0xFFFFF) >> 4);
    }
    /// The fields of snapshot(), in order, to a packer or from an unpacker (idle.cpp).
    template <class Self, class V> static void state_fields(Self& c, V& v);
    void ff_note_cycle(const BusRecord& r);
    void ff_note_write(std::uint8_t* p, std::uint32_t addr) {
        if (ff_writes_.size() < kFfMaxWrites) ff_writes_.push_back(LoopWrite{p, addr & 0xFFFFF, *p});
        else ff_recording_ = false;
    }
    void ff_note_read(const std::uint8_t* p, std::uint32_t addr) {
        if (ff_reads_.size() < kFfMaxWrites) ff_reads_.push_back(LoopWrite{const_cast<std::uint8_t*>(p), addr & 0xFFFFF, *p});
        else ff_recording_ = false;
    }
    static constexpr std::size_t kFfMaxCycles = 8192, kFfMaxWrites = 8192, kFfMaxMarks = 64;
    static constexpr std::size_t kFfMaxPoints = 16384;
    // Boundaries of the loop's code whose state matches none of its points before the loop is
    // given up (after an interrupt the state comes back to one within a few jumps).
    static constexpr unsigned kFfMaxMisses = 4096;
    static constexpr cycles_t kFfMaxSpan = 32768; // clocks recorded before a candidate is given up

    bool ff_on_ = false;
    bool ff_recording_ = false;
    std::uint32_t ff_pc_ = 0, ff_last_pc_ = 0;
    // Recordings that find no period (a loop interrupted more often than its period, or none)
    // back off, doubling up to kFfMaxBackoff clocks: their logging is pure cost. (65.5 ms at
    // 8 MHz: with three saturated ports a recording every 8.2 ms, the earlier bound, cost 2 %
    // of the run; a loop that becomes idle later is learned at most that much later.)
    static constexpr cycles_t kFfMaxBackoff = 524288;
    bool ff_found_ = true;          // the current/last recording found its period
    cycles_t ff_backoff_ = 0, ff_quiet_until_ = 0;
    std::vector<LoopCycle> ff_log_;
    std::vector<LoopWrite> ff_writes_;
    std::vector<LoopWrite> ff_reads_;         // RAM bytes read (data and code), value as read
    std::vector<IfChange> ff_if_log_;         // IF changes while recording
    std::vector<LoopMark> ff_marks_;
    std::vector<LoopPoint> ff_points_;        // every boundary of the recording
    Loop ff_loop_;
    /// A zeroed array from calloc(), which takes large blocks from pages the kernel maps zeroed
    /// on first touch: the per-address tables below cost only the pages a loop uses, where a
    /// vector's zeroing touched all 4.1 MB at every start (page faults, a part of each short run).
    template <class T>
    struct ZeroedArray {
        std::unique_ptr<T[], void (*)(void*)> p{nullptr, std::free};
        std::size_t n = 0;
        void allocate(std::size_t count) {
            p.reset(static_cast<T*>(std::calloc(count, sizeof(T))));
            if (!p) throw std::bad_alloc();
            n = count;
        }
        void clear() { std::fill(p.get(), p.get() + n, T{}); }
        bool empty() const { return n == 0; }
        T& operator[](std::size_t i) { return p[i]; }
        const T& operator[](std::size_t i) const { return p[i]; }
    };
    ZeroedArray<std::uint64_t> ff_pc_bits_;   // one bit per linear address: a pc of the loop's points
    unsigned ff_misses_ = 0;
    // Where the last forwarding stopped (cycle, instructions, point): a boundary still there has
    // the RAM that point needs (the forwarding made it so, nothing has run since).
    cycles_t ff_landed_cycle_ = ~cycles_t(0);
    std::uint64_t ff_landed_instructions_ = 0;
    std::size_t ff_landed_point_ = 0;
    ZeroedArray<std::uint32_t> ff_seen_;      // per RAM byte: the last check that saw a write to it
    std::uint32_t ff_check_ = 0;
    struct Answer {
        std::uint16_t data;
        unsigned waits;
    };
    std::vector<Answer> ff_answers_;          // handler answers already given, for a re-execution
    std::size_t ff_answer_pos_ = 0;
    unsigned ff_hook_mute_ = 0;               // bus hook calls already made, for a re-execution
    bool via_handler_ = false;                // the last bus cycle went to the BusHandler
    std::uint16_t sent_ = 0;                  // ... with this data value
    cycles_t ff_cycles_ = 0;
    std::uint64_t ff_instructions_ = 0;
    cycles_t horizon_ = ~cycles_t(0);

    // state
    Registers r_;
    MemoryMap mem_;
    // The region covering each whole 4 KB page of the 1 MB space (nullptr: none, or a page that
    // is not covered by one region alone): the direct path's lookup without a search.
    static constexpr unsigned kPageBits = 12;
    std::array<const MemRegion*, ((1u << 20) >> kPageBits)> page_{};
    BusHandler* handler_ = nullptr;
    BusHook hook_ = nullptr;
    BusKinds hook_kinds_ = 0;      // the kinds hook_ is called for (0 without a hook)
    void* hook_ctx_ = nullptr;
    StepHook step_hook_ = nullptr;
    void* step_hook_ctx_ = nullptr;
    bool step_hook_done_ = false; // the hook already saw (and stopped at) the current boundary
    SkipHook skip_hook_ = nullptr;
    // Boundaries at which step() called the step hook (or would have: counted without one), for
    // the fast-forward's points: which of them the hook sees (not an interrupt entry, a HLT).
    std::uint64_t boundaries_ = 0;
    std::vector<CycleRecord>* trace_ = nullptr;

    cycles_t cycle_ = 0;
    std::uint64_t instructions_ = 0;

    // queue: 6 bytes; fetch_ip_ is the offset in CS of the next fetch
    std::uint8_t q_[6] = {};
    unsigned q_head_ = 0, q_len_ = 0;
    std::uint16_t fetch_ip_ = 0;

    // bus state
    TState t_ = TState::Ti;
    BusOp cur_;
    unsigned waits_left_ = 0, cur_waits_ = 0;
    cycles_t cur_start_ = 0;
    std::uint16_t data_bus_ = 0;
    std::uint32_t latch_ = 0;      // address latched by the last ALE
    std::uint16_t eu_data_ = 0;    // value read by the last EU bus cycle
    std::uint64_t rom_writes_ = 0;
    bool fetch_sched_ = false;     // a prefetch is scheduled once the bus is idle ...
    cycles_t fetch_t1_ = 0;        // ... with its T1 not before this clock
    /// Clocks until the scheduled prefetch may begin (its T1), 0 once it may.
    unsigned fetch_delay() const { return fetch_t1_ > cycle_ ? unsigned(fetch_t1_ - cycle_) : 0; }
    bool fetch_next_ = false;      // decided at T2: next fetch follows T4 directly
    bool fetch_after_t4_ = false;  // room appeared in T3/T4: prefetch four clocks after T4
    bool eu_claim_ = false;        // the EU has asked for the bus; no prefetch may start
    bool fetch_suspended_ = false; // EU asked the BIU not to prefetch (e.g. before a flush)
    // The last queue operation (QS1/QS0 and the byte), made in clock qop_at_: reported on the QS
    // lines in the clock after it. last_* hold the lines for the current clock while tracing.
    QueueOp qop_ = QueueOp::idle, last_qop_ = QueueOp::idle;
    std::uint8_t qbyte_ = 0, last_qbyte_ = 0;
    cycles_t qop_at_ = ~cycles_t(0);
    bool last_ale_ = false;
    bool lock_pin_ = false;        // LOCK output: a LOCK-prefixed instruction, or the INTA pair

    // EU decode state
    std::uint8_t opcode_ = 0;       // first byte, read ahead
    std::uint8_t modrm_ = 0;
    unsigned mod_ = 0, reg_ = 0, rm_ = 0;
    std::uint16_t ea_ = 0;
    int ea_seg_ = DS;
    int seg_override_ = -1;
    unsigned rep_ = 0;              // 0, 0xF2 or 0xF3
    bool lock_ = false;
    std::uint16_t instr_ip_ = 0;    // IP of the first prefix of the current instruction
    std::uint16_t instr_cs_ = 0;    // ... its CS
    cycles_t instr_start_ = 0;      // ... and the boundary it began at

    std::array<IfChange, kIfHistory> if_ring_{};      // newest at if_count_ - 1
    std::array<HeldCycle, kHeldHistory> held_ring_{}; // newest at held_count_ - 1
    std::uint64_t if_count_ = 0, held_count_ = 0;
    IfHook if_hook_ = nullptr;
    void* if_hook_ctx_ = nullptr;
    cycles_t intr_boundary_ = 0;
    bool intr_from_halt_ = false, entry_at_boundary_ = false; // (interrupt() from check_interrupts)

    // interrupt inputs and inhibits
    bool intr_ = false, nmi_level_ = false, nmi_pending_ = false;
    bool halted_ = false;
    bool inhibit_ = false;          // no INTR/NMI/TF after this instruction (MOV/POP sreg, STI)
    cycles_t interrupts_enabled_at_ = kNever;
    bool trap_armed_ = false;       // TF was set at the start of this instruction
    bool stop_ = false;
    bool started_ = false;
    bool boundary_pending_ = false; // an instruction boundary precedes the pre-read opcode
    bool rep_interrupted_ = false;  // a REP run stopped for an interrupt (IP at the last prefix)
    bool rep_suspended_ = false;    // a REP run parked at a run_until limit between elements
    cycles_t limit_ = ~cycles_t(0); // the current run_until limit

public:
    std::uint64_t rom_writes() const { return rom_writes_; }
};

} // namespace rcsim::i8086
