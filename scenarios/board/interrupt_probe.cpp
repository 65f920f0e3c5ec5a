#include "scenarios/board/interrupt_probe.h"

#include "comm_cpu/cpu8086.h"
#include "comm_cpu/i8086/disasm.h"

#include <algorithm>

namespace rcsim {

using i8086::Bus;
using i8086::BusRecord;

double InterruptRecord::latency_us() const { return to_us(first_isr - ir_rise); }
double InterruptRecord::service_us() const { return to_us(iret_done - first_isr); }
double InterruptRecord::blocking_us() const { return to_us(blocking); }

InterruptProbe::InterruptProbe(sc_core::sc_module_name name, Cpu8086& cpu, std::vector<IrqLine*> ir,
                               std::uint16_t pic_io_base, std::uint32_t dpram_base,
                               std::uint32_t dpram_data_size)
    : sc_module(name), cpu_(cpu), ir_(std::move(ir)), pic_io_base_(pic_io_base), dpram_base_(dpram_base),
      dpram_size_(dpram_data_size) {
    SC_METHOD(sample_lines);
    for (IrqLine* line : ir_) sensitive << line->value_changed_event();
    dont_initialize();
    cpu_.set_bus_observer(&InterruptProbe::bus_hook, this, watched_);
    cpu_.core().set_if_hook(&InterruptProbe::if_hook, this);
}

void InterruptProbe::if_hook(void* self, const i8086::IfChange& c) {
    auto* probe = static_cast<InterruptProbe*>(self);
    probe->if_clock_.change(probe->cpu_.time_of(c.cycle), c.enabled);
}

void InterruptProbe::IfClock::change(const sc_core::sc_time& at, bool enabled) {
    // A change stamped before the last one (a fast-forward replays a loop's changes after its
    // bus cycles) counts from the last: the running total never goes back.
    const sc_core::sc_time t = std::max(at, last);
    prev = last;
    prev_off = off;
    prev_total = total;
    if (off) total += t - last;
    last = t;
    off = !enabled;
}

sc_core::sc_time InterruptProbe::IfClock::off_until(const sc_core::sc_time& t) const {
    if (t >= last) return off ? total + (t - last) : total;
    // Asked for a time just before the last change (a window that ends at a cycle the core
    // has already run past): the change before it still holds there.
    if (t >= prev) return prev_off ? prev_total + (t - prev) : prev_total;
    return prev_total;
}

void InterruptProbe::watch_kinds() {
    using i8086::bus_kind_bit;
    i8086::BusKinds kinds = bus_kind_bit(Bus::int_ack) | bus_kind_bit(Bus::mem_write);
    if (forward_) {
        kinds = i8086::kAllBusKinds;
    } else if (!stack_.empty()) {
        // Inside an interrupt every kind but code fetches; those only until the handler's first
        // fetch and once the return IP is popped (the fetch at the return address closes it).
        const Open& top = stack_.back();
        kinds = i8086::kAllBusKinds;
        if (top.entered && !top.popped) kinds &= ~bus_kind_bit(Bus::code_fetch);
    }
    if (kinds != watched_) {
        watched_ = kinds;
        cpu_.set_bus_observer_kinds(kinds);
    }
}

void InterruptProbe::sample_lines() {
    for (std::size_t level = 0; level < ir_.size() && level < 8; ++level) {
        const bool now = ir_[level]->read();
        if (now && !last_level_[level] && !rise_pending_[level]) {
            rise_[level] = sc_core::sc_time_stamp();
            rise_pending_[level] = true;
            track_[level].open(rise_[level], pic_ ? pic_->hold(unsigned(level)) : Pic8259::Hold{});
        }
        // A request that goes away before its INTA is not served (the 8259A needs IR high until
        // the first INTA): the next interrupt of this level belongs to a later rise.
        if (!now) {
            rise_pending_[level] = false;
            track_[level].close();
        }
        last_level_[level] = now;
    }
}

void InterruptProbe::bus_hook(void* self, const BusRecord& r) {
    auto* probe = static_cast<InterruptProbe*>(self);
    if (probe->forward_) probe->forward_(probe->forward_ctx_, r);
    probe->on_cycle(r);
    probe->watch_kinds(); // the cycle may have opened, entered, popped or closed an interrupt
}

void InterruptProbe::on_cycle(const BusRecord& r) {
    const bool dpram_write = r.kind == Bus::mem_write && r.address - dpram_base_ < 0x400;
    // Outside interrupts only INTA and DP-RAM writes matter: skip the rest cheaply.
    if (stack_.empty() && r.kind != Bus::int_ack && !dpram_write) return;
    // The cycle's time only where a record takes it (most cycles of a handler just count).
    if (r.kind == Bus::int_ack) {
        on_inta(r, cpu_.time_of(r.start));
    } else if (!stack_.empty()) {
        Open& top = stack_.back();
        // The entry's pushes may straddle the first handler fetch: the 8086 flushes the queue to the
        // new CS:IP between pushing CS and pushing IP (FARCALL microcode), so the BIU can fetch at the
        // handler before the return IP is written. Until all three pushes are seen, entry cycles
        // are matched even after the handler was entered.
        const bool entry_cycle = (!top.entered || top.pushes < 3) && on_entry_cycle(top, r);
        if (!entry_cycle && top.entered) on_handler_cycle(r);
    }
    if (dpram_write && on_dpram_write) on_dpram_write(r, cpu_.time_of(r.start));
}

void InterruptProbe::on_inta(const BusRecord& r, const sc_core::sc_time& t) {
    // The two INTA cycles are back to back: a second one completes the entry opened by the first.
    if (!stack_.empty() && !stack_.back().entered && stack_.back().rec.inta2 == sc_core::SC_ZERO_TIME &&
        stack_.back().rec.inta1 != t) {
        InterruptRecord& rec = stack_.back().rec;
        rec.inta2 = t;
        rec.vector = static_cast<std::uint8_t>(r.data & 0xFF);
        rec.level = rec.vector & 7;
        rec.boundary_cycle = cpu_.core().interrupt_boundary();
        stack_.back().begin_if_off = if_clock_.off_until(cpu_.time_of(rec.boundary_cycle));
        if (rise_pending_[rec.level]) {
            rec.ir_rise = rise_[rec.level];
            rec.has_rise = true;
            rise_pending_[rec.level] = false;
            // Interrupts are enabled by now (this is their acknowledge): was the request older?
            rec.startup = rec.ir_rise < cpu_.time_of(cpu_.core().interrupts_enabled_at());
            rec.cause = explain_latency(track_[rec.level], rec.ir_rise, cpu_);
            track_[rec.level].close();
        }
        return;
    }
    // A handler whose IRET has already popped its return address is finished even though the
    // interrupted code never ran again: the CPU took the next pending interrupt at the boundary
    // right after the IRET (the new entry pushes the same return address). Its IRET completed
    // at that boundary, the T1 of this INTA.
    while (!stack_.empty() && stack_.back().entered && stack_.back().popped) close_top(t);
    Open o;
    o.rec.inta1 = t;
    o.rec.depth = static_cast<unsigned>(stack_.size());
    stack_.push_back(o);
}

std::string source_name(unsigned level) {
    if (level < 3) return "rs232_" + std::to_string(level);
    if (level == 3) return "dpram";
    return "ir" + std::to_string(level);
}

double exact_us(const sc_core::sc_time& t) {
    // sc_time is an integer count of picoseconds: value() / 1e6 keeps every digit.
    return sc_core::sc_get_time_resolution() == sc_core::sc_time(1, sc_core::SC_PS)
               ? static_cast<double>(t.value()) / 1e6
               : t.to_seconds() * 1e6;
}

std::optional<sc_core::sc_time> InterruptProbe::interrupts_enabled() const {
    const i8086::cycles_t at = cpu_.core().interrupts_enabled_at();
    if (at == i8086::Cpu::kNever) return std::nullopt;
    return cpu_.time_of(at);
}

void InterruptProbe::close_top(const sc_core::sc_time& iret_done) {
    const Open o = stack_.back();
    InterruptRecord rec = o.rec;
    stack_.pop_back();
    rec.iret_done = iret_done;
    rec.done = true;
    rec.ret_cs = o.ret_cs;
    rec.ret_ip = o.ret_ip;
    if (rec.path_len == 0 && o.entered) { // no write while blocking: its handler at least ran
        rec.path[0] = rec.handler;
        rec.path_len = 1;
    }
    // Blocking: all of the service up to its EOI (its level in service), IF = 0 after it; the
    // nested services' own windows taken out of each part.
    const sc_core::sc_time if_off_end = if_clock_.off_until(iret_done);
    if (rec.has_eoi && rec.eoi < iret_done) {
        rec.blocking = (rec.eoi - rec.first_isr) - o.nested_before_eoi;
        const sc_core::sc_time after = if_off_end - o.eoi_if_off;
        if (after > o.nested_if_off) rec.blocking += after - o.nested_if_off;
    } else {
        rec.blocking = (iret_done - rec.first_isr) - o.nested_before_eoi;
    }
    if (!stack_.empty()) { // nested: its window [boundary, iret_done] is not its parent's
        Open& parent = stack_.back();
        const sc_core::sc_time from = cpu_.time_of(rec.boundary_cycle);
        if (!parent.rec.has_eoi) parent.nested_before_eoi += iret_done - from;
        else parent.nested_if_off += if_off_end - o.begin_if_off;
    }
    recent_[recent_n_++ % kRecent] = rec;
    const unsigned level = rec.level & 7;
    if (rec.startup) {
        startup_.push_back(rec);
    } else {
        blocking_[level].add(rec.blocking_us());
        if (!longest_[level].done || rec.blocking > longest_[level].blocking) longest_[level] = rec;
        ++count_[level];
        if (rec.has_rise) {
            latency_[level].add(rec.latency_us());
            worst_[level].add(rec);
        }
        service_[level].add(rec.service_us());
    }
    if (keep_) done_.push_back(rec);
    held_.push_back(rec);
    // Back in the main program: everything entered so far has completed.
    if (stack_.empty()) hand_over(start_horizon());
}

void InterruptProbe::hand_over(const sc_core::sc_time& horizon) {
    // Nested records completed before the one they interrupted: entry order is by first INTA.
    std::sort(held_.begin(), held_.end(),
              [](const InterruptRecord& a, const InterruptRecord& b) { return a.inta1 < b.inta1; });
    if (on_record)
        for (const InterruptRecord& r : held_) on_record(r);
    held_.clear();
    if (on_settled) on_settled(horizon);
}

sc_core::sc_time InterruptProbe::start_horizon() const {
    // A later record is entered after now (its INTA is still to come, at or after the kernel's
    // time) and starts at that INTA or at its IR rise: one pending now, or one still to come.
    sc_core::sc_time h = sc_core::sc_time_stamp();
    for (const Open& o : stack_) h = std::min(h, o.rec.has_rise ? o.rec.ir_rise : o.rec.inta1);
    for (std::size_t level = 0; level < 8; ++level)
        if (rise_pending_[level]) h = std::min(h, rise_[level]);
    return h;
}

void InterruptProbe::flush() { hand_over(sc_core::sc_max_time()); }

bool InterruptProbe::on_entry_cycle(Open& o, const BusRecord& r) {
    if (o.rec.inta2 == sc_core::SC_ZERO_TIME) return false;
    const std::uint32_t ivt = o.rec.vector * 4u;
    if (r.kind == Bus::mem_read && o.ivt_reads < 2 && (r.address == ivt || r.address == ivt + 2)) {
        (r.address == ivt ? o.new_ip : o.new_cs) = r.data;
        ++o.ivt_reads;
        return true;
    }
    if (r.kind == Bus::mem_write && o.ivt_reads == 2 && o.pushes < 3) {
        // Pushes in order FLAGS, CS, IP. With an odd SP each word is two byte cycles, low byte
        // first at the word's address (the firmware's C code can leave SP odd).
        std::uint16_t word = r.data;
        std::uint32_t at = r.address;
        if (r.width == 1) {
            if (!o.half_pending) {
                o.half_pending = true;
                o.half_address = r.address;
                o.half_low = static_cast<std::uint8_t>(r.data);
                return true;
            }
            o.half_pending = false;
            at = o.half_address;
            word = static_cast<std::uint16_t>((r.data & 0xFF) << 8 | o.half_low);
        }
        if (o.pushes == 1) o.ret_cs = word;
        if (o.pushes == 2) {
            o.ret_ip = word;
            o.ip_slot = at;
        }
        ++o.pushes;
        if (o.pushes == 3 && o.entered && o.rec.has_rise) name_holder(o); // the first fetch came first
        return true;
    }
    if (r.kind == Bus::code_fetch && o.ivt_reads == 2 && !o.entered) {
        const std::uint32_t handler = ((std::uint32_t(o.new_cs) << 4) + o.new_ip) & 0xFFFFF;
        if (r.address == handler || r.address == (handler & ~1u)) {
            o.entered = true;
            o.rec.handler = handler;
            o.rec.first_isr = cpu_.time_of(r.start + 4 + r.wait_states);
            if (fifo_level && o.rec.level < 3) o.rec.rx_fifo_level = fifo_level(o.rec.level);
            if (o.rec.has_rise) {
                finish_latency_cause(o.rec.cause, o.rec.ir_rise, o.rec.first_isr, cpu_, dpram_base_, 0x400);
                if (o.pushes == 3) name_holder(o); // else at the last push, below
            }
            return true;
        }
    }
    return false;
}

void InterruptProbe::on_handler_cycle(const BusRecord& r) {
    Open& o = stack_.back();
    if (!o.entered) return;
    switch (r.kind) {
    case Bus::io_write:
        // OCW2 (A0=0, D4:D3 = 00) with the EOI bit (D5) set.
        if (r.address == pic_io_base_ && (r.data & 0x18) == 0 && (r.data & 0x20) && !o.rec.has_eoi) {
            o.rec.eoi = cpu_.time_of(r.start);
            o.rec.has_eoi = true;
            o.eoi_if_off = if_clock_.off_until(o.rec.eoi);
        }
        break;
    case Bus::mem_read:
        if (r.address - dpram_base_ < dpram_size_) o.rec.dpram_reads += r.width;
        if (r.address == o.ip_slot && o.pushes == 3) o.popped = true; // IRET pops the return IP
        break;
    case Bus::mem_write:
        if (r.address - dpram_base_ < dpram_size_) o.rec.dpram_writes += r.width;
        // Blocking now (IF = 0, or no EOI yet): a write deeper in the stack than any before may
        // come from a deeper routine.
        if (!(cpu_.core().regs().flags & i8086::flag::IF) || !o.rec.has_eoi) sample_path(o, r);
        break;
    case Bus::code_fetch: {
        const std::uint32_t ret = ((std::uint32_t(o.ret_cs) << 4) + o.ret_ip) & 0xFFFFF;
        if (o.popped && (r.address == ret || r.address == (ret & ~1u))) close_top(cpu_.time_of(r.start));
        break;
    }
    default:
        break;
    }
}

void InterruptProbe::watch_pic(Pic8259& pic) {
    pic_ = &pic;
    pic.on_update = [this] { pic_update(); };
}

// The chip's state changed: every request still waiting may be held otherwise now.
void InterruptProbe::pic_update() {
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    for (unsigned level = 0; level < 8; ++level)
        if (track_[level].is_open()) track_[level].update(now, pic_->hold(level));
}

void WorstLatencies::add(const InterruptRecord& r) {
    if (!r.has_rise) return;
    const sc_core::sc_time latency = r.first_isr - r.ir_rise;
    const auto longer = [](const sc_core::sc_time& l, const InterruptRecord& k) { return l > k.first_isr - k.ir_rise; };
    if (kept_.size() >= keep_ && !longer(latency, kept_.back())) return;
    kept_.insert(std::upper_bound(kept_.begin(), kept_.end(), latency,
                                  [&](const sc_core::sc_time& l, const InterruptRecord& k) { return longer(l, k); }),
                 r);
    if (kept_.size() > keep_) kept_.pop_back();
}

std::vector<const InterruptRecord*> InterruptProbe::of_level(unsigned level) const {
    std::vector<const InterruptRecord*> out;
    for (const auto& r : done_)
        if (r.level == level) out.push_back(&r);
    return out;
}

// ---------------------------------------------------------------------------------------------
// Call paths, read off the stack: a word is a return address when the bytes before the code it
// points at decode as a CALL (near: E8, FF /2; far: 9A, FF /3) that ends exactly there.

namespace {

using i8086::Flow;

// Whether a CALL of kind `flow` ends at cs:ip. `*inside` gets an address inside the routine it
// called: its target for a direct call (E8, 9A), else 0 (the bytes do not name it).
/// `n` bytes at `linear` where the CPU maps memory directly (RAM, ROM), or nullptr: the probe
/// reads code and stack there without a copy (the walks run on every blocking service).
const std::uint8_t* mapped(Cpu8086& cpu, std::uint32_t linear, unsigned n) {
    const MemRegion* r = cpu.core().memory().find(linear);
    if (!r || !r->contains(linear + n - 1)) return nullptr;
    return r->data + (linear - r->base);
}

bool call_ending_at(Cpu8086& cpu, std::uint16_t cs, std::uint16_t ip, Flow flow, std::uint32_t* inside) {
    constexpr unsigned kBack = i8086::kLongestInstruction + 1;
    if (ip < 2) return false;
    const unsigned back = ip < kBack ? ip : kBack;
    // Code runs from memory the CPU maps directly: a word that points elsewhere is data.
    const std::uint8_t* before = mapped(cpu, i8086::Cpu::linear(cs, static_cast<std::uint16_t>(ip - back)), back);
    if (!before) return false;
    for (unsigned len = 2; len <= back; ++len) {
        const std::uint8_t* b = before + (back - len);
        // Only a CALL's opcode (E8, 9A, FF) or a segment prefix can begin one: the common case,
        // a data word, is turned away without decoding.
        const std::uint8_t first = b[0];
        if (first != 0xE8 && first != 0x9A && first != 0xFF && first != 0x26 && first != 0x2E && first != 0x36 &&
            first != 0x3E)
            continue;
        const i8086::Decoded d = i8086::decode(b, len);
        if (d.length != len || d.flow != flow) continue;
        const std::uint8_t* op = b + d.prefixes;
        *inside = 0;
        if (d.opcode == 0xE8)
            *inside = i8086::Cpu::linear(cs, static_cast<std::uint16_t>(ip + (op[1] | op[2] << 8)));
        else if (d.opcode == 0x9A)
            *inside = i8086::Cpu::linear(static_cast<std::uint16_t>(op[3] | op[4] << 8),
                                         static_cast<std::uint16_t>(op[1] | op[2] << 8));
        return true;
    }
    return false;
}

} // namespace

unsigned InterruptProbe::walk_stack(std::uint32_t from, std::uint32_t to, std::uint16_t cs, std::uint32_t skip,
                                    std::uint32_t here, std::uint32_t* out, unsigned max) {
    // Upward from the top of the stack (the deepest call first), reversed at the end.
    struct Call {
        std::uint32_t ret, inside;
    };
    std::array<Call, 2 * InterruptRecord::kMaxPath> calls{};
    unsigned n = 0;
    const auto word = [&](std::uint32_t a, std::uint16_t* w) {
        std::uint8_t b[2];
        if (a == skip || a + 1 == skip) return false;
        if (const std::uint8_t* m = mapped(cpu_, a, 2)) *w = static_cast<std::uint16_t>(m[0] | m[1] << 8);
        else if (cpu_.debug_read(a, b, 2)) *w = static_cast<std::uint16_t>(b[0] | b[1] << 8);
        else return false;
        return true;
    };
    for (std::uint32_t a = from; a + 2 <= to && n < calls.size(); a += 2) {
        std::uint16_t ip = 0, seg = 0;
        if (!word(a, &ip)) continue;
        std::uint32_t inside = 0;
        if (a + 4 <= to && word(a + 2, &seg) && call_ending_at(cpu_, seg, ip, Flow::call_far, &inside)) {
            calls[n++] = {i8086::Cpu::linear(seg, ip), inside};
            a += 2; // its CS
        } else if (call_ending_at(cpu_, cs, ip, Flow::call_near, &inside)) {
            calls[n++] = {i8086::Cpu::linear(cs, ip), inside};
        }
    }
    // A chain of frames: the routine a direct call entered holds the code that runs inside it
    // (the next return address inward, or `here` for the deepest), so it starts at or before that
    // code. A word that breaks the chain is stale data that only looks like a return address
    // (left above the stack's top, or a local): dropped.
    unsigned kept = 0;
    std::uint32_t inner = here;
    for (unsigned k = 0; k < n; ++k) {
        if (calls[k].inside && calls[k].inside > inner) continue;
        calls[kept++] = calls[k];
        inner = calls[k].ret;
    }
    // Outermost first: each call names the routine it called (its target), or, for an indirect
    // call, the next return address inward (inside that routine) or `here`.
    unsigned m = 0;
    for (unsigned k = kept; k-- > 0 && m < max;) {
        if (calls[k].inside) out[m++] = calls[k].inside;
        else out[m++] = k > 0 ? calls[k - 1].ret : here;
    }
    return m;
}

void InterruptProbe::sample_path(Open& o, const BusRecord& r) {
    const i8086::Cpu& core = cpu_.core();
    const i8086::Registers& regs = core.regs();
    std::uint32_t sp = i8086::Cpu::linear(regs.s[i8086::SS], regs.r[i8086::SP]);
    if (r.address < sp && sp - r.address <= 2) sp = r.address; // a push whose SP is not yet down
    // Only deeper than before, and only on the stack the entry pushed to (a handler that
    // switches stacks is not walked: 1 KB bounds the walk).
    if (sp >= o.deepest_sp || o.pushes < 3 || sp >= o.ip_slot || o.ip_slot - sp > 0x400) return;
    o.deepest_sp = sp;
    std::array<std::uint32_t, 2 * InterruptRecord::kMaxPath> called{};
    const std::uint32_t here = i8086::Cpu::linear(core.instruction_cs(), core.instruction_ip());
    const unsigned n = walk_stack(sp, o.ip_slot, o.new_cs, r.address, here, called.data(), unsigned(called.size()));
    InterruptRecord& rec = o.rec;
    // The handler, then the deepest kMaxPath - 1 routines called.
    rec.path[0] = rec.handler;
    rec.path_len = 1;
    for (unsigned k = n > InterruptRecord::kMaxPath - 1 ? n - (InterruptRecord::kMaxPath - 1) : 0; k < n; ++k)
        rec.path[rec.path_len++] = called[k];
}

// What held the latency being explained (its dominant cause): for interrupts_disabled the service
// whose entry cleared IF, or the main-program code that did; for in_service the service of the
// level in service (the 8259A's ISR bit is its handler's until the EOI).
void InterruptProbe::name_holder(Open& entering) {
    InterruptRecord& rec = entering.rec;
    const LatencyCause::IfOff& f = rec.cause.if_off;
    const auto take = [&rec](const InterruptRecord& h, std::uint16_t ret_cs, std::uint16_t ret_ip) {
        rec.holder_service = true;
        rec.holder_level = int(h.level);
        rec.holder_path = h.path;
        rec.holder_path_len = h.path_len;
        if (h.path_len == 0) { // it wrote nothing while blocking (so far): its handler at least
            rec.holder_path[0] = h.handler;
            rec.holder_path_len = 1;
        }
        rec.holder_ret_cs = ret_cs;
        rec.holder_ret_ip = ret_ip;
    };
    // A service still open (below the one being entered: it let this one nest), innermost first,
    // else one closed lately, newest first.
    const auto find = [&](auto&& is_it) {
        for (std::size_t k = stack_.size() - 1; k-- > 0;)
            if (is_it(stack_[k].rec)) return take(stack_[k].rec, stack_[k].ret_cs, stack_[k].ret_ip), true;
        for (unsigned k = 0; k < kRecent && k < recent_n_; ++k) {
            const InterruptRecord& c = recent_[(recent_n_ - 1 - k) % kRecent];
            if (is_it(c)) return take(c, c.ret_cs, c.ret_ip), true;
        }
        return false;
    };
    if (rec.cause.cause == LatencyPhase::Kind::in_service && rec.cause.cause_level >= 0) {
        const unsigned level = unsigned(rec.cause.cause_level);
        find([&](const InterruptRecord& h) { return h.level == level && h.entered_before(rec.inta1); });
        return;
    }
    if (rec.cause.cause != LatencyPhase::Kind::interrupts_disabled || !f.valid || !f.has_off) return;
    if (f.off.how == i8086::IfChange::How::entry) {
        find([&](const InterruptRecord& h) { return h.boundary_cycle == f.off.cycle; });
        return;
    }
    if (f.off.how != i8086::IfChange::How::instruction || stack_.size() > 1) return;
    // Main-program code (CLI, POPF): the routines on its stack now (no frame bounds it: 64 words),
    // then the instruction that cleared IF.
    // Its stack as the interrupted code left it: above the entry's FLAGS, CS, IP.
    const std::uint32_t sp = entering.ip_slot + 6;
    const std::uint32_t here = i8086::Cpu::linear(entering.ret_cs, entering.ret_ip);
    std::array<std::uint32_t, InterruptRecord::kMaxPath> called{};
    const unsigned n = walk_stack(sp, sp + 128, f.off.cs, ~0u, here, called.data(), InterruptRecord::kMaxPath - 1);
    rec.holder_path_len = 0;
    for (unsigned k = 0; k < n; ++k) rec.holder_path[rec.holder_path_len++] = called[k];
    rec.holder_path[rec.holder_path_len++] = i8086::Cpu::linear(f.off.cs, f.off.ip);
}

} // namespace rcsim
