// rcsim — Intel 8086 core: the exact idle fast-forward (docs/cpu8086.md "Idle fast-forward").
//
// The core is deterministic: from the same state (registers, flags, queue, BIU phase, decode
// latches, input levels) and the same memory, with the same answers from the bus handler, it
// runs the same clocks and bus cycles. So when a polling loop comes back to an instruction with
// the whole state as it was one period earlier, and the RAM it wrote holds again what it held
// then, every later period repeats the recorded one for as long as the handler answers the
// same and the inputs do not change (they cannot before the run's horizon, the next pending
// kernel event). Those periods are then not executed clock by clock: their bus cycles are
// replayed in order (I/O and non-RAM memory to the handler at their start cycle, every cycle to
// the bus hook), the RAM writes are made and the cycle counter moves. Every instruction boundary
// of the recorded period is kept with its state, so the forwarding can start at any boundary
// whose state is one of them (after an interrupt, the loop comes back to its recorded path) and
// stop at the last one before the horizon, inside a period. A handler answer that differs (data
// or wait states), or an access that ends the run or brings the horizon closer, makes the
// segment being replayed run again from its start with the answers already given: the accesses
// are not made twice and the hook does not see a cycle twice.
#include "comm_cpu/i8086/cpu.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <type_traits>
#include <unordered_map>

