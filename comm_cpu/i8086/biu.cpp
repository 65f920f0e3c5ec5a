// rcsim — Intel 8086 bus interface unit: T-states, prefetch queue, EU/prefetch arbitration.
//
// Documentation: Intel 8086 data sheet (231455) "Bus operation" and "Instruction queue";
// timing rules observed on a P80C86A-2 (SingleStepTests 8086 v1, see docs/cpu8086.md):
// - a bus cycle is T1 T2 T3 [Tw...] T4; data moves at the end of T3 or the last Tw;
// - the BIU prefetches a word whenever two queue bytes are free; the decision to run the next
//   prefetch back-to-back is taken in T2 of the current cycle;
// - from an idle bus the BIU needs three clocks to begin a cycle the EU or the queue asked for
//   (four for the EU when a prefetch set-up has begun and its T1 is still two clocks away);
//   an EU request that finds a prefetch in progress starts three clocks after that T4;
// - a queue read is reported on the QS lines in the following clock.
#include "comm_cpu/i8086/cpu.h"
#include "comm_cpu/i8086/microcode.h"

namespace rcsim::i8086 {

const char* to_string(Bus b) {
    static const char* const names[] = {"INTA", "IOR", "IOW", "HALT", "CODE", "MEMR", "MEMW", "PASV"};
    return names[static_cast<unsigned>(b)];
}

const char* to_string(TState t) {
    static const char* const names[] = {"Ti", "T1", "T2", "T3", "Tw", "T4"};
    return names[static_cast<unsigned>(t)];
}

Cpu::Cpu() { reset(); }

void Cpu::map_memory(const MemRegion& region) {
    mem_.add(region);
    // Adding may move the regions: rebuild the whole page table.
    for (std::uint32_t p = 0; p < page_.size(); ++p) {
        const std::uint32_t first = p << kPageBits, last = first + (1u << kPageBits) - 1;
        const MemRegion* r = mem_.find(first);
        page_[p] = r && r->contains(last) ? r : nullptr;
    }
}

void Cpu::reset() {
    r_ = Registers{};
    r_.s[CS] = 0xFFFF;
    r_.ip = 0;
    r_.flags = 0xF002;
    q_head_ = q_len_ = 0;
    fetch_ip_ = r_.ip;
    t_ = TState::Ti;
    cur_ = BusOp{};
    fetch_sched_ = true;
    fetch_t1_ = cycle_;
    fetch_next_ = eu_claim_ = false;
    fetch_suspended_ = fetch_after_t4_ = false;
    qop_ = last_qop_ = QueueOp::idle;
    halted_ = inhibit_ = false;
    lock_pin_ = false;
    nmi_pending_ = false;
    started_ = false;
    ff_recording_ = false;
    // IF = 0 from here (the IF history starts with the reset; a held-cycle history is void).
    if_count_ = held_count_ = 0;
    IfChange c;
    c.cycle = cycle_;
    c.instructions = instructions_;
    c.cs = r_.s[CS];
    c.ip = r_.ip;
    c.how = IfChange::How::reset;
    push_if(c);
    instr_start_ = cycle_;
    instr_cs_ = r_.s[CS];
}

void Cpu::load_state(const Registers& regs, const std::uint8_t* queue, unsigned queue_len) {
    reset();
    r_ = regs;
    r_.flags = static_cast<std::uint16_t>((r_.flags & 0x0FD5) | 0xF002);
    for (unsigned i = 0; i < queue_len && i < 6; ++i) q_[i] = queue[i];
    q_head_ = 0;
    q_len_ = queue_len > 6 ? 6 : queue_len;
    fetch_ip_ = static_cast<std::uint16_t>(r_.ip + q_len_);
    // The queue as filled by the set-up: the BIU idles until a read frees two bytes.
    fetch_sched_ = q_len_ <= 4;
    if_count_ = 0; // how IF came to be what the set-up gives is unknown
    instr_cs_ = r_.s[CS];
}

void Cpu::set_nmi(bool level) {
    if (level != nmi_level_) ff_recording_ = false; // a recorded period holds its inputs constant
    if (level && !nmi_level_) nmi_pending_ = true; // NMI is rising-edge triggered
    nmi_level_ = level;
}

// ---------------------------------------------------------------------------------------------
// One clock.

// A prefetch's T1 in the next clock. The common case, from RAM/ROM by direct pointer, is
// bus_start() without the general path; anything else takes it (fetch_from_handler).
inline void Cpu::start_fetch() {
    const std::uint32_t addr = linear(r_.s[CS], fetch_ip_);
    // The 8086 fetches a word from an even address, a single byte from an odd one.
    const std::uint8_t width = (addr & 1) ? 1 : 2;
    const MemRegion* r = page_[addr >> kPageBits];
    if (__builtin_expect(!r || (width == 2 && !r->contains(addr + 1)), 0)) {
        fetch_from_handler(addr, width);
        return;
    }
    cur_ = BusOp{Bus::code_fetch, SegStatus::CS, addr, 0, width, true, false, false};
    t_ = TState::T1;
    latch_ = addr;
    cur_start_ = cycle_ + 1;
    const std::uint8_t* p = r->data + (addr - r->base);
    const std::uint16_t d = width == 2 ? std::uint16_t(p[0] | (p[1] << 8)) : p[0];
    data_bus_ = width == 2 ? d : std::uint16_t(d << 8); // an odd byte travels on D8-D15
    cur_waits_ = waits_left_ = r->wait_states;
    via_handler_ = false;
    if (observed(Bus::code_fetch)) observe_fetch(r, p, d);
}

// The T4 clock: fetched bytes enter the queue, then the next cycle is decided (clk() in
// i8086.h runs the simple transitions inline).
void Cpu::clk_t4() {
    if (cur_.fetch && !cur_.discard) {
        // The fetched bytes enter the queue at the end of T4.
        unsigned tail = q_head_ + q_len_;
        if (tail >= 6) tail -= 6;
        if (cur_.width == 2) {
            q_[tail] = data_bus_ & 0xFF;
            q_[tail == 5 ? 0 : tail + 1] = data_bus_ >> 8;
            q_len_ += 2;
        } else {
            q_[tail] = data_bus_ >> 8; // odd address: high lane
            q_len_ += 1;
        }
        fetch_ip_ = static_cast<std::uint16_t>(fetch_ip_ + cur_.width);
    }
    t_ = TState::Ti;
    cur_.kind = Bus::passive;
    if (fetch_next_ && !eu_claim_ && !fetch_suspended_ && q_len_ <= 4) {
        fetch_next_ = false;
        fetch_sched_ = false;
        fetch_after_t4_ = false;
        start_fetch();
    } else if (fetch_after_t4_) {
        // Room appeared in T3/T4 of this cycle: the prefetch starts four clocks after T4.
        fetch_after_t4_ = false;
        fetch_sched_ = true;
        fetch_t1_ = cycle_ + 4;
    } else if (fetch_sched_ && !eu_claim_ && cycle_ + 1 >= fetch_t1_) {
        fetch_tick(); // one scheduled earlier (a flush during this cycle) is due now
    }
    fetch_next_ = false;
}

// A prefetch scheduled once the bus is idle: it begins at the end of the clock before its T1
// (fetch_t1_), never while the EU claims the bus.
void Cpu::fetch_tick() {
    if (eu_claim_ || cycle_ + 1 < fetch_t1_) return;
    fetch_sched_ = false;
    if (!fetch_suspended_ && q_len_ <= 4) start_fetch();
}

void Cpu::record_cycle() {
    CycleRecord c{};
    c.t = t_;
    c.ale = t_ == TState::T1;
    c.address_latch = latch_;
    const bool busy = t_ != TState::Ti;
    c.segment = (busy && t_ != TState::T1) ? cur_.seg : SegStatus::none;
    c.status = (t_ == TState::T1 || t_ == TState::T2) ? cur_.kind : Bus::passive;
    const bool active = t_ == TState::T2 || t_ == TState::T3 || t_ == TState::Tw;
    const bool rd = cur_.kind == Bus::mem_read || cur_.kind == Bus::code_fetch;
    c.mem_read = active && rd;
    c.mem_write = active && cur_.kind == Bus::mem_write;
    c.io_read = active && cur_.kind == Bus::io_read;
    c.io_write = active && cur_.kind == Bus::io_write;
    c.bhe = busy && (cur_.width == 2 || (cur_.addr & 1));
    c.transfer = (t_ == TState::T3 || t_ == TState::Tw) && waits_left_ == 0;
    c.data = c.transfer ? data_bus_ : 0;
    c.qop = last_qop_;
    c.qbyte = last_qop_ == QueueOp::idle ? 0 : last_qbyte_;
    c.lock = lock_pin_;
    trace_->push_back(c);
}

// ---------------------------------------------------------------------------------------------
// Bus cycles.

// The device of a bus cycle: RAM/ROM by direct pointer (inline: the common case), anything
// else through the BusHandler. Its Tw count.
inline unsigned Cpu::direct_or_handler(Bus kind, std::uint32_t addr, std::uint16_t& data, unsigned width,
                                       cycles_t start) {
    const bool write = kind == Bus::mem_write;
    via_handler_ = false;
    if (kind == Bus::mem_read || kind == Bus::code_fetch || write) {
        const MemRegion* r = page_[addr >> kPageBits];
        if (!r) r = mem_.find(addr);
        if (r && (width == 1 || r->contains(addr + 1))) {
            std::uint8_t* p = r->data + (addr - r->base);
            if (__builtin_expect(ff_recording_ || (write && !r->writable), 0))
                return direct_noted(r, p, write, addr, data, width, start);
            if (write) {
                p[0] = data & 0xFF;
                if (width == 2) p[1] = data >> 8;
            } else {
                data = width == 2 ? std::uint16_t(p[0] | (p[1] << 8)) : p[0];
            }
            return r->wait_states;
        }
    }
    return handler_access(kind, addr, data, width, start);
}

// A direct access the fast-forward records, or a write into ROM (dropped, counted, logged).
unsigned Cpu::direct_noted(const MemRegion* r, std::uint8_t* p, bool write, std::uint32_t addr,
                           std::uint16_t& data, unsigned width, cycles_t start) {
    if (write) {
        if (r->writable) {
            if (ff_recording_) {
                ff_note_write(p, addr);
                if (width == 2) ff_note_write(p + 1, addr + 1);
            }
            p[0] = data & 0xFF;
            if (width == 2) p[1] = data >> 8;
        } else {
            ++rom_writes_;
            ff_recording_ = false; // a side effect the fast-forward does not replay
            if (handler_) handler_->write_ignored(addr, width, start);
        }
    } else {
        data = width == 2 ? std::uint16_t(p[0] | (p[1] << 8)) : p[0];
        if (ff_recording_ && r->writable) {
            ff_note_read(p, addr);
            if (width == 2) ff_note_read(p + 1, addr + 1);
        }
    }
    return r->wait_states;
}

// I/O, INTA, memory outside the direct map: the BusHandler (open bus without one).
unsigned Cpu::handler_access(Bus kind, std::uint32_t addr, std::uint16_t& data, unsigned width, cycles_t start) {
    const bool write = kind == Bus::mem_write;
    if (handler_) {
        via_handler_ = true;
        sent_ = data;
        if (ff_answer_pos_ < ff_answers_.size()) {
            // Re-executing a fast-forward period that diverged: this access has been made.
            const Answer& a = ff_answers_[ff_answer_pos_++];
            if (!write && kind != Bus::io_write) data = a.data;
            return a.waits; // (noted when it was made: ff_replay)
        }
        const unsigned waits = handler_->bus_access(kind, addr, data, width, start);
        if (waits) note_held(kind, addr, start, waits);
        return waits;
    }
    if (!write && kind != Bus::io_write) data = 0xFFFF; // open bus
    return 0;
}

// Begins T1 of a bus cycle in the next clock: the device is asked now (start cycle = this
// clock), so its wait states are known before T3. The cycle comes as scalars, not as a BusOp
// the caller builds: a struct written with narrow stores and read back whole at once stalls
// the load (store forwarding), which was half of this function's time.
void Cpu::bus_start(Bus kind, SegStatus seg, std::uint32_t addr, std::uint16_t data, std::uint8_t width, bool fetch,
                    cycles_t t1) {
    cur_.kind = kind;
    cur_.seg = seg;
    cur_.addr = addr;
    cur_.data = data;
    cur_.width = width;
    cur_.fetch = fetch;
    cur_.discard = false;
    cur_.inta_first = kind == Bus::int_ack && !lock_pin_; // the second INTA finds LOCK active
    t_ = TState::T1;
    latch_ = addr;
    cur_start_ = t1;
    std::uint16_t d = data;
    cur_waits_ = waits_left_ = direct_or_handler(kind, addr, d, width, t1);
    // A byte on the odd lane travels on D8-D15.
    if (kind == Bus::mem_write || kind == Bus::io_write) {
        data_bus_ = width == 1 && (addr & 1) ? std::uint16_t(data << 8) : data;
    } else if (width == 1 && (addr & 1)) {
        data_bus_ = std::uint16_t((d & 0xFF) << 8);
    } else {
        data_bus_ = d;
    }
    if (kind != Bus::code_fetch) eu_data_ = d;
    if (observed(kind)) observe(BusRecord{kind, addr, d, width, cur_waits_, cur_start_});
}

// The observers of a direct prefetch (out of line: most runs have none).
void Cpu::observe_fetch(const MemRegion* r, const std::uint8_t* p, std::uint16_t d) {
    if (ff_recording_ && r->writable) { // code in RAM: the loop depends on it
        ff_note_read(p, cur_.addr);
        if (cur_.width == 2) ff_note_read(p + 1, cur_.addr + 1);
    }
    observe(BusRecord{Bus::code_fetch, cur_.addr, d, cur_.width, cur_waits_, cur_start_});
}

void Cpu::fetch_from_handler(std::uint32_t addr, std::uint8_t width) {
    bus_start(Bus::code_fetch, SegStatus::CS, addr, 0, width, true, cycle_ + 1); // T1 is the next clock
}

std::uint16_t Cpu::eu_bus(Bus kind, SegStatus seg, std::uint32_t addr, std::uint16_t data, unsigned width,
                          bool last) {
    eu_claim_ = true;
    if (t_ == TState::T4 && !cur_.fetch) {
        clk(); // our own previous cycle ends: the next one follows its T4 directly
    } else {
        // Three clocks from the request to T1 on an idle bus (a scheduled prefetch waits). A
        // prefetch on the bus runs to its T4: a request seen by its T2 decision follows T4
        // directly, a later one starts three clocks after T4.
        if (t_ == TState::Ti) {
            // A prefetch the BIU has already begun to set up (its T1 still two clocks away)
            // costs the EU one more clock; one about to start (T1 next clock) simply waits.
            clks(fetch_sched_ && fetch_delay() >= 2 ? 4 : 3);
        } else {
            const bool early = t_ == TState::T1 || t_ == TState::T2;
            to_t4();
            clks(early ? 1 : 3);
        }
    }
    bus_start(kind, seg, addr, data, static_cast<std::uint8_t>(width), false, cycle_);
    eu_claim_ = false;
    if (!trace_) {
        eu_cycle_untraced(last);
        return eu_data_;
    }
    clk(); // T1
    clk(); // T2
    if (last) {
        to_last_transfer(); // return on T3 / the last Tw: the next clock moves the data
        return eu_data_;
    }
    to_t4();
    return eu_data_;
}

// ---------------------------------------------------------------------------------------------
// Runs of clocks in which only the BIU moves (the EU waits for the bus or the queue). With a
// trace every clock is recorded; without one the T-states are advanced in one step, to the
// state the same clocks one by one would leave (tests/comm_cpu/i8086/sst_trace_skip_test.cpp).

// The clocks of an EU bus cycle from its T1 without a trace, in one step: the same state as
// clk() T1, clk() T2, then to_last_transfer() or to_t4(). In T1 and T2 only LOCK (INTA) and
// the T2 prefetch decision happen (the EU claim is released, this is no prefetch); a prefetch
// scheduled meanwhile cannot start on a busy bus.
void Cpu::eu_cycle_untraced(bool last) {
    if (cur_.kind == Bus::int_ack) lock_pin_ = cur_.inta_first;
    fetch_next_ = !fetch_suspended_ && q_len_ <= 4;
    if (last) {
        t_ = waits_left_ ? TState::Tw : TState::T3;
        cycle_ += 2 + waits_left_;
    } else {
        t_ = TState::T4;
        cycle_ += 3 + waits_left_;
    }
    waits_left_ = 0;
}

// From T1, T2, T3 or Tw to T4 of the cycle on the bus (T4 itself not yet clocked).
void Cpu::to_t4() {
    if (trace_) {
        while (t_ != TState::T4) clk();
        return;
    }
    if (t_ == TState::T4) return;
    if (t_ == TState::T1) clk();
    if (t_ == TState::T2) clk();
    // T3 and every Tw: a clock each, none of them Ti, so a scheduled prefetch only counts down.
    const unsigned rest = waits_left_ + 1;
    waits_left_ = 0;
    t_ = TState::T4;
    quiet(rest);
}

// From T2 (just clocked) to the clock before the transfer: T3, or the last Tw.
void Cpu::to_last_transfer() {
    if (trace_ || waits_left_ == 0) {
        while (waits_left_) clk();
        return;
    }
    const unsigned k = waits_left_;
    waits_left_ = 0;
    t_ = TState::Tw;
    quiet(k);
}

// The EU needs a queue byte and there is none: clocks until a prefetch delivers one.
void Cpu::wait_queue() {
    while (q_len_ == 0) {
        if (!trace_) {
            if (t_ == TState::Ti && fetch_sched_ && !eu_claim_ && fetch_delay() > 1) quiet(fetch_delay() - 1);
            else if (t_ != TState::Ti && t_ != TState::T4) to_t4();
        }
        clk();
    }
}

// ---------------------------------------------------------------------------------------------
// Queue.

void Cpu::flush_queue() {
    if (t_ != TState::Ti && cur_.fetch) cur_.discard = true; // its bytes belong to the old stream
    q_head_ = q_len_ = 0;
    fetch_ip_ = r_.ip;
    qop_ = QueueOp::flush;
    qop_at_ = cycle_;
    fetch_suspended_ = false;
    fetch_next_ = false;
    fetch_after_t4_ = false;
    fetch_sched_ = true;
    fetch_t1_ = cycle_ + 3;
}

void Cpu::suspend_fetch() {
    fetch_suspended_ = true;
    fetch_after_t4_ = false;
    fetch_next_ = false;
    fetch_sched_ = false;
}

// The SUSP micro-instruction: prefetching stops; a bus cycle in progress runs to its T4 and
// the micro-instruction completes in that clock (one clock when the bus is idle).
void Cpu::susp() {
    suspend_fetch();
    if (t_ != TState::Ti && t_ != TState::T4) to_t4();
    clk(kSuspLine);
}

// The RELJMP tail shared by the near jumps: SUSP (0D2), CORR (0D3) and the addition (0D4), then
// the queue flush (0D5), reported in the following clock. CALL rel16 runs the same lines at
// 07E-081.
void Cpu::reljmp(std::uint16_t target) {
    susp();
    clks(kCorr + kReljmpAdd);
    r_.ip = target;
    flush_queue();
    clk(kFlushLine);
}

} // namespace rcsim::i8086
