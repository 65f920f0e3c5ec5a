#include "scenarios/world/world.h"

#include "models/plumbing/config_error.h"
#include "models/dpram_layout.h"
#include "models/plumbing/stop_signal.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <iostream>
#include <string>

namespace rcsim {

namespace {

using sc_core::sc_time;
constexpr unsigned kDpramDataBytes = dpram_layout::ports * dpram_layout::area_size; // data[p] and pflag[p]

FaultKind fault_kind(const std::string& k) {
    if (k == "flip_data_bit") return FaultKind::flip_data_bit;
    if (k == "flip_cell") return FaultKind::flip_cell;
    if (k == "drop") return FaultKind::drop;
    return FaultKind::corrupt_stop;
}

} // namespace

World::World(sc_core::sc_module_name name, const Scenario& s)
    : sc_module(name), ctl("controller", s.board), lines("line", kPorts),
      probe("probe", ctl.comm.cpu,
            {&ctl.comm.uart_int[0], &ctl.comm.uart_int[1], &ctl.comm.uart_int[2], &ctl.int_l},
            s.board.comm.pic_io_base, s.board.comm.dpram_base, kDpramDataBytes),
      scenario_(s) {
    for (unsigned p = 0; p < kPorts; ++p) {
        ctl.comm.uart[p].connect(lines[p], SerialLine::a);
        attach_host(p, s.ports[p]);
        ctl.comm.uart[p].on_char_read = [this, p](const Uart82510::CharTiming& c) {
            recent_reads_[p].push_back(c.read);
            const double wait = to_us(c.read - c.stop);
            char_latency_us[p].add(wait);
            if (char_latency_us[p].count() == 1 || wait > char_latency_worst[p].wait_us)
                char_latency_worst[p] = {wait, c.stop, c.read};
        };
        lines[p].on_deliver = [this, p](const SerialLine::Delivered& d) { observe_line(p, d); };
        observers[p].clock = [] { return to_us(sc_core::sc_time_stamp()); };
        // A faulted character is counted when it starts: its cause has that time.
        lines[p].on_transmit = [this, p](const SerialLine::Traced& t) { sync_line_faults(p, &t); };
    }
    if (s.main_motion) {
        motion = std::make_unique<motion::MotionController>("motion", motion_config(s));
        if (s.trajectory.pulse_trace) // trajectory_pulses.csv (docs/motion.md "Trajectory pictures")
            for (unsigned a = 0; a < motion::MotionController::axes; ++a) motion->chip().trace_pulses(a, true);
        ctl.set_motion(motion.get());
    }
    if (s.program) load_program(*s.program);
    probe.keep_records(false);
    probe.watch_pic(ctl.comm.pic); // what the 8259A held each request for (latency causes)
    probe.fifo_level = [this](unsigned level) { return ctl.comm.uart[level].rx_level(); }; // IR0..2: port 0..2
    ctl.main.keep_history(false);
    ctl.main.on_received = [this](const FrameRecord& f) {
        if (f.port < kPorts)
            observers[f.port].main_received(frame_key(f.token, f.bch, f.data), frame_label(f.token, f.bch, f.data));
    };
    ctl.main.on_sent = [this](const FrameRecord& f) {
        if (f.port < kPorts)
            observers[f.port].main_handed(frame_key(f.token, f.bch, f.data), frame_label(f.token, f.bch, f.data));
    };
    probe.on_record = [this](const InterruptRecord& r) { on_record(r); };
    probe.on_settled = [this](const sc_time& h) { on_settled(h); };
    probe.on_dpram_write = [this](const i8086::BusRecord& r, const sc_time& t) { watch_dpram(r, t); };
    bool any_tcp = false;
    for (const auto& h : tcp) any_tcp = any_tcp || h;
    for (const auto& h : pty) any_tcp = any_tcp || h; // a terminal's timeouts are wall-clock too
    const double rtf = s.realtime >= 0 ? s.realtime : any_tcp ? 1.0 : 0.0;
    if (rtf > 0) pacer = std::make_unique<RealtimePacer>("pacer", rtf);
    SC_THREAD(inject_breaks);
}

// The text compiled when the scenario was read (scenario.h): this cannot fail. The program's
// AXIS_REFs are the motion layer's axes, its MC_Power drives the layer's own.
void World::load_program(const Scenario::Program& p) {
    std::vector<motion::McAxis*> axes;
    std::vector<motion::MC_Power*> power;
    for (unsigned a = 0; motion && a < motion::MotionController::axes; ++a) {
        axes.push_back(&motion->axis(a));
        power.push_back(&motion->power(a));
    }
    program = std::make_unique<st::StProgram>(p.text, p.path, axes, power, st::StProgram::Config{p.budget});
    ctl.main.set_program(program.get());
}

const char* World::host_kind(unsigned p) const {
    return protocol[p] ? "protocol" : raw[p] ? "raw" : tcp[p] ? "tcp" : replay[p] ? "replay" : pty[p] ? "pty" : "none";
}

void World::attach_host(unsigned p, const PortScenario& ps) {
    const std::string n = "host" + std::to_string(p);
    if (ps.host == PortScenario::Host::protocol) {
        protocol[p] = std::make_unique<ProtocolHost>(n.c_str(), ps.protocol);
        protocol[p]->connect(lines[p], SerialLine::b);
        protocol[p]->keep_history(false);
        if (!ps.log_path.empty()) {
            logs_[p].emplace(ps.log_path, "the host log");
            protocol[p]->log_to(&logs_[p]->stream());
        }
    } else if (ps.host == PortScenario::Host::raw) {
        raw[p] = std::make_unique<RawHost>(n.c_str(), ps.raw);
        raw[p]->connect(lines[p], SerialLine::b);
    } else if (ps.host == PortScenario::Host::tcp) {
        tcp[p] = std::make_unique<TcpHost>(n.c_str(), ps.tcp);
        tcp[p]->connect(lines[p], SerialLine::b);
        std::cout << "port " << p << ": tcp host listening on " << tcp[p]->endpoint() << std::endl;
    } else if (ps.host == PortScenario::Host::replay) {
        replay[p] = std::make_unique<ReplayHost>(n.c_str(), ps.replay);
        replay[p]->connect(lines[p], SerialLine::b);
    } else if (ps.host == PortScenario::Host::pty) {
        pty[p] = std::make_unique<PtyHost>(n.c_str(), ps.pty);
        pty[p]->connect(lines[p], SerialLine::b);
        std::cout << "port " << p << ": pty host at " << pty[p]->slave_path()
                  << (ps.pty.link.empty() ? "" : " (link " + ps.pty.link + ")") << std::endl;
    }
    if (ps.noise_per_bit > 0) lines[p].set_noise(ps.noise_per_bit, scenario_.noise_seed(p));
    for (const LineFault& f : ps.faults) {
        if (f.kind == "break") continue;
        const auto from = f.from == LineFault::From::host ? SerialLine::b : SerialLine::a;
        lines[p].inject(from, f.index, fault_kind(f.kind), f.bit);
    }
}

void World::inject_breaks() {
    struct Brk { sc_time at, duration; unsigned port; SerialLine::Side from; };
    std::vector<Brk> breaks;
    for (unsigned p = 0; p < kPorts; ++p)
        for (const LineFault& f : scenario_.ports[p].faults)
            if (f.kind == "break")
                breaks.push_back({f.at, f.duration, p,
                                  f.from == LineFault::From::host ? SerialLine::b : SerialLine::a});
    std::stable_sort(breaks.begin(), breaks.end(), [](const Brk& a, const Brk& b) { return a.at < b.at; });
    for (const Brk& b : breaks) {
        if (b.at > sc_core::sc_time_stamp()) wait(b.at - sc_core::sc_time_stamp());
        inject_break(b.port, b.from, b.duration);
    }
}

void World::inject_break(unsigned p, SerialLine::Side from, const sc_time& duration) {
    sync_main_side();
    observers[p].line_fault({from == SerialLine::b ? "BREAK from the host" : "BREAK from the controller (injected)",
                             to_us(sc_core::sc_time_stamp())});
    lines[p].insert_break(from, duration);
}

// What the scenario did to each line since the last look, from the line's own counters (they
// count at the faulted character's START, where on_transmit looks at once; a BREAK at its fall):
// each is a cause for the frames on their way on that port (LineObserver::line_fault). Every host-side BREAK is the scenario's (a
// host is part of it); the controller's side only when the world injected it (inject_break).
void World::sync_line_faults() {
    for (unsigned p = 0; p < kPorts; ++p) sync_line_faults(p);
}

void World::sync_line_faults(unsigned p, const SerialLine::Traced* sent) {
    for (const SerialLine::Side side : {SerialLine::a, SerialLine::b}) {
        const SerialLine::Stats& now = lines[p].stats(side);
        SerialLine::Stats& seen = line_stats_seen_[p][side];
        const bool host = side == SerialLine::b;
        // The character being sent is the one hit (a fault counts at its START); the observer
        // counts the attempts it destroyed. A dropped one kept its bits: its byte is known (the
        // low 7 data bits after START: the control bytes are ASCII, whatever the format).
        std::optional<LineObserver::HitChar> hit;
        if (sent && sent->from == side) {
            hit = LineObserver::HitChar{host ? LineObserver::host_to_controller : LineObserver::controller_to_host, {}};
            if (sent->dropped) hit->byte = static_cast<std::uint8_t>((sent->word.cells >> 1) & 0x7F);
        }
        auto note = [&](std::uint64_t cur, std::uint64_t& old, const char* what, bool a_character = true) {
            if (cur == old) return;
            old = cur;
            observers[p].line_fault({what, to_us(sc_core::sc_time_stamp())},
                                    a_character ? hit : std::nullopt);
        };
        note(now.dropped, seen.dropped, host ? "injected fault: a host character dropped"
                                             : "injected fault: a controller character dropped");
        note(now.faults, seen.faults, host ? "injected fault: a host character altered"
                                           : "injected fault: a controller character altered");
        note(now.noise_flips, seen.noise_flips, host ? "noise on a host character" : "noise on a controller character");
        if (host) note(now.breaks, seen.breaks, "BREAK from the host", false);
    }
}

// DP-RAM forwarding: data bytes written into data[p], closed by the 0x1p word in int2rbt.
void World::watch_dpram(const i8086::BusRecord& r, const sc_time& t) {
    namespace L = dpram_layout;
    const std::uint32_t off = r.address - scenario_.board.comm.dpram_base;
    if (off < kDpramDataBytes && off % L::area_size != L::chunk_size) {
        dpram_.data_write(off / L::area_size, t, r.width);
        return;
    }
    sync_main_side();
    const std::uint8_t word = r.data & 0xFF;
    if (off != L::int2rbt || L::word_port(word) >= kPorts) return;
    const unsigned port = L::word_port(word);
    switch (L::word_kind(word)) {
    case L::kind_chunk: dpram_.chunk_closed(port); break;
    case L::kind_reset: observers[port].port_reset(false); break;
    case L::kind_gave_up:
    case L::kind_gave_up_sent: observers[port].response_given_up(); break;
    default: break;
    }
}

// Side a of every line is the controller's 82510, side b the host.
void World::observe_line(unsigned p, const SerialLine::Delivered& d) {
    sync_main_side();
    const auto dir = d.from == SerialLine::a ? LineObserver::controller_to_host : LineObserver::host_to_controller;
    if (d.kind == SerialLine::Delivered::character)
        observers[p].line_char(dir, static_cast<std::uint8_t>(d.rx.data & 0xFF), d.rx.parity_error || d.rx.framing_error);
    else if (d.kind == SerialLine::Delivered::break_on)
        observers[p].line_break(dir);
}

// The main CPU's frames reach the observers through on_received/on_sent as they happen; a reset
// it asks for (0x3p in int2ext) is read from its counter, and the faults on the lines from theirs
// (sync_line_faults). Cheap when nothing changed; called on every line character and every
// DP-RAM mailbox write of the comm CPU.
void World::sync_main_side() {
    sync_line_faults();
    const MainCpu& m = ctl.main;
    // A reset the main CPU asks for drops the comm CPU's transmit ring too.
    for (unsigned p = 0; p < kPorts; ++p)
        for (; main_resets_seen_[p] < m.port_stats(p).resets_sent; ++main_resets_seen_[p])
            observers[p].port_reset(true);
}

// A run a signal stopped (no drain) leaves the frames still on their way in flight, not lost.
void World::finish_observers() {
    sync_main_side();
    const bool interrupted = stop_signal() != 0;
    for (LineObserver& o : observers) o.finish(interrupted);
}

// A completed interrupt, in entry order. It is an rs232_rx interrupt when its port's RXD was
// read between its first instruction and its IRET. Those reads came after the probe last settled
// (the handler was entered after that), and are in time order.
void World::on_record(const InterruptRecord& r) {
    bool rx = false;
    if (r.level < kPorts) {
        const auto& reads = recent_reads_[r.level];
        const auto it = std::lower_bound(reads.begin(), reads.end(), r.first_isr);
        rx = it != reads.end() && *it <= r.iret_done;
    }
    if (rx && !r.startup) { // start-up interrupts are reported apart, judged by no check
        if (rx_service_.count() == 0 || r.service_us() > rx_longest_.service_us()) rx_longest_ = r;
        rx_service_.add(r.service_us());
        if (r.has_rise) rx_latency_.add(r.latency_us());
        rx_worst_.add(r);
    }
    if (r.depth == 0) dpram_.interrupt(r.inta1, r.iret_done);
    if (sink_) sink_->record(r, rx);
}

// Every later record was entered after now: reads before now are of no more use to on_record.
void World::on_settled(const sc_time& horizon) {
    const sc_time now = sc_core::sc_time_stamp();
    for (auto& reads : recent_reads_)
        while (!reads.empty() && reads.front() < now) reads.pop_front();
    dpram_.settle();
    if (sink_) sink_->settle(horizon);
}

void World::finish() {
    probe.flush();
    dpram_.finish();
    if (sink_) sink_->finish();
}

void World::drain(double drain_s) {
    for (auto& h : protocol)
        if (h) h->stop_traffic();
    const sc_time step = us(10000);
    const sc_time end = sc_core::sc_time_stamp() + ps(static_cast<std::uint64_t>(drain_s * 1e12 + 0.5));
    // In flight: a protocol host's command or awaited response, or a response the main CPU owes
    // or has handed to DP-RAM and the comm CPU has not finished (EOT, given up or reset). Every
    // command the main CPU dispatched is answered by one response (main_cpu/README.md).
    auto busy = [this] {
        for (auto& h : protocol)
            if (h && !h->idle()) return true;
        sync_main_side();
        for (unsigned p = 0; p < kPorts; ++p) {
            const MainCpuPortStats& m = ctl.main.port_stats(p);
            if (observers[p].responses_in_flight() > 0 ||
                m.frames_received > m.frames_sent + m.tx_aborted + m.ack_timeouts)
                return true;
        }
        return false;
    };
    while (busy() && sc_core::sc_time_stamp() < end && stop_signal() == 0)
        start_for(std::min(step, end - sc_core::sc_time_stamp()));
}

void World::finish_files() {
    for (unsigned p = 0; p < kPorts; ++p) {
        if (logs_[p]) logs_[p]->check();
        if (raw[p]) raw[p]->finish_files();
        if (tcp[p]) tcp[p]->finish_log();
        if (replay[p]) replay[p]->finish_log();
    }
}

} // namespace rcsim