namespace rcsim::i8086 {
namespace {

// Packs the state fields into a snapshot buffer (compared byte for byte: no padding, no stale
// bytes). Every field has a fixed place (the queue too), so once snapshot() has the field list
// inlined, the position is a constant and each field one store; the size check folds away.
class Packer {
public:
    Packer(std::uint8_t* out, std::size_t size) : out_(out), size_(size) {}
    template <typename T> void operator()(const T& v) { put(v); }
    template <typename N, typename T> void as(const T& v) { put(static_cast<N>(v)); }
    // The queue as its length and six bytes, those past the length zero.
    void queue(const std::uint8_t* q, unsigned head, unsigned len) {
        put(std::uint8_t(len));
        for (unsigned i = 0; i < 6; ++i) put(std::uint8_t(i < len ? q[(head + i) % 6] : 0));
    }
    void relative(cycles_t c, cycles_t now) { put(std::int32_t(std::int64_t(c) - std::int64_t(now))); }
    // A time the BIU waits for (the next prefetch's T1): only how far ahead of now it lies
    // matters; any time already reached acts as now.
    void ahead(cycles_t c, cycles_t now) { put(std::uint16_t(c > now ? c - now : 0)); }
    // The clock of the last queue operation: only whether it was this clock or the one before
    // matters (the QS lines it drives); older is "long ago" (-2).
    void recent(cycles_t c, cycles_t now) {
        put(std::int8_t(c == now ? 0 : c + 1 == now ? -1 : -2));
    }
    /// Zeroes the bytes after the fields.
    void finish() { std::memset(out_ + n_, 0, size_ - n_); }

private:
    template <typename T> void put(const T& v) {
        static_assert(std::is_trivially_copyable<T>::value, "scalars only");
        if (__builtin_expect(n_ + sizeof v > size_, 0)) too_small();
        std::memcpy(out_ + n_, &v, sizeof v);
        n_ += sizeof v;
    }
    [[noreturn, gnu::noinline, gnu::cold]] static void too_small() {
        throw std::logic_error("i8086 fast-forward: snapshot buffer too small");
    }
    std::uint8_t* out_;
    std::size_t size_, n_ = 0;
};

// ... and back (the queue from the ring's start: its position is storage only).
class Unpacker {
public:
    explicit Unpacker(const std::uint8_t* in) : in_(in) {}
    template <typename T> void operator()(T& v) { get(v); }
    template <typename N, typename T> void as(T& v) {
        N n;
        get(n);
        v = static_cast<T>(n);
    }
    void queue(std::uint8_t* q, unsigned& head, unsigned& len) {
        std::uint8_t n;
        get(n);
        head = 0;
        len = n;
        for (unsigned i = 0; i < 6; ++i) get(q[i]);
    }
    void relative(cycles_t& c, cycles_t now) {
        std::int32_t d;
        get(d);
        c = cycles_t(std::int64_t(now) + d);
    }
    void ahead(cycles_t& c, cycles_t now) {
        std::uint16_t d;
        get(d);
        c = now + d;
    }
    void recent(cycles_t& c, cycles_t now) {
        std::int8_t d;
        get(d);
        c = d == -2 ? (now >= 2 ? now - 2 : ~cycles_t(0)) : cycles_t(std::int64_t(now) + d);
    }

private:
    template <typename T> void get(T& v) {
        std::memcpy(&v, in_ + n_, sizeof v);
        n_ += sizeof v;
    }
    const std::uint8_t* in_;
    std::size_t n_ = 0;
};

// The registers of a packed state: the first fields of state_fields(), in its order.
// Inlined alike in the training copy and the profiled core (comm_cpu/tools/pgo/README.md: else GCC warns
// of missing counts).
[[gnu::always_inline]] inline Registers registers_of(const std::uint8_t* state) {
    Registers r;
    Unpacker u(state);
    for (auto& x : r.r) u(x);
    for (auto& x : r.s) u(x);
    u(r.ip);
    u(r.flags);
    return r;
}

} // namespace

// Everything the clocks after an instruction boundary depend on, except memory, the cycle
// number and the run's limits. Queue bytes as a sequence; the current bus cycle's start
// relative to now. One list for snapshot() and ff_restore().
template <class Self, class V> void Cpu::state_fields(Self& c, V& v) {
    for (auto& x : c.r_.r) v(x);
    for (auto& x : c.r_.s) v(x);
    v(c.r_.ip);
    v(c.r_.flags);
    v.queue(c.q_, c.q_head_, c.q_len_);
    v(c.fetch_ip_);
    v(c.t_);
    v(c.cur_.kind);
    v(c.cur_.seg);
    v(c.cur_.addr);
    v(c.cur_.data);
    v(c.cur_.width);
    v(c.cur_.fetch);
    v(c.cur_.discard);
    v(c.cur_.inta_first);
    v.template as<std::uint16_t>(c.waits_left_);
    v.template as<std::uint16_t>(c.cur_waits_);
    v.relative(c.cur_start_, c.cycle_);
    v(c.data_bus_);
    v(c.latch_);
    v(c.eu_data_);
    v(c.fetch_sched_);
    v.ahead(c.fetch_t1_, c.cycle_);
    v(c.fetch_next_);
    v(c.fetch_after_t4_);
    v(c.eu_claim_);
    v(c.fetch_suspended_);
    v(c.qop_);
    v.recent(c.qop_at_, c.cycle_);
    v(c.last_qop_);
    v(c.qbyte_);
    v(c.last_qbyte_);
    v(c.last_ale_);
    v(c.lock_pin_);
    v(c.opcode_);
    v(c.modrm_);
    v.template as<std::uint8_t>(c.mod_);
    v.template as<std::uint8_t>(c.reg_);
    v.template as<std::uint8_t>(c.rm_);
    v(c.ea_);
    v.template as<std::int8_t>(c.ea_seg_);
    v.template as<std::int8_t>(c.seg_override_);
    v.template as<std::uint8_t>(c.rep_);
    v(c.lock_);
    v(c.instr_ip_);
    v(c.intr_);
    v(c.nmi_level_);
    v(c.nmi_pending_);
    v(c.halted_);
    v(c.inhibit_);
    v(c.trap_armed_);
    v(c.started_);
    v(c.boundary_pending_);
    v(c.rep_interrupted_);
    v(c.rep_suspended_);
    v(c.step_hook_done_);
}

void Cpu::set_fast_forward(bool on) {
    ff_on_ = on;
    ff_recording_ = false;
    if (on && ff_seen_.empty()) ff_seen_.allocate(std::size_t(1) << 20);
    if (on && ff_pc_bits_.empty()) ff_pc_bits_.allocate((std::size_t(1) << 20) / 64);
    if (!on) ff_drop_loop();
}

// Flattened: with the field list inlined the packer is a local the compiler keeps in registers
// (out of line, every byte store through it could alias its own position and was reloaded).
[[gnu::flatten]] Cpu::Snapshot Cpu::snapshot() const {
    Snapshot s;
    Packer p(s.data(), s.size());
    state_fields(*this, p);
    p.finish();
    return s;
}

// The CPU at point `p` of the loop, now at cycle `at` (registers, queue, BIU, decode latches:
// all of snapshot(); memory is the caller's).
[[gnu::flatten]] void Cpu::ff_restore(const LoopPoint& p, cycles_t at) {
    cycle_ = at;
    Unpacker u(p.state.data());
    state_fields(*this, u);
}

void Cpu::ff_note_cycle(const BusRecord& r) {
    if (ff_log_.size() >= kFfMaxCycles) {
        ff_recording_ = false;
        return;
    }
    ff_log_.push_back(LoopCycle{r, sent_, via_handler_, cycle_, instructions_});
}

void Cpu::ff_record_point(const Snapshot& s) {
    if (ff_points_.size() >= kFfMaxPoints) {
        ff_recording_ = false;
        return;
    }
    ff_points_.push_back(
        LoopPoint{s, cycle_, instructions_, ff_log_.size(), ff_writes_.size(), ff_reads_.size(), pc(), boundaries_});
}

// Recording starts at the current boundary, whose instruction becomes the candidate.
void Cpu::ff_start() {
    ff_recording_ = true;
    ff_pc_ = pc();
    ff_log_.clear();
    ff_writes_.clear();
    ff_reads_.clear();
    ff_marks_.clear();
    ff_points_.clear();
    ff_if_log_.clear();
    const Snapshot now = snapshot();
    ff_marks_.push_back(LoopMark{now, cycle_, instructions_, 0, 0, 0, 0});
    ff_record_point(now);
}

// True when every RAM byte written since position `from` of the write log holds again the
// value it had before its first write there.
bool Cpu::ff_ram_restored(std::size_t from) {
    if (++ff_check_ == 0) {
        ff_seen_.clear();
        ff_check_ = 1;
    }
    for (std::size_t i = from; i < ff_writes_.size(); ++i) {
        const LoopWrite& w = ff_writes_[i];
        if (ff_seen_[w.addr] == ff_check_) continue; // a later write: the first one holds the old value
        ff_seen_[w.addr] = ff_check_;
        if (*w.at != w.before) return false;
    }
    return true;
}

void Cpu::ff_drop_loop() {
    for (const LoopPoint& p : ff_loop_.points) ff_pc_bits_[p.pc >> 6] &= ~(std::uint64_t(1) << (p.pc & 63));
    ff_loop_.valid = false;
    ff_loop_.points.clear();
    ff_loop_.by_pc.clear();
    ff_misses_ = 0;
    ff_landed_cycle_ = ~cycles_t(0);
}

// The state now equals that of mark `m` and the RAM the clocks since wrote is as it was then:
// those clocks are one period, with the boundaries recorded since the mark as its points.
void Cpu::ff_learn(const LoopMark& m) {
    ff_drop_loop();
    Loop& l = ff_loop_;
    l.valid = true;
    l.period = cycle_ - m.cycle;
    l.instructions = instructions_ - m.instructions;
    l.cycles.assign(ff_log_.begin() + static_cast<std::ptrdiff_t>(m.cycles_at), ff_log_.end());
    for (LoopCycle& c : l.cycles) {
        c.rec.start -= m.cycle;
        c.at -= m.cycle;
        c.instructions_at -= m.instructions;
    }
    l.points.assign(ff_points_.begin() + static_cast<std::ptrdiff_t>(m.points_at), ff_points_.end());
    // The boundaries the step hook sees: those after which step() counted one (a point's step
    // is one instruction, or an interrupt entry or a HLT clock, which the hook does not see).
    const std::uint64_t boundaries_base = l.points.front().boundaries; // the mark's own point
    l.boundaries.clear();
    for (std::size_t i = 0; i < l.points.size(); ++i) {
        const std::uint64_t next = i + 1 < l.points.size() ? l.points[i + 1].boundaries : boundaries_;
        if (next != l.points[i].boundaries) l.boundaries.push_back(Boundary{l.points[i].pc, registers_of(l.points[i].state.data())});
    }
    for (LoopPoint& p : l.points) {
        p.boundaries -= boundaries_base;
        p.cycle -= m.cycle;
        p.instructions -= m.instructions;
        p.cycles_at -= m.cycles_at;
        p.writes_at -= m.writes_at;
        p.reads_at -= m.reads_at;
        ff_pc_bits_[p.pc >> 6] |= std::uint64_t(1) << (p.pc & 63);
    }
    l.by_pc.clear();
    for (std::size_t i = 0; i < l.points.size(); ++i) l.by_pc.emplace_back(l.points[i].pc, std::uint32_t(i));
    l.needs.assign(l.points.size(), {});
    l.needs_known.assign(l.points.size(), false);
    l.notable.clear();
    std::sort(l.by_pc.begin(), l.by_pc.end());
    l.writes.assign(ff_writes_.begin() + static_cast<std::ptrdiff_t>(m.writes_at), ff_writes_.end());
    l.reads.assign(ff_reads_.begin() + static_cast<std::ptrdiff_t>(m.reads_at), ff_reads_.end());
    l.if_changes.clear();
    for (IfChange c : ff_if_log_)
        if (c.cycle >= m.cycle) {
            c.cycle -= m.cycle;
            c.instructions -= m.instructions;
            l.if_changes.push_back(c);
        }
    // The value of each write: what the next write to the byte found there, or for the last one
    // the value at the period's end (now).
    l.written.assign(l.writes.size(), 0);
    std::unordered_map<std::uint32_t, std::uint8_t> next;
    for (std::size_t i = l.writes.size(); i-- > 0;) {
        const LoopWrite& w = l.writes[i];
        const auto it = next.find(w.addr);
        l.written[i] = it != next.end() ? it->second : *w.at;
        next[w.addr] = w.before;
    }
    ff_misses_ = 0;
}

// Whether the RAM allows the recorded path from point k: every byte whose first access after
// k (around the period) is a read holds the value read then. Within one instruction the reads
// count first (the conservative order: a byte both read and written there must match). The
// list of those bytes is made the first time point k is asked about.
bool Cpu::ff_holds_at(std::size_t k) {
    Loop& l = ff_loop_;
    if (!l.needs_known[k]) {
        l.needs_known[k] = true;
        std::vector<LoopWrite>& need = l.needs[k];
        if (++ff_check_ == 0) {
            ff_seen_.clear();
            ff_check_ = 1;
        }
        const std::size_t n = l.points.size();
        for (std::size_t step = 0; step < n; ++step) {
            const std::size_t i = (k + step) % n;
            const LoopPoint& p = l.points[i];
            const std::size_t reads_end = i + 1 < n ? l.points[i + 1].reads_at : l.reads.size();
            const std::size_t writes_end = i + 1 < n ? l.points[i + 1].writes_at : l.writes.size();
            for (std::size_t r = p.reads_at; r < reads_end; ++r) {
                if (ff_seen_[l.reads[r].addr] == ff_check_) continue;
                ff_seen_[l.reads[r].addr] = ff_check_;
                need.push_back(l.reads[r]);
            }
            for (std::size_t w = p.writes_at; w < writes_end; ++w) ff_seen_[l.writes[w].addr] = ff_check_;
        }
    }
    for (const LoopWrite& x : l.needs[k])
        if (*x.at != x.before) return false;
    return true;
}

// At a boundary of the loop's code: when its state is that of one of the loop's points and
// the RAM allows the path from there, forward. True if time moved.
bool Cpu::ff_try_forward(std::uint32_t here) {
    if (cycle_ >= horizon_ || stop_) return false;
    const Loop& l = ff_loop_;
    const Snapshot now = snapshot();
    auto it = std::lower_bound(l.by_pc.begin(), l.by_pc.end(), std::make_pair(here, std::uint32_t(0)));
    // Still where the last forwarding stopped: its RAM is the point's (nothing ran since).
    const bool landed = cycle_ == ff_landed_cycle_ && instructions_ == ff_landed_instructions_;
    for (; it != l.by_pc.end() && it->first == here; ++it) {
        const bool ram_ok = landed && it->second == ff_landed_point_;
        if (l.points[it->second].state == now && (ram_ok || ff_holds_at(it->second))) {
            ff_misses_ = 0;
            return ff_forward(it->second);
        }
    }
    if (++ff_misses_ > kFfMaxMisses) ff_drop_loop();
    return false;
}

// At point k of the loop: advances along the recorded path, in segments (to the end of the
// period, whole periods, a part of the last one), each replayed and then committed (its RAM
// writes made, the state of its end point restored), to the point where the run would stop
// clock by clock: the first one at or after the limit, unless the horizon comes first (then the
// last one before it). Never past the limit: the slices, and so the boundary the core stands at
// when the simulation stops, stay those of the run without the fast-forward. At the limit, a
// slice the handler chains (run_until) is forwarded on from that point. True if time moved.
bool Cpu::ff_forward(std::size_t k) {
    const Loop& l = ff_loop_;
    ff_recording_ = false;
    const cycles_t start = cycle_;
    bool period_written = false; // the RAM holds what the loop's writes leave at its start
    // The boundaries of committed segments, for the SkipHook: a part of a period at once, whole
    // periods counted and told in one call as the forwarding ends (however it ends).
    struct WholePeriods {
        Cpu& cpu;
        std::uint64_t n = 0;
        ~WholePeriods() { cpu.ff_tell_skipped(0, cpu.ff_loop_.boundaries.size(), n); }
    } whole{*this};
    // The first point past `from` at or after `offset`. (always_inline: inlined alike in the
    // profile-generating copy of the core; comm_cpu/tools/pgo/README.md.)
    const auto after = [&l](std::size_t from, cycles_t offset) __attribute__((always_inline)) {
        return std::size_t(std::lower_bound(l.points.begin() + static_cast<std::ptrdiff_t>(from) + 1, l.points.end(), offset,
                                            [](const LoopPoint& q, cycles_t c) { return q.cycle < c; }) -
                           l.points.begin());
    };
    // At the limit, a chained slice (run_until) goes on along the path from the same point.
    while (!stop_ && (cycle_ < limit_ || (!halted_ && next_slice()))) {
        const LoopPoint& p = l.points[k];
        const cycles_t base = cycle_ - p.cycle; // where the current period started
        const std::size_t at_limit = after(k, limit_ - base); // l.points.size(): the period's end
        if (at_limit == l.points.size() && base + l.period <= horizon_) {
            if (!ff_replay(p.cycles_at, l.cycles.size(), base, instructions_ - p.instructions, base + l.period))
                return true;
            if (k == 0) ++whole.n;
            else ff_tell_skipped(p.boundaries, l.boundaries.size(), 1);
            if (!(k == 0 && period_written)) ff_apply_writes(p.writes_at, l.writes.size());
            period_written = period_written || k == 0;
            ff_replay_if(p.cycle, l.period, base, instructions_ - p.instructions);
            ff_restore(l.points[0], base + l.period);
            ff_landed_after(l.points.back(), base);
            instructions_ += l.instructions - p.instructions;
            ff_instructions_ += l.instructions - p.instructions;
            ff_cycles_ += l.period - p.cycle;
            k = 0;
            continue;
        }
        // The first point at the limit, or the last one at or before the horizon.
        const std::size_t j = std::min(at_limit, after(k, horizon_ - base + 1) - 1);
        if (j == k || j == l.points.size()) break;
        const LoopPoint& q = l.points[j];
        if (!ff_replay(p.cycles_at, q.cycles_at, base, instructions_ - p.instructions, base + q.cycle)) return true;
        ff_tell_skipped(p.boundaries, q.boundaries, 1);
        ff_apply_writes(p.writes_at, q.writes_at);
        ff_replay_if(p.cycle, q.cycle, base, instructions_ - p.instructions);
        ff_restore(q, base + q.cycle);
        ff_landed_after(l.points[j - 1], base);
        instructions_ += q.instructions - p.instructions;
        ff_instructions_ += q.instructions - p.instructions;
        ff_cycles_ += q.cycle - p.cycle;
        k = j;
        if (cycle_ < limit_) break; // the last point before the horizon: executed from here
    }
    ff_last_pc_ = pc();
    ff_landed_cycle_ = cycle_;
    ff_landed_instructions_ = instructions_;
    ff_landed_point_ = k;
    return cycle_ != start;
}

// Replays the loop's bus cycles [from, to), their starts shifted by `base`, up to the boundary
// at cycle `end`: each to the handler (those it answered) and to the hook. The counters stand
// where they stood at each handler call (a handler that suspends its caller, as the SystemC
// module does to sync, may be the last thing to run before the simulation ends). False when an
// answer differs, the run must end or the horizon came before `end`: the segment has then been
// executed again from its start (nothing of it was committed).
bool Cpu::ff_replay(std::size_t from, std::size_t to, cycles_t base, std::uint64_t instructions_base, cycles_t end) {
    ff_answers_.clear();
    if (ff_loop_.notable.empty() || ff_loop_.notable_kinds != hook_kinds_) ff_index_notable();
    const cycles_t cycle = cycle_, limit = limit_;
    const std::uint64_t instructions = instructions_;
    for (std::size_t i = ff_loop_.notable[from]; i < to; i = ff_loop_.notable[i + 1]) {
        const LoopCycle& e = ff_loop_.cycles[i];
        BusRecord r = e.rec;
        r.start += base;
        if (e.handler) {
            std::uint16_t d = e.sent;
            cycle_ = base + e.at;
            instructions_ = instructions_base + e.instructions_at;
            const unsigned waits = handler_->bus_access(r.kind, r.address, d, r.width, r.start);
            cycle_ = cycle;
            instructions_ = instructions;
            if (waits) note_held(r.kind, r.address, r.start, waits); // made: a re-execution does not note it again
            const bool read = r.kind != Bus::mem_write && r.kind != Bus::io_write;
            ff_answers_.push_back(Answer{d, waits});
            // (A lowered limit may end the run before `end`: executed, the steps find where.)
            if ((read && d != r.data) || waits != r.wait_states || stop_ || end > horizon_ || limit_ != limit) {
                ff_reexecute(unsigned(i - from)); // the cycles before this one were handed over
                return false;
            }
        }
        if (hook_kinds_ & bus_kind_bit(r.kind)) {
            hook_(hook_ctx_, r);
            if (ff_loop_.notable_kinds != hook_kinds_) ff_index_notable(); // the hook changed them
        }
    }
    ff_answers_.clear(); // the segment is committed: its answers are not for a re-execution
    return true;
}

// The replay's index of the loop's notable cycles for the hook's kinds now.
void Cpu::ff_index_notable() {
    Loop& l = ff_loop_;
    const std::size_t n = l.cycles.size();
    l.notable.resize(n + 1);
    l.notable[n] = std::uint32_t(n);
    for (std::size_t i = n; i-- > 0;) {
        const LoopCycle& e = l.cycles[i];
        l.notable[i] = e.handler || (hook_kinds_ & bus_kind_bit(e.rec.kind)) ? std::uint32_t(i) : l.notable[i + 1];
    }
    l.notable_kinds = hook_kinds_;
}

void Cpu::ff_replay_if(cycles_t from, cycles_t to, cycles_t base, std::uint64_t instructions_base) {
    for (IfChange c : ff_loop_.if_changes)
        if (c.cycle >= from && c.cycle < to) {
            c.cycle += base;
            c.instructions += instructions_base;
            push_if(c);
        }
}

// The RAM writes [from, to) of the loop, in order (the last one to a byte holds).
void Cpu::ff_apply_writes(std::size_t from, std::size_t to) {
    const Loop& l = ff_loop_;
    for (std::size_t i = from; i < to; ++i) *l.writes[i].at = l.written[i];
}

// At a boundary inside run_until() while recording (every boundary: each becomes a point), or
// at a backward transfer (a recording may start). Candidates are the targets of backward
// transfers (loop heads, returns into a loop); at each visit of the candidate the state is
// compared with the earlier visits, newest first. True if time moved.
bool Cpu::ff_boundary(std::uint32_t here, bool backward) {
    if (!ff_recording_ || (backward && cycle_ - ff_marks_.front().cycle > kFfMaxSpan)) {
        if (!backward || cycle_ < ff_quiet_until_) return false;
        if (ff_loop_.valid && ff_misses_ == 0) return false; // on the learned loop's path
        if (!ff_found_) {
            // The last recording found nothing: pause before the next one.
            ff_backoff_ = std::min(std::max(2 * ff_backoff_, cycles_t(1024)), kFfMaxBackoff);
            ff_quiet_until_ = cycle_ + ff_backoff_;
            ff_found_ = true; // the next attempt, after the pause, starts a fresh count
            ff_recording_ = false;
            return false;
        }
        ff_start(); // (again) from this loop head
        ff_found_ = false;
        return false;
    }
    const Snapshot now = snapshot();
    if (here == ff_pc_) {
        if (ff_marks_.size() >= kFfMaxMarks) {
            ff_recording_ = false;
            return false;
        }
        for (std::size_t i = ff_marks_.size(); i-- > 0;) {
            const LoopMark& m = ff_marks_[i];
            if (m.cycle < cycle_ && m.state == now && ff_ram_restored(m.writes_at)) {
                ff_learn(m);
                // A recording that found its period: the next may start without a pause.
                // (Forwarding along a loop already learned says nothing of that, and after
                // each interrupt it made the first boundaries off the loop's path start a
                // recording the loop's return then dropped.)
                ff_found_ = true;
                ff_backoff_ = 0;
                return ff_forward(0);
            }
        }
        ff_marks_.push_back(
            LoopMark{now, cycle_, instructions_, ff_log_.size(), ff_writes_.size(), ff_reads_.size(), ff_points_.size()});
    }
    ff_record_point(now);
    return false;
}

// A replayed segment diverged at its last handler access: run it again from its start (the
// state is that of its start: nothing was committed), the handler's answers taken from the
// list and the hook calls already made left out, up to the step that made that access.
void Cpu::ff_reexecute(unsigned delivered) {
    ff_answer_pos_ = 0;
    ff_hook_mute_ = delivered;
    // The run's limit is the one these steps had when they first ran: none of theirs (a REP
    // run parks at the limit; parking is invisible, but keep the first run's path).
    const cycles_t limit = limit_;
    limit_ = ~cycles_t(0);
    while (ff_answer_pos_ < ff_answers_.size()) step();
    limit_ = std::min(limit, limit_); // an access after the diverging one may have lowered it
    ff_answers_.clear();
    ff_answer_pos_ = 0;
}

} // namespace rcsim::i8086
