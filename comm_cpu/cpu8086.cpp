// rcsim — Intel 8086-2 SystemC module. See cpu8086.h.
#include "comm_cpu/cpu8086.h"

#include <sstream>

namespace rcsim {
using namespace sc_core;

static_assert(static_cast<BusCycle>(i8086::Bus::io_write) == BusCycle::io_write &&
                  static_cast<BusCycle>(i8086::Bus::code_fetch) == BusCycle::code_fetch &&
                  static_cast<BusCycle>(i8086::Bus::mem_write) == BusCycle::mem_write,
              "i8086::Bus and BusCycle share the S2..S0 encoding");

Cpu8086::Cpu8086(sc_module_name name, const Clock& clock)
    : sc_module(name), io("io"), mem("mem"), inta("inta"), intr("intr"), nmi("nmi"), clock_(clock),
      quantum_(us(kDefaultQuantumUs)) {
    core_.set_bus_handler(this);
    SC_HAS_PROCESS(Cpu8086);
    SC_THREAD(run);
    SC_METHOD(track_inputs);
    sensitive << intr << nmi;
    dont_initialize();
}

void Cpu8086::set_quantum(const sc_time& q) {
    if (q < clock_.period()) {
        std::ostringstream os;
        os << "quantum " << q << " is shorter than one clock (" << clock_.period() << ")";
        SC_REPORT_ERROR(name(), os.str().c_str());
        return;
    }
    quantum_ = q;
}

void Cpu8086::track_inputs() {
    const sc_time now = sc_time_stamp();
    if (intr.read() != intr_now_) {
        intr_prev_ = intr_now_;
        intr_now_ = intr.read();
        intr_changed_ = now;
    }
    if (nmi.read() != nmi_now_) {
        nmi_prev_ = nmi_now_;
        nmi_now_ = nmi.read();
        nmi_changed_ = now;
    }
}

// The levels as they were just before time `at` (the core's boundary).
void Cpu8086::sample_inputs(const sc_time& at) {
    core_.set_intr(sampled(intr_now_, intr_prev_, intr_changed_, at));
    core_.set_nmi(sampled(nmi_now_, nmi_prev_, nmi_changed_, at));
}

// The slice that begins at cycle `start`, at kernel time or ahead of it (now_ps): its limit (no
// further than the quantum and event_ps, the next pending event's time, kNoEvent: none or no
// lookahead) and its horizon (no input can change before it). One boundary only after a fresh
// change of INTR/NMI: the kernel runs what it caused before the core goes on.
void Cpu8086::plan_slice(std::uint64_t now_ps, i8086::cycles_t start, bool fresh_change, std::uint64_t event_ps,
                         i8086::cycles_t& limit, i8086::cycles_t& horizon) const {
    const std::uint64_t period = clock_.period_ps();
    limit = horizon = start + 1;
    if (fresh_change) return;
    std::uint64_t end_ps = now_ps + to_ps(quantum_);
    if (event_ps != kNoEvent) {
        if (event_ps < end_ps) end_ps = event_ps;
        // Boundaries at edges up to and including the event time still see the old level.
        horizon = event_ps / period + 1;
    }
    limit = end_ps / period + 1;
    if (limit <= start) limit = start + 1;
    if (horizon < limit) horizon = limit;
}

// sc_time_to_pending_activity() says all three: zero with activity at the current time,
// sc_max_time() - now with nothing pending, else the distance to the next timed event.
std::uint64_t Cpu8086::next_activity_ps() {
    const sc_time now = sc_time_stamp(), ahead = sc_time_to_pending_activity();
    return ahead == sc_max_time() - now ? kNoEvent : to_ps(now) + to_ps(ahead);
}

// The slice chain (docs/architecture.md "Slice chain"): the core reached its limit at cycle `at`,
// before the next pending event, with no activity left at the current time. The sync run()
// would make next only moves kernel time (no process runs before that event), and the inputs
// it samples then hold the levels they have now: the next slice is planned here, as run() would.
// A halted core goes back to run(), which sleeps until INTR or NMI changes.
bool Cpu8086::next_slice(i8086::cycles_t at, i8086::cycles_t& limit, i8086::cycles_t& horizon) {
    if (!slice_chain_ || !lookahead_ || boundary_log_ || core_.halted()) return false;
    // (nothing pending: no event would ever end the chain)
    const std::uint64_t event_ps = next_activity_ps(), at_ps = at * clock_.period_ps();
    if (event_ps == kNoEvent || at_ps >= event_ps) return false;
    sample_inputs(ps(at_ps));
    plan_slice(at_ps, at, false, event_ps, limit, horizon);
    ++slices_;
    slice_limit_ = limit;
    return true;
}

void Cpu8086::run() {
    const std::uint64_t period = clock_.period_ps();
    unsigned stuck = 0;
    for (;;) {
        // Sync: kernel time catches up with the core.
        const sc_time core_time = clock_.cycles(core_.cycles());
        if (core_time > sc_time_stamp()) {
            ++kernel_waits_;
            wait(core_time - sc_time_stamp());
        }
        const sc_time now = sc_time_stamp();
        sample_inputs(now);
        const bool fresh_change = intr_changed_ == now || nmi_changed_ == now;

        if (core_.halted() && !(intr_now_ && (core_.regs().flags & i8086::flag::IF)) && !nmi_now_) {
            // HLT: sleep until INTR or NMI changes; the core resumes at the first clock edge
            // after the change.
            ++kernel_waits_;
            wait(intr.value_changed_event() | nmi.value_changed_event());
            track_inputs();
            core_.skip_to(to_ps(sc_time_stamp()) / period + 1);
            continue;
        }

        const i8086::cycles_t start = core_.cycles();
        i8086::cycles_t limit, horizon; // horizon: no input can change before it (the fast-forward's bound)
        const std::uint64_t event_ps = lookahead_ ? next_activity_ps() : kNoEvent;
        plan_slice(to_ps(now), start, fresh_change, event_ps, limit, horizon);
        ++slices_;
        slice_end_ = false;
        slice_limit_ = limit;
        if (boundary_log_) {
            while (core_.cycles() < slice_limit_ && !slice_end_) {
                core_.step_within(slice_limit_);
                boundary_log_->push_back(core_.cycles());
                if (core_.halted()) break;
            }
        } else {
            core_.run_until(limit, false, horizon);
        }
        // Stuck-in-time guard: a slice that neither advanced the core nor kernel time.
        if (core_.cycles() == start && sc_time_stamp() == now) {
            if (++stuck > 1000) SC_REPORT_FATAL(name(), "CPU made no progress in 1000 slices (stuck in time)");
        } else {
            stuck = 0;
        }
    }
}

unsigned Cpu8086::bus_access(i8086::Bus kind, std::uint32_t address, std::uint16_t& data, unsigned width,
                             i8086::cycles_t start) {
    // Sync so the target sees sc_time_stamp() == T1 of this cycle, unless the read is one the
    // target declared stable and nothing is scheduled before T1.
    const sc_time t1 = clock_.cycles(start);
    if (t1 > sc_time_stamp()) {
        if (may_read_early(kind, address, width, t1)) {
            ++stable_reads_;
        } else {
            ++kernel_waits_;
            ++access_waits_;
            wait(t1 - sc_time_stamp());
        }
    }
    std::uint8_t buf[2] = {std::uint8_t(data), std::uint8_t(data >> 8)};
    BusResult r;
    switch (kind) {
    case i8086::Bus::io_read: r = payload_.access(io, BusCycle::io_read, address, buf, width, t1); break;
    case i8086::Bus::io_write: r = payload_.access(io, BusCycle::io_write, address, buf, width, t1); break;
    case i8086::Bus::mem_read:
    case i8086::Bus::code_fetch:
        r = payload_.access(mem, kind == i8086::Bus::mem_read ? BusCycle::mem_read : BusCycle::code_fetch,
                            address, buf, width, t1);
        break;
    case i8086::Bus::mem_write: r = payload_.access(mem, BusCycle::mem_write, address, buf, width, t1); break;
    case i8086::Bus::int_ack: r = payload_.access(inta, BusCycle::int_ack, address, buf, 1, t1); break;
    default: return 0;
    }
    const bool read = kind != i8086::Bus::io_write && kind != i8086::Bus::mem_write;
    if (read) data = r.ok() ? std::uint16_t(buf[0] | (width == 2 ? buf[1] << 8 : 0xFF00)) : 0xFFFF;
    if (!r.ok())
        bus_errors_.add(r.status == tlm::TLM_ADDRESS_ERROR_RESPONSE ? BusErrorLog::Kind::unmapped
                                                                    : BusErrorLog::Kind::tlm_error,
                        address, static_cast<BusCycle>(kind), t1); // the same S2..S0 encoding
    after_access();
    return r.wait_states;
}

// A read ahead of kernel time (docs/architecture.md "Stable reads"): the target declared it
// stable, and T1 comes before every pending kernel event, so the sync would only move time:
// no process runs between now and T1 (one due at T1 itself might run first: the sync then).
bool Cpu8086::may_read_early(i8086::Bus kind, std::uint32_t address, unsigned width, const sc_time& t1) const {
    if (!stable_reads_on_) return false;
    const StableReads* decl = kind == i8086::Bus::io_read ? io_stable_
                              : kind == i8086::Bus::mem_read || kind == i8086::Bus::code_fetch ? mem_stable_
                                                                                                  : nullptr;
    if (!decl || !decl->read_is_stable(address, width)) return false;
    // (one kernel query: zero with activity at the current time, sc_max_time() - now with nothing
    // pending, so that T1 is before every pending event exactly when it is before now + this)
    return t1 < sc_time_stamp() + sc_time_to_pending_activity();
}

// Kernel time is the access's T1 (or, after a stable read, before it). Activity left at the
// current time (a signal write, an immediate or delta notification) may change INTR/NMI: the
// slice ends at the next boundary and the kernel runs it. Otherwise nothing can change before
// the next timed event, which the access may have moved closer: the slice goes on with its limit
// lowered to that event, the same limit a fresh slice would compute.
void Cpu8086::after_access() {
    if (!fast_sync_ || !lookahead_ || sc_pending_activity_at_current_time()) {
        core_.stop_run();
        slice_end_ = true;
        return;
    }
    const std::uint64_t event_ps = next_activity_ps(); // (none now: the next timed one)
    if (event_ps == kNoEvent) return;
    const i8086::cycles_t limit = event_ps / clock_.period_ps() + 1;
    if (limit < slice_limit_) slice_limit_ = limit;
    core_.shorten_run(limit);
}

void Cpu8086::install_bus_observers() {
    if (!debug_bus_observer_.hook) core_.set_bus_hook(bus_observer_.hook, bus_observer_.context, bus_observer_.kinds);
    else if (!bus_observer_.hook) core_.set_bus_hook(debug_bus_observer_.hook, debug_bus_observer_.context);
    else core_.set_bus_hook(&Cpu8086::bus_fanout, this); // the debugger sees every cycle
}

void Cpu8086::bus_fanout(void* self, const i8086::BusRecord& record) {
    const auto* cpu = static_cast<Cpu8086*>(self);
    if (cpu->bus_observer_.kinds & i8086::bus_kind_bit(record.kind))
        cpu->bus_observer_.hook(cpu->bus_observer_.context, record);
    cpu->debug_bus_observer_.hook(cpu->debug_bus_observer_.context, record);
}

bool Cpu8086::debug_read(std::uint32_t linear, std::uint8_t* out, std::size_t n) {
    return debug_access(linear, out, n, false);
}

bool Cpu8086::debug_write(std::uint32_t linear, const std::uint8_t* in, std::size_t n) {
    return debug_access(linear, const_cast<std::uint8_t*>(in), n, true); // only read from when writing
}

bool Cpu8086::debug_access(std::uint32_t linear, std::uint8_t* data, std::size_t n, bool write) {
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t a = (linear + std::uint32_t(i)) & 0xFFFFF; // the 8086 wraps at 1 MB
        if (const MemRegion* r = core_.memory().find(a)) {
            if (write) r->data[a - r->base] = data[i];
            else data[i] = r->data[a - r->base];
            continue;
        }
        tlm::tlm_generic_payload gp;
        gp.set_command(write ? tlm::TLM_WRITE_COMMAND : tlm::TLM_READ_COMMAND);
        gp.set_address(a);
        gp.set_data_ptr(data + i);
        gp.set_data_length(1);
        if (mem->transport_dbg(gp) != 1) return false;
    }
    return true;
}

void Cpu8086::write_ignored(std::uint32_t address, unsigned, i8086::cycles_t start) {
    bus_errors_.add(BusErrorLog::Kind::rom_write, address, BusCycle::mem_write, time_of(start));
}

} // namespace rcsim
