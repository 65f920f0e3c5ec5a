#include "scenarios/trace/perfetto_trace.h"

#include "models/plumbing/hex.h"
#include "scenarios/world/world.h"

#include <cstdio>

namespace rcsim::trace {

namespace {

static_assert(PerfettoTrace::ports() == World::kPorts, "one 82510 per port");

constexpr const char* kBusyLeft = "BUSY left (comm CPU)";
constexpr const char* kBusyRight = "BUSY right (main CPU)";

std::uint64_t ps_of(const sc_core::sc_time& t) { return t.value(); } // the kernel's resolution is 1 ps
std::uint64_t now_ps() { return ps_of(sc_core::sc_time_stamp()); }

// report.json's names of the levels (scenarios/verdict/measure.cpp).
std::string level_name(unsigned level) {
    static const char* names[] = {"rs232_0", "rs232_1", "rs232_2", "dpram"};
    return "IR" + std::to_string(level) + (level < 4 ? std::string(" ") + names[level] : std::string());
}

std::string hex5(std::uint32_t linear) { return "0x" + hex(linear, 5); }

const char* dir_name(unsigned dir) {
    return dir == LineObserver::host_to_controller ? "host to controller" : "controller to host";
}

/// A hook that calls what `existing` did (if anything), then `added`.
template <class F, class... A>
std::function<void(A...)> chain(std::function<void(A...)> existing, F added) {
    if (!existing) return added;
    return [existing = std::move(existing), added = std::move(added)](A... a) {
        existing(a...);
        added(a...);
    };
}

} // namespace

PerfettoTrace::PerfettoTrace(World& world, const std::string& path) : world_(world), out_(path) {
    name_tracks();
    InterruptProbe& probe = world.probe;
    // The world's own listeners run first: the trace only reads what they leave.
    probe.on_record = chain(probe.on_record, [this](const InterruptRecord& r) { on_record(r); });
    probe.on_settled = chain(probe.on_settled, [this](const sc_core::sc_time& h) { flush_before(ps_of(h)); });
    for (unsigned p = 0; p < kPorts; ++p) {
        Uart82510& uart = world.ctl.comm.uart[p];
        uart.on_fifo_change = chain(uart.on_fifo_change, [this, p] { sample_fifos(p); });
        SerialLine& line = world.lines[p];
        line.on_deliver = chain(line.on_deliver, [this, p](const SerialLine::Delivered& d) {
            if (d.kind == SerialLine::Delivered::character && (d.rx.data & 0xFF) == proto::SOH && !d.rx.parity_error &&
                !d.rx.framing_error) {
                const unsigned dir = d.from == SerialLine::a ? LineObserver::controller_to_host : LineObserver::host_to_controller;
                ports_[p].frame_start_ps[dir] = ps_of(d.rx.start);
            }
            sample_states(p);
        });
        LineObserver& observer = world.observers[p];
        observer.on_frame = chain(observer.on_frame, [this, p](LineObserver::Dir d, bool valid, const proto::Frame& f) {
            on_frame(p, d, valid, f.token);
        });
        sample_fifos(p);
        sample_states(p);
    }
    Idt7130& dpram = world.ctl.dpram;
    for (const char* name : {kBusyLeft, kBusyRight}) out_.counter(pid_dpram, name, 0, 0); // released at reset
    dpram.on_busy = chain(dpram.on_busy, [this](const Idt7130::BusyEvent& e) {
        // One port's BUSY episodes come in order and do not overlap: each is written whole.
        const char* name = e.port == Idt7130::left_port ? kBusyLeft : kBusyRight;
        out_.counter(pid_dpram, name, ps_of(e.busy_low), 1);
        out_.counter(pid_dpram, name, ps_of(e.busy_high), 0);
    });
}

void PerfettoTrace::name_tracks() {
    out_.process_name(pid_pic, "8259A", 0);
    out_.thread_name(pid_pic, kNestingTid, "ISR nesting (all levels)", 100);
    for (unsigned p = 0; p < kPorts; ++p)
        out_.process_name(pid_uart + p, "82510 port " + std::to_string(p), 10 + static_cast<int>(p));
    out_.process_name(pid_dpram, "IDT7130 DP-RAM", 20);
    for (unsigned p = 0; p < kPorts; ++p) {
        out_.process_name(pid_host + p, "host " + std::to_string(p) + " (" + world_.host_kind(p) + ")",
                          30 + static_cast<int>(p));
        for (unsigned dir = 0; dir < 2; ++dir)
            out_.thread_name(pid_host + p, dir + 1, std::string("frames ") + dir_name(dir), static_cast<int>(dir));
    }
}

// ---------------------------------------------------------------------------------------------
// Interrupts: queued by time, written up to the probe's horizon.

void PerfettoTrace::on_record(const InterruptRecord& r) {
    const unsigned level = r.level & 7;
    const unsigned tid = level + 1;
    if (!level_named_[level]) {
        level_named_[level] = true;
        out_.thread_name(pid_pic, tid, level_name(level), static_cast<int>(level));
    }
    const std::uint64_t start = ps_of(r.first_isr), dur = ps_of(r.iret_done) - start;
    const std::string args = "\"vector\":" + std::to_string(r.vector) + ",\"depth\":" + std::to_string(r.depth) +
                             ",\"handler\":\"" + hex5(r.handler) + "\"" +
                             ",\"latency_us\":" + (r.has_rise ? micros(ps_of(r.first_isr - r.ir_rise)) : std::string("null")) +
                             ",\"service_us\":" + micros(dur);
    if (r.has_rise) queue_.emplace(ps_of(r.ir_rise), Queued{Queued::instant, tid, "IR rise", "", 0});
    queue_.emplace(ps_of(r.inta1), Queued{Queued::instant, tid, "INTA", "", 0});
    queue_.emplace(start, Queued{Queued::slice, tid, level_name(level) + " ISR", args, dur});
    queue_.emplace(start, Queued{Queued::slice, kNestingTid, level_name(level), args, dur});
    if (r.has_eoi) queue_.emplace(ps_of(r.eoi), Queued{Queued::instant, tid, "EOI", "", 0});
}

void PerfettoTrace::flush_before(std::uint64_t horizon_ps) {
    auto it = queue_.begin();
    for (; it != queue_.end() && it->first < horizon_ps; ++it) {
        const Queued& q = it->second;
        if (q.kind == Queued::slice) out_.complete(pid_pic, q.tid, q.name, it->first, q.dur_ps, q.args);
        else out_.instant(pid_pic, q.tid, q.name, it->first);
    }
    queue_.erase(queue_.begin(), it);
}

// ---------------------------------------------------------------------------------------------
// Counters and frames, at kernel time.

void PerfettoTrace::counter(unsigned pid, const std::string& name, std::int64_t& last, std::int64_t value,
                            std::uint64_t ts_ps) {
    if (value == last) return;
    last = value;
    out_.counter(pid, name, ts_ps, value);
}

void PerfettoTrace::sample_fifos(unsigned port) {
    const Uart82510& uart = world_.ctl.comm.uart[port];
    PortCounters& c = ports_[port];
    counter(pid_uart + port, "RX FIFO", c.rx, uart.rx_level(), now_ps());
    counter(pid_uart + port, "TX FIFO", c.tx, uart.tx_level(), now_ps());
}

void PerfettoTrace::sample_states(unsigned port) {
    PortCounters& c = ports_[port];
    for (unsigned dir = 0; dir < 2; ++dir) {
        const auto s = world_.observers[port].state(static_cast<LineObserver::Dir>(dir));
        counter(pid_uart + port, std::string("protocol ") + dir_name(dir), c.state[dir], static_cast<std::int64_t>(s),
                now_ps());
    }
}

void PerfettoTrace::on_frame(unsigned port, unsigned dir, bool valid, const std::string& token) {
    const std::uint64_t start = ports_[port].frame_start_ps[dir], end = now_ps();
    out_.complete(pid_host + port, dir + 1, valid ? token : "bad frame", start, end - start);
}

void PerfettoTrace::finish() {
    flush_before(~std::uint64_t(0));
    out_.close();
}

} // namespace rcsim::trace
