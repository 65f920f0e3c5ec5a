#include "scenarios/board/latency_cause.h"

#include "comm_cpu/cpu8086.h"
#include "models/clock.h"

#include <algorithm>
#include <vector>

namespace rcsim {

using sc_core::sc_time;
using Kind = LatencyPhase::Kind;

double LatencyPhase::us() const { return to_us(to - from); }

const char* to_string(LatencyPhase::Kind kind) {
    switch (kind) {
    case Kind::not_ready: return "pic_not_ready";
    case Kind::masked: return "masked";
    case Kind::in_service: return "in_service";
    case Kind::priority: return "priority";
    case Kind::interrupts_disabled: return "interrupts_disabled";
    case Kind::instruction: return "instruction";
    case Kind::dpram_busy: return "dpram_busy";
    case Kind::entry: return "entry";
    case Kind::presented: return "presented";
    }
    return "?";
}

namespace {

bool same_stretch(const LatencyPhase& a, const LatencyPhase& b) { return a.kind == b.kind && a.level == b.level; }

LatencyPhase of_hold(const Pic8259::Hold& h, const sc_time& at) {
    LatencyPhase p;
    p.from = p.to = at;
    switch (h.kind) {
    case Pic8259::Hold::Kind::none: p.kind = Kind::presented; break;
    case Pic8259::Hold::Kind::not_ready: p.kind = Kind::not_ready; break;
    case Pic8259::Hold::Kind::masked: p.kind = Kind::masked; break;
    case Pic8259::Hold::Kind::in_service: p.kind = Kind::in_service; p.level = h.by; break;
    case Pic8259::Hold::Kind::priority: p.kind = Kind::priority; p.level = h.by; break;
    }
    return p;
}

// Appends a phase of some time, joining it to the last one of the same kind that it continues.
void add(LatencyCause& c, LatencyPhase p) {
    if (p.to <= p.from) return;
    if (c.phases > 0) {
        LatencyPhase& last = c.phase[c.phases - 1];
        if (same_stretch(last, p) && last.to == p.from) {
            last.to = p.to;
            return;
        }
        if (c.phases == LatencyCause::kMaxPhases) { // the last one holds the rest
            last.to = p.to;
            c.truncated = true;
            return;
        }
    }
    c.phase[c.phases++] = p;
}

// IF at time t, as far as the core's history reaches: the newest change at or before t, else the
// state before the oldest one it holds.
bool enabled_at(const i8086::Cpu& core, const Cpu8086& cpu, const sc_time& t) {
    const unsigned n = core.if_changes();
    for (unsigned k = 0; k < n; ++k)
        if (cpu.time_of(core.if_change(k).cycle) <= t) return core.if_change(k).enabled;
    return n > 0 ? !core.if_change(n - 1).enabled : true;
}

// The change that cleared IF for a stretch that began at a: the newest clear at or before a
// among the core's changes from the k-th newest on. Clears after a come with a set before them
// that let no interrupt in (an STI directly followed by CLI, while INT was up): IF stayed off in
// effect, and the walk goes on to the one before. Not found: has_off stays false.
void find_off(LatencyCause::IfOff& f, const sc_time& a, unsigned k, const i8086::Cpu& core, const Cpu8086& cpu) {
    f.has_off = false;
    for (; k < core.if_changes(); ++k) {
        const i8086::IfChange& ch = core.if_change(k);
        if (ch.enabled) continue;
        f.off = ch;
        f.has_off = true;
        f.since = cpu.time_of(ch.cycle);
        if (f.since <= a) return;
    }
    f.has_off = false; // the history does not reach back to it
}

// A stretch [a, until) with IF = 0; its details are the cause's when it is the longest one.
void disabled(LatencyCause& c, const LatencyCause::IfOff& f) {
    add(c, LatencyPhase{Kind::interrupts_disabled, -1, f.from, f.to});
    if (!c.if_off.valid || f.to - f.from > c.if_off.to - c.if_off.from) c.if_off = f;
}

// A stretch [a, b) in which INT was up but the CPU took nothing, ended by the 8259A (another
// request taken first): IF = 0 at a (disabled, the set that ended it the newest one up to b, the
// stretch's end its end) or the other kind.
void waited(LatencyCause& c, LatencyPhase p, Kind otherwise, const i8086::Cpu& core, const Cpu8086& cpu) {
    if (enabled_at(core, cpu, p.from)) {
        p.kind = otherwise;
        add(c, p);
        return;
    }
    LatencyCause::IfOff f;
    f.valid = true;
    f.from = p.from;
    f.to = f.until = p.to;
    f.has_on = false;
    // IF came back with the first set after the stretch began (before or after the 8259A ended
    // it; the newest change is the one that let this interrupt in at the latest): the walk goes
    // from the newest change back, the last set seen is the first.
    for (unsigned k = 0; k < core.if_changes(); ++k) {
        const i8086::IfChange& ch = core.if_change(k);
        const sc_time t = cpu.time_of(ch.cycle);
        if (t <= p.from) break;
        if (ch.enabled) {
            f.on = ch;
            f.has_on = true;
            f.until = t;
        }
    }
    find_off(f, p.from, 0, core, cpu);
    disabled(c, f);
}

// The stretch [a, B) in which INT presented the request up to the boundary B where the CPU took
// it: IF = 0 up to the end of the instruction that set IF, then the instruction in progress.
void cpu_side(LatencyCause& c, const sc_time& a, const sc_time& b, Cpu8086& cpu) {
    const i8086::Cpu& core = cpu.core();
    sc_time enabled = a; // IF effectively 1 from here
    const unsigned n = core.if_changes();
    if (n > 0 && core.if_change(0).enabled) {
        const i8086::IfChange& on = core.if_change(0);
        const std::uint64_t after = core.instructions() - on.instructions; // instructions since its boundary
        bool shadow = false;
        sc_time end = cpu.time_of(on.cycle); // later than the instruction after it: IF was 1 before
        if (on.how == i8086::IfChange::How::instruction && on.opcode == 0xFB && after == 2) {
            end = cpu.time_of(core.instruction_start()); // STI: the next instruction runs first
            shadow = true;
        } else if (after == 1) {
            end = b; // POPF, IRET: the boundary right after it
        }
        if (end > a) {
            enabled = end;
            LatencyCause::IfOff f;
            f.valid = true;
            f.from = a;
            f.to = f.until = end;
            f.on = on;
            f.has_on = true;
            find_off(f, a, 1, core, cpu);
            disabled(c, f);
            c.instruction.sti_shadow = shadow;
        }
    }
    const sc_time from = std::max(a, enabled);
    if (b <= from) return;
    add(c, LatencyPhase{Kind::instruction, -1, from, b});
    LatencyCause::Instruction& i = c.instruction;
    i.valid = true;
    i.halted = core.interrupt_from_halt();
    i.start = cpu.time_of(core.instruction_start());
    i.cs = core.instruction_cs();
    i.ip = core.instruction_ip();
    const std::uint32_t linear = i8086::Cpu::linear(i.cs, i.ip);
    i.nbytes = 0;
    for (unsigned k = 0; k < i.bytes.size(); ++k) {
        if (!cpu.debug_read(linear + k, &i.bytes[k], 1)) break;
        i.nbytes = k + 1;
    }
}

} // namespace

// ---------------------------------------------------------------------------------------------

void RequestTrack::open(const sc_time& rise, const Pic8259::Hold& h) {
    open_ = true;
    n_ = 0;
    cur_ = of_hold(h, rise);
}

void RequestTrack::update(const sc_time& now, const Pic8259::Hold& h) {
    if (!open_) return;
    const LatencyPhase next = of_hold(h, now);
    if (same_stretch(next, cur_)) return;
    if (now > cur_.from) {
        cur_.to = now;
        if (n_ < kMaxPhases) done_[n_++] = cur_;
        else done_[n_ - 1].to = now; // the last one holds the rest
        cur_ = next;
    } else if (n_ > 0 && same_stretch(done_[n_ - 1], next)) {
        cur_ = done_[--n_]; // a change of no time in between: the earlier stretch goes on
    } else {
        cur_ = next;
    }
}

unsigned RequestTrack::phases(const sc_time& end, std::array<LatencyPhase, kMaxPhases>& out) const {
    unsigned n = 0;
    const auto put = [&](LatencyPhase p) {
        if (p.to > end) p.to = end;
        if (p.to <= p.from) return;
        if (n < kMaxPhases) out[n++] = p;
        else out[n - 1].to = p.to;
    };
    for (unsigned k = 0; k < n_; ++k) put(done_[k]);
    LatencyPhase last = cur_;
    last.to = end;
    put(last);
    return n;
}

// ---------------------------------------------------------------------------------------------

LatencyCause explain_latency(const RequestTrack& track, const sc_time& rise, Cpu8086& cpu) {
    LatencyCause c;
    c.known = true;
    const i8086::Cpu& core = cpu.core();
    const sc_time b = cpu.time_of(core.interrupt_boundary());
    c.boundary = b;
    std::array<LatencyPhase, RequestTrack::kMaxPhases> pic{};
    unsigned n = 0;
    if (track.is_open()) {
        n = track.phases(b, pic);
    } else if (b > rise) { // no 8259A watched: presented from the rise
        pic[0] = LatencyPhase{Kind::presented, -1, rise, b};
        n = 1;
    }
    for (unsigned k = 0; k < n; ++k) {
        LatencyPhase p = pic[k];
        p.from = std::max(p.from, rise);
        if (p.to <= p.from) continue;
        if (p.kind == Kind::presented && k + 1 == n && p.to == b) {
            cpu_side(c, p.from, b, cpu);
        } else if (p.kind == Kind::presented) {
            waited(c, p, Kind::instruction, core, cpu); // presented, then another request came first
        } else if (p.kind == Kind::priority) {
            waited(c, p, Kind::priority, core, cpu); // INT up for a higher request: taken at once, or IF = 0
        } else {
            add(c, p);
        }
    }
    return c;
}

void finish_latency_cause(LatencyCause& c, const sc_time& rise, const sc_time& first_isr, Cpu8086& cpu,
                          std::uint32_t dpram_base, std::uint32_t dpram_size) {
    if (!c.known) return;
    add(c, LatencyPhase{Kind::entry, -1, std::max(c.boundary, rise), first_isr});

    // DP-RAM cycles held by BUSY: their Tw clocks inside the instruction and the entry.
    const i8086::Cpu& core = cpu.core();
    struct Held {
        sc_time from, to;
        std::uint32_t address;
        unsigned waits;
        bool counted;
    };
    std::vector<Held> held;
    for (unsigned k = core.held_cycles(); k-- > 0;) { // oldest first
        const i8086::HeldCycle& h = core.held_cycle(k);
        if (h.address - dpram_base >= dpram_size) continue;
        const sc_time from = std::max(cpu.time_of(h.start + 3), rise);
        const sc_time to = std::min(cpu.time_of(h.start + 3 + h.waits), first_isr);
        if (to > from) held.push_back(Held{from, to, h.address, h.waits, false});
    }
    if (!held.empty()) {
        LatencyCause out = c;
        out.phases = 0;
        out.truncated = c.truncated;
        for (unsigned k = 0; k < c.phases; ++k) {
            const LatencyPhase& p = c.phase[k];
            sc_time at = p.from;
            if (p.kind == Kind::instruction || p.kind == Kind::entry) {
                for (Held& h : held) {
                    const sc_time from = std::max(h.from, p.from), to = std::min(h.to, p.to);
                    if (to <= from) continue;
                    add(out, LatencyPhase{p.kind, -1, at, from});
                    add(out, LatencyPhase{Kind::dpram_busy, -1, from, to});
                    if (!h.counted) {
                        if (out.busy.wait_states == 0) out.busy.address = h.address;
                        out.busy.wait_states += h.waits;
                        h.counted = true;
                    }
                    at = to;
                }
            }
            add(out, LatencyPhase{p.kind, p.level, at, p.to});
        }
        c = out;
    }

    // The dominant cause: the kind (and level) with the most time, the first one on a tie.
    sc_time best;
    for (unsigned k = 0; k < c.phases; ++k) {
        sc_time total;
        for (unsigned j = 0; j < c.phases; ++j)
            if (same_stretch(c.phase[j], c.phase[k])) total += c.phase[j].to - c.phase[j].from;
        if (total > best) {
            best = total;
            c.cause = c.phase[k].kind;
            c.cause_level = c.phase[k].level;
        }
    }
    c.cause_time = best;
}

} // namespace rcsim
