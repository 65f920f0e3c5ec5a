// rcsim — VCD waveforms (see vcd_trace.h).
#include "scenarios/trace/vcd_trace.h"

#include "scenarios/world/world.h"
#include "scenarios/report/output.h"

namespace rcsim {

namespace {

using sc_core::sc_time;

// Wire numbers: port p's TXD is 2p, its RXD 2p + 1, then these.
constexpr unsigned kPorts = World::kPorts;
constexpr unsigned kInta = 2 * kPorts;
constexpr unsigned kBusyLeft = kInta + 1;
constexpr unsigned kBusyRight = kInta + 2;
constexpr unsigned kWires = kBusyRight + 1;

std::vector<std::string> wire_names() {
    std::vector<std::string> n;
    for (unsigned p = 0; p < kPorts; ++p) {
        n.push_back("port" + std::to_string(p) + "_txd");
        n.push_back("port" + std::to_string(p) + "_rxd");
    }
    n.insert(n.end(), {"inta", "dpram_busy_l", "dpram_busy_r"});
    return n;
}

} // namespace

VcdTrace::VcdTrace(sc_core::sc_module_name name, World& world, const std::string& path)
    : sc_module(name), file_(open_vcd(path)), signals_("wire"), wake_("wake"),
      clock_(sc_core::sc_time(1.0 / static_cast<double>(world.scenario().board.comm.cpu_hz), sc_core::SC_SEC)) {
    const std::vector<std::string> names = wire_names();
    wires_.resize(kWires);
    // Serial wires idle at MARK; INTA and BUSY start deasserted.
    signals_.init(kWires, [&names](const char*, std::size_t i) {
        return new sc_core::sc_signal<bool>(names[i].c_str(), i < kInta);
    });
    for (unsigned i = 0; i < kWires; ++i) {
        wires_[i].level = i < kInta;
        sc_core::sc_trace(file_, signals_[i], names[i]);
    }

    Controller& ctl = world.ctl;
    for (unsigned p = 0; p < kPorts; ++p)
        sc_core::sc_trace(file_, ctl.comm.uart_int[p], "ir" + std::to_string(p));
    sc_core::sc_trace(file_, ctl.int_l, "ir3_int_l");
    sc_core::sc_trace(file_, ctl.int_r, "int_r");
    sc_core::sc_trace(file_, ctl.comm.intr, "intr");

    for (unsigned p = 0; p < kPorts; ++p) trace_line(world.lines[p], 2 * p, 2 * p + 1);
    // T1 is the kernel time of the INTA cycle (the CPU syncs before each access); INTA# falls at
    // T2 and rises at T4.
    ctl.comm.pic.on_inta = [this](const Pic8259::IntaEvent& e) {
        schedule(e.time + clock_, kInta, Input::level, true);
        schedule(e.time + 3 * clock_, kInta, Input::level, false);
    };
    ctl.dpram.on_busy = [this](const Idt7130::BusyEvent& e) {
        const unsigned w = e.port == Idt7130::left_port ? kBusyLeft : kBusyRight;
        schedule(e.busy_low, w, Input::level, true);
        schedule(e.busy_high, w, Input::level, false);
    };

    SC_HAS_PROCESS(VcdTrace);
    SC_METHOD(apply);
    sensitive << wake_;
    dont_initialize();
}

VcdTrace::~VcdTrace() { close(); }

void VcdTrace::close() {
    if (file_) sc_core::sc_close_vcd_trace_file(file_);
    file_ = nullptr;
}

// Side a of every line is the 82510: what it sends is its TXD, what side b sends its RXD.
void VcdTrace::trace_line(SerialLine& line, unsigned txd, unsigned rxd) {
    // The world watches every transmitted character too (its line faults): keep its hook.
    line.on_transmit = [this, txd, rxd, before = line.on_transmit](const SerialLine::Traced& t) {
        if (before) before(t);
        if (t.dropped) return; // a dropped character never reaches the wire
        const unsigned w = t.from == SerialLine::a ? txd : rxd;
        for (unsigned i = 0; i < t.word.ncells; ++i)
            schedule(t.start + t.word.bit.span(2 * i), w, Input::level, (t.word.cells >> i) & 1);
        // After the first STOP the transmitter's wire is at MARK (further STOP bits are MARK).
        schedule(t.start + t.word.bit.span(2 * t.word.ncells), w, Input::level, true);
    };
    line.on_break_level = [this, txd, rxd](SerialLine::Side from, bool held) {
        schedule(sc_core::sc_time_stamp(), from == SerialLine::a ? txd : rxd, Input::hold, held);
    };
}

void VcdTrace::schedule(const sc_time& at, unsigned wire, Input input, bool value) {
    const sc_time now = sc_core::sc_time_stamp();
    const sc_time when = at < now ? now : at; // a hook never reports the past; never trace it there
    pending_.emplace(when, Change{wire, input, value});
    wake_.notify(when - now); // an earlier pending notification stays, a later one is replaced
}

void VcdTrace::apply() {
    const sc_time now = sc_core::sc_time_stamp();
    while (!pending_.empty() && pending_.begin()->first <= now) {
        const Change c = pending_.begin()->second;
        pending_.erase(pending_.begin());
        Wire& w = wires_[c.wire];
        (c.input == Input::level ? w.level : w.held) = c.value;
        w.dirty = true;
    }
    for (unsigned i = 0; i < kWires; ++i) {
        if (!wires_[i].dirty) continue;
        wires_[i].dirty = false;
        signals_[i].write(wires_[i].level && !wires_[i].held);
    }
    if (!pending_.empty()) wake_.notify(pending_.begin()->first - now);
}

} // namespace rcsim
