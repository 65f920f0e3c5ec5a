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
// the bus hook) and the cycle counter moves by whole periods. A handler answer that differs
// (data or wait states), or an access that ends the run or brings the horizon closer, makes the
// period run again from its start with the answers already given: the accesses are not made
// twice and the hook does not see a cycle twice.
#include "comm_cpu/i8086.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <type_traits>

namespace rcsim::i8086 {
namespace {

// Packs scalars into a snapshot buffer (compared byte for byte: no padding, no stale bytes).
class Packer {
public:
    explicit Packer(std::uint8_t* out, std::size_t size) : out_(out), size_(size) { std::memset(out, 0, size); }
    template <typename T> void put(const T& v) {
        static_assert(std::is_trivially_copyable<T>::value, "scalars only");
        if (n_ + sizeof v > size_) throw std::logic_error("i8086 fast-forward: snapshot buffer too small");
        std::memcpy(out_ + n_, &v, sizeof v);
        n_ += sizeof v;
    }

private:
    std::uint8_t* out_;
    std::size_t size_, n_ = 0;
};

} // namespace

void Cpu::set_fast_forward(bool on) {
    ff_on_ = on;
    ff_recording_ = false;
    if (on && ff_seen_.empty()) ff_seen_.assign(std::size_t(1) << 20, 0);
}

// Everything the clocks after an instruction boundary depend on, except memory, the cycle
// number and the run's limits. Queue bytes as a sequence (the ring position is storage only);
// the current bus cycle's start relative to now.
Cpu::Snapshot Cpu::snapshot() const {
    Snapshot s;
    Packer p(s.data(), s.size());
    for (std::uint16_t v : r_.r) p.put(v);
    for (std::uint16_t v : r_.s) p.put(v);
    p.put(r_.ip);
    p.put(r_.flags);
    p.put(std::uint8_t(q_len_));
    for (unsigned i = 0; i < q_len_; ++i) p.put(q_[(q_head_ + i) % 6]);
    p.put(fetch_ip_);
    p.put(t_);
    p.put(cur_.kind);
    p.put(cur_.seg);
    p.put(cur_.addr);
    p.put(cur_.data);
    p.put(cur_.width);
    p.put(cur_.fetch);
    p.put(cur_.discard);
    p.put(cur_.inta_first);
    p.put(std::uint16_t(waits_left_));
    p.put(std::uint16_t(cur_waits_));
    p.put(std::int32_t(std::int64_t(cur_start_) - std::int64_t(cycle_)));
    p.put(data_bus_);
    p.put(latch_);
    p.put(eu_data_);
    p.put(fetch_sched_);
    p.put(std::uint16_t(fetch_delay()));
    p.put(fetch_next_);
    p.put(fetch_after_t4_);
    p.put(eu_claim_);
    p.put(fetch_suspended_);
    p.put(qop_);
    p.put(last_qop_);
    p.put(qbyte_);
    p.put(last_qbyte_);
    p.put(last_ale_);
    p.put(lock_pin_);
    p.put(opcode_);
    p.put(modrm_);
    p.put(std::uint8_t(mod_));
    p.put(std::uint8_t(reg_));
    p.put(std::uint8_t(rm_));
    p.put(ea_);
    p.put(std::int8_t(ea_seg_));
    p.put(std::int8_t(seg_override_));
    p.put(std::uint8_t(rep_));
    p.put(lock_);
    p.put(instr_ip_);
    p.put(intr_);
    p.put(nmi_level_);
    p.put(nmi_pending_);
    p.put(halted_);
    p.put(inhibit_);
    p.put(trap_armed_);
    p.put(started_);
    p.put(boundary_pending_);
    p.put(rep_interrupted_);
    p.put(rep_suspended_);
    p.put(step_hook_done_);
    return s;
}

void Cpu::ff_note_cycle(const BusRecord& r) {
    if (ff_log_.size() >= kFfMaxCycles) {
        ff_recording_ = false;
        return;
    }
    ff_log_.push_back(LoopCycle{r, sent_, via_handler_});
}

// Recording starts at the current boundary, whose instruction becomes the candidate.
void Cpu::ff_start() {
    ff_recording_ = true;
    ff_pc_ = pc();
    ff_log_.clear();
    ff_writes_.clear();
    ff_reads_.clear();
    ff_marks_.clear();
    ff_marks_.push_back(LoopMark{snapshot(), cycle_, instructions_, 0, 0, 0});
}

// True when every RAM byte written since position `from` of the write log holds again the
// value it had before its first write there.
bool Cpu::ff_ram_restored(std::size_t from) {
    if (++ff_check_ == 0) {
        std::fill(ff_seen_.begin(), ff_seen_.end(), 0);
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

// The state now equals that of mark `m` and the RAM the clocks since wrote is as it was then:
// those clocks are one period. Nothing else writes RAM, so every byte the period read or wrote
// holds now what it held at its start: that is the period's footprint.
void Cpu::ff_learn(const LoopMark& m) {
    Loop& l = ff_loop_;
    l.valid = true;
    l.pc = ff_pc_;
    l.state = m.state;
    l.period = cycle_ - m.cycle;
    l.instructions = instructions_ - m.instructions;
    l.cycles.assign(ff_log_.begin() + static_cast<std::ptrdiff_t>(m.cycles_at), ff_log_.end());
    for (LoopCycle& c : l.cycles) c.rec.start -= m.cycle;
    l.footprint.clear();
    if (++ff_check_ == 0) {
        std::fill(ff_seen_.begin(), ff_seen_.end(), 0);
        ff_check_ = 1;
    }
    auto add = [&](const std::vector<LoopWrite>& v, std::size_t from) {
        for (std::size_t i = from; i < v.size(); ++i) {
            if (ff_seen_[v[i].addr] == ff_check_) continue;
            ff_seen_[v[i].addr] = ff_check_;
            l.footprint.push_back(LoopWrite{v[i].at, v[i].addr, *v[i].at});
        }
    };
    add(ff_writes_, m.writes_at);
    add(ff_reads_, m.reads_at);
}

bool Cpu::ff_footprint_holds() const {
    for (const LoopWrite& w : ff_loop_.footprint)
        if (*w.at != w.before) return false;
    return true;
}

// At an instruction boundary inside run_until(). A known period repeats from its instruction
// when the state and its footprint are as they were. Otherwise: recording. Candidates are the
// targets of backward transfers (loop heads, returns into a loop); at each visit of the
// candidate the state is compared with the earlier visits, newest first. True if time moved.
bool Cpu::ff_boundary(std::uint32_t here, bool backward) {
    if (ff_loop_.valid && here == ff_loop_.pc && snapshot() == ff_loop_.state && ff_footprint_holds())
        return ff_forward();
    if (!ff_recording_ || (backward && cycle_ - ff_marks_.front().cycle > kFfMaxSpan)) {
        if (!backward || cycle_ < ff_quiet_until_) return false;
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
    if (here != ff_pc_) return false;
    if (ff_marks_.size() >= kFfMaxMarks) {
        ff_recording_ = false;
        return false;
    }
    const Snapshot now = snapshot();
    for (std::size_t i = ff_marks_.size(); i-- > 0;) {
        if (ff_marks_[i].cycle < cycle_ && ff_marks_[i].state == now && ff_ram_restored(ff_marks_[i].writes_at)) {
            ff_learn(ff_marks_[i]);
            return ff_forward();
        }
    }
    ff_marks_.push_back(LoopMark{now, cycle_, instructions_, ff_log_.size(), ff_writes_.size(), ff_reads_.size()});
    return false;
}

// At the start of the known period: advances whole periods while they end at or before the
// horizon. True if time moved.
bool Cpu::ff_forward() {
    const Loop& l = ff_loop_;
    ff_found_ = true;
    ff_backoff_ = 0;
    ff_recording_ = false;
    const cycles_t start = cycle_;
    while (cycle_ + l.period <= horizon_ && !stop_) {
        ff_answers_.clear();
        unsigned delivered = 0;
        for (const LoopCycle& e : l.cycles) {
            BusRecord r = e.rec;
            r.start += cycle_;
            if (e.handler) {
                std::uint16_t d = e.sent;
                const unsigned waits = handler_->bus_access(r.kind, r.address, d, r.width, r.start);
                const bool read = r.kind != Bus::mem_write && r.kind != Bus::io_write;
                ff_answers_.push_back(Answer{d, waits});
                if ((read && d != r.data) || waits != r.wait_states || stop_ || cycle_ + l.period > horizon_) {
                    ff_reexecute(delivered);
                    return true;
                }
            }
            if (hook_) hook_(hook_ctx_, r);
            ++delivered;
        }
        ff_answers_.clear(); // the period is committed: its answers are not for a re-execution
        cycle_ += l.period;
        cur_start_ += l.period;
        fetch_t1_ += l.period; // the BIU's times move with the clock (qop_at_: the QS lines)
        qop_at_ += l.period;
        instructions_ += l.instructions;
        ff_cycles_ += l.period;
    }
    ff_start(); // recording goes on from here (another loop may follow)
    return cycle_ != start;
}

// A replayed period diverged at its last handler access: run it again from its start (the
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
