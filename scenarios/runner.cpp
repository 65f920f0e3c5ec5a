#include "scenarios/runner.h"

#include "models/config_error.h"
#include "scenarios/interrupt_probe.h"
#include "models/stats.h"
#include "scenarios/report_html.h"
#include "main_cpu/motion/motion_controller.h"
#include "scenarios/motion_scenario.h"
#include "scenarios/trajectory_report.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <ostream>
#include <sstream>

#ifndef RCSIM_COMM_FW_ROM
#define RCSIM_COMM_FW_ROM ""
#endif

namespace rcsim {

namespace {

using sc_core::sc_time;
constexpr unsigned kPorts = CommBoard::kPorts;
constexpr unsigned kDpramDataBytes = 3 * 340; // data[p] and pflag[p] of the three ports
// The paper's Table 3 (HP 8086 emulator measurements).
constexpr double kPaperRs232IsrUs = 82.0;
constexpr double kPaperDpramByteUs = 52.553;
constexpr unsigned kRxFifoDepth = 4; // 82510 RX FIFO

FaultKind fault_kind(const std::string& k) {
    if (k == "flip_data_bit") return FaultKind::flip_data_bit;
    if (k == "flip_cell") return FaultKind::flip_cell;
    if (k == "drop") return FaultKind::drop;
    return FaultKind::corrupt_stop;
}

/// One chunk the comm CPU wrote into DP-RAM: its data-byte writes, closed by its 0x1p mailbox
/// word. The time per byte is measured over the data writes only (first to last), so waiting for
/// the mailbox to be free is not counted as processing.
struct DpramChunk {
    unsigned port = 0;
    sc_time first, last; // T1 of the first and of the last data write
    std::uint64_t writes = 0, bytes = 0;
};

/// The simulated world of one run: the controller, three lines, the hosts, the probes.
class Bench : public sc_core::sc_module {
public:
    Controller ctl;
    sc_core::sc_vector<SerialLine> lines;
    std::array<std::unique_ptr<ProtocolHost>, kPorts> protocol;
    std::array<std::unique_ptr<RawHost>, kPorts> raw;
    std::array<std::unique_ptr<TcpHost>, kPorts> tcp;
    std::array<std::unique_ptr<ReplayHost>, kPorts> replay;
    std::unique_ptr<RealtimePacer> pacer; // with a tcp host, or `realtime:` set
    InterruptProbe probe;
    std::array<std::vector<sc_time>, kPorts> char_reads;
    std::array<Samples, kPorts> char_latency_us;
    std::vector<DpramChunk> chunks;
    std::unique_ptr<motion::MotionController> motion;

    SC_HAS_PROCESS(Bench);
    Bench(sc_core::sc_module_name name, const Scenario& s)
        : sc_module(name), ctl("controller", s.board), lines("line", kPorts),
          probe("probe", ctl.comm.cpu,
                {&ctl.comm.uart_int[0], &ctl.comm.uart_int[1], &ctl.comm.uart_int[2], &ctl.int_l},
                s.board.comm.pic_io_base, s.board.comm.dpram_base, kDpramDataBytes),
          scenario_(s) {
        for (unsigned p = 0; p < kPorts; ++p) {
            ctl.comm.uart[p].connect(lines[p], SerialLine::a);
            attach_host(p, s.ports[p]);
            ctl.comm.uart[p].on_char_read = [this, p](const Uart82510::CharTiming& c) {
                char_reads[p].push_back(c.read);
                char_latency_us[p].add(to_us(c.read - c.stop));
            };
        }
        if (s.main_motion) {
            motion = std::make_unique<motion::MotionController>("motion");
            ctl.set_motion(motion.get());
        }
        probe.on_dpram_write = [this](const i8086::BusRecord& r, const sc_time& t) { watch_dpram(r, t); };
        bool any_tcp = false;
        for (const auto& h : tcp) any_tcp = any_tcp || h;
        const double rtf = s.realtime >= 0 ? s.realtime : any_tcp ? 1.0 : 0.0;
        if (rtf > 0) pacer = std::make_unique<RealtimePacer>("pacer", rtf);
        SC_THREAD(inject_breaks);
    }

private:
    const Scenario& scenario_;
    std::array<int, kPorts> open_chunk_{-1, -1, -1};
    std::array<std::ofstream, kPorts> logs_;

    void attach_host(unsigned p, const PortScenario& ps) {
        const std::string n = "host" + std::to_string(p);
        if (ps.host == PortScenario::Host::protocol) {
            protocol[p] = std::make_unique<ProtocolHost>(n.c_str(), ps.protocol);
            protocol[p]->connect(lines[p], SerialLine::b);
            if (!ps.log_path.empty()) {
                logs_[p].open(ps.log_path);
                if (!logs_[p]) throw ConfigError(ps.log_path, 0, "cannot write the host log");
                protocol[p]->log_to(&logs_[p]);
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
        }
        if (ps.noise_per_bit > 0) lines[p].set_noise(ps.noise_per_bit, scenario_.seed * 7919 + p);
        for (const LineFault& f : ps.faults) {
            if (f.kind == "break") continue;
            const auto from = f.from == LineFault::From::host ? SerialLine::b : SerialLine::a;
            lines[p].inject(from, f.index, fault_kind(f.kind), f.bit);
        }
    }

    void inject_breaks() {
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
            lines[b.port].insert_break(b.from, b.duration);
        }
    }

    // DP-RAM forwarding: data bytes written into data[p], closed by the 0x1p word in int2rbt.
    void watch_dpram(const i8086::BusRecord& r, const sc_time& t) {
        const std::uint32_t off = r.address - scenario_.board.comm.dpram_base;
        if (off < kDpramDataBytes && off % 340 != 339) {
            const unsigned port = off / 340;
            if (open_chunk_[port] < 0) {
                open_chunk_[port] = static_cast<int>(chunks.size());
                chunks.push_back({port, t, t, 0, 0});
            }
            DpramChunk& ch = chunks[open_chunk_[port]];
            ch.last = t;
            ++ch.writes;
            ch.bytes += r.width;
        } else if (off == Idt7130::kMailboxRight && (r.data & 0xF0) == 0x10 && (r.data & 0x0F) < kPorts) {
            open_chunk_[r.data & 0x0F] = -1;
        }
    }
};

/// Interrupt handler time that falls inside [a, b] (the part of a chunk copy spent in ISRs).
double isr_time_inside_us(const InterruptProbe& probe, const sc_time& a, const sc_time& b) {
    double sum = 0;
    for (const auto& r : probe.records()) {
        if (r.depth != 0) continue; // nested time is already inside its parent
        const sc_time lo = std::max(a, r.inta1), hi = std::min(b, r.iret_done);
        if (hi > lo) sum += to_us(hi - lo);
    }
    return sum;
}

bool read_char_inside(const std::vector<sc_time>& reads, const sc_time& a, const sc_time& b) {
    auto it = std::lower_bound(reads.begin(), reads.end(), a);
    return it != reads.end() && *it <= b;
}

nlohmann::json samples_json(const Samples& s) { return to_json(s.summary()); }

/// The probe's records for interrupts.csv and report.html, with the rs232_rx classification.
std::vector<report::InterruptRow> interrupt_rows(const Bench& b) {
    std::vector<report::InterruptRow> rows;
    for (const auto& r : b.probe.records())
        rows.push_back(report::row_of(r, r.level < kPorts && read_char_inside(b.char_reads[r.level], r.first_isr, r.iret_done)));
    return rows;
}

struct Collected {
    nlohmann::json interrupts = nlohmann::json::object();
    Samples rs232_rx_service, rs232_rx_latency;
    double dpram_byte_us = 0;
    std::uint64_t dpram_bytes = 0;
};

Collected collect_interrupts(const Bench& b) {
    Collected c;
    static const char* names[] = {"rs232_0", "rs232_1", "rs232_2", "dpram"};
    for (unsigned level = 0; level < 4; ++level) {
        nlohmann::json j;
        j["count"] = b.probe.of_level(level).size();
        j["latency_us"] = samples_json(b.probe.latency_us(level));
        j["service_us"] = samples_json(b.probe.service_us(level));
        c.interrupts[names[level]] = j;
    }
    // RS-232 interrupts that took at least one character out of the RX FIFO (the paper's
    // "RS-232 interrupt"; the others are the firmware's timer tick and transmit interrupts).
    for (unsigned p = 0; p < kPorts; ++p)
        for (const auto* r : b.probe.of_level(p))
            if (read_char_inside(b.char_reads[p], r->first_isr, r->iret_done)) {
                c.rs232_rx_service.add(r->service_us());
                if (r->has_rise) c.rs232_rx_latency.add(r->latency_us());
            }
    c.interrupts["rs232_rx"] = {{"count", c.rs232_rx_service.count()},
                                {"latency_us", samples_json(c.rs232_rx_latency)},
                                {"service_us", samples_json(c.rs232_rx_service)}};
    // Per byte: the span of a chunk's data writes over the writes it holds (n writes, n-1 gaps),
    // less the interrupt handlers that ran inside it.
    double time_us = 0;
    std::uint64_t gaps = 0;
    for (const DpramChunk& ch : b.chunks) {
        if (ch.writes < 2) continue;
        time_us += to_us(ch.last - ch.first) - isr_time_inside_us(b.probe, ch.first, ch.last);
        gaps += ch.writes - 1;
        c.dpram_bytes += ch.bytes;
    }
    c.dpram_byte_us = gaps ? time_us / static_cast<double>(gaps) : 0;
    return c;
}

nlohmann::json port_json(const Bench& b, unsigned p) {
    const auto& u = b.ctl.comm.uart[p].stats();
    nlohmann::json j;
    j["host"] = b.protocol[p] ? "protocol" : b.raw[p] ? "raw" : b.tcp[p] ? "tcp" : b.replay[p] ? "replay" : "none";
    std::uint64_t sent = 0, delivered = 0, failed = 0, naks = 0, retries = 0;
    if (const auto& h = b.protocol[p]) {
        const auto& c = h->counters();
        sent = c.frames_sent, delivered = c.frames_delivered, failed = c.frames_failed;
        naks = c.naks, retries = c.retries;
        j["responses_received"] = c.responses_received;
        j["timeouts"] = c.timeouts;
        j["collisions"] = c.collisions;
        j["delivery_us"] = samples_json(h->delivery_us());
        j["response_us"] = samples_json(h->response_us());
    }
    if (const auto& h = b.raw[p]) {
        j["bytes_sent"] = h->bytes_sent();
        j["bytes_received"] = h->received().size();
    }
    if (const auto& h = b.tcp[p]) {
        const auto c = h->counters();
        j["tcp"] = {{"listen", h->endpoint()},   {"connections", c.connections}, {"bytes_in", c.bytes_in},
                    {"bytes_sent", c.bytes_sent}, {"bytes_received", c.bytes_received}, {"bytes_out", c.bytes_out},
                    {"bytes_buffered", c.bytes_buffered}, {"bytes_dropped", c.bytes_dropped}};
    }
    if (const auto& h = b.replay[p]) {
        const auto& c = h->counters();
        j["replay"] = {{"bytes_sent", c.bytes_sent},         {"bytes_late", c.bytes_late},
                       {"bytes_received", c.bytes_received}, {"out_expected", c.out_expected},
                       {"out_matched", c.out_matched},       {"out_mismatched", c.out_mismatched},
                       {"out_missing", h->out_missing()},   {"first_mismatch", h->first_mismatch()}};
    }
    j["frames_sent"] = sent;
    j["frames_delivered"] = delivered;
    j["frames_failed"] = failed;
    j["naks"] = naks;
    j["retries"] = retries;
    j["overruns"] = u.overruns;
    j["parity_errors"] = u.parity_errors;
    j["framing_errors"] = u.framing_errors;
    j["break_detects"] = u.break_detects;
    j["rx_fifo_high_water"] = u.rx_fifo_high_water;
    j["chars_received"] = u.chars_received;
    j["chars_sent"] = u.chars_sent;
    j["char_latency_us"] = samples_json(b.char_latency_us[p]);
    j["main_cpu_frames_received"] = b.ctl.main.port_stats(p).frames_received;
    j["main_cpu_frames_sent"] = b.ctl.main.port_stats(p).frames_sent;
    return j;
}

nlohmann::json check(const std::string& name, bool passed, double value, double limit) {
    return {{"name", name}, {"passed", passed}, {"value", value}, {"limit", limit}};
}

/// The drain phase: the hosts start no new command; the run goes on in 10 ms steps until every
/// host is idle (its last command answered) or `drain_s` has passed, so that frames in flight at
/// the end are not counted as lost.
void drain(Bench& b, double drain_s) {
    for (auto& h : b.protocol)
        if (h) h->stop_traffic();
    const sc_time step = us(10000);
    const sc_time end = sc_core::sc_time_stamp() + ps(static_cast<std::uint64_t>(drain_s * 1e12 + 0.5));
    auto busy = [&b] {
        for (auto& h : b.protocol)
            if (h && !h->idle()) return true;
        return false;
    };
    while (busy() && sc_core::sc_time_stamp() < end) sc_core::sc_start(std::min(step, end - sc_core::sc_time_stamp()));
}

/// Frames the host saw EOT for that the main CPU did not receive intact, in order, exactly once.
std::uint64_t frame_mismatches(const ProtocolHost& host, const MainCpu& main, unsigned port) {
    std::vector<const FrameRecord*> got;
    for (const auto& r : main.received())
        if (r.port == port) got.push_back(&r);
    const auto& sent = host.delivered();
    std::uint64_t bad = sent.size() > got.size() ? sent.size() - got.size() : got.size() - sent.size();
    for (std::size_t i = 0; i < std::min(sent.size(), got.size()); ++i)
        if (sent[i].token != got[i]->token || sent[i].bch != got[i]->bch || sent[i].data != got[i]->data) ++bad;
    return bad;
}

/// Creates --out DIR before the run, so that a bad path fails at once and not after the simulation.
void prepare_out_dir(const std::string& dir) {
    if (dir.empty()) return;
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir))
        throw ConfigError("--out '" + dir + "': cannot create the output directory" + (ec ? ": " + ec.message() : ""));
}

/// Writes DIR/report.json; a failed write is an error, not a silently missing report.
void write_report_json(const std::filesystem::path& dir, const nlohmann::json& report) {
    const std::filesystem::path file = dir / "report.json";
    std::ofstream out(file);
    out << report.dump(2) << "\n";
    out.flush();
    if (!out) throw ConfigError(file.string(), 0, "cannot write the report");
}

/// SystemC appends ".vcd" to the name it is given: --vcd x.vcd writes x.vcd (not x.vcd.vcd), --vcd x
/// writes x.vcd. A file that cannot be written is bad input, not a SystemC error.
sc_core::sc_trace_file* open_vcd(const std::string& path) {
    const std::string ext = ".vcd";
    const bool has_ext = path.size() > ext.size() && path.compare(path.size() - ext.size(), ext.size(), ext) == 0;
    const std::string stem = has_ext ? path.substr(0, path.size() - ext.size()) : path;
    if (!std::ofstream(stem + ext)) throw ConfigError(stem + ext, 0, "cannot write the VCD file");
    return sc_core::sc_create_vcd_trace_file(stem.c_str());
}

double default_budget_us(const Scenario& s) {
    // One character time at the slowest active port, shared by the three ports (docs/system.md §9.2).
    double char_us = to_us(SerialFormat::rs232(9600).frame_time());
    for (const auto& p : s.ports)
        if (p.host != PortScenario::Host::none) char_us = std::min(char_us, to_us(p.format().frame_time()));
    return char_us / kPorts;
}

} // namespace

/// A scenario with a `motion:` section: the motion side alone (main_cpu/motion, docs/motion.md).
/// What every report starts with. wall_time_s and rtf are the only host-dependent fields;
/// `reproducible` writes 0 for both.
nlohmann::json run_header(const Scenario& s, const RunOptions& opt, double wall) {
    const double sim_s = sc_core::sc_time_stamp().to_seconds();
    return {{"scenario", s.name},
            {"seed", s.seed},
            {"sim_time_s", sim_s},
            {"wall_time_s", opt.reproducible ? 0.0 : wall},
            {"rtf", opt.reproducible || wall <= 0 ? 0.0 : sim_s / wall}};
}

int run_motion_only(const Scenario& s, const RunOptions& opt, nlohmann::json& report) {
    const std::filesystem::path out = opt.out_dir.empty() ? std::filesystem::path(".") : std::filesystem::path(opt.out_dir);
    const auto wall0 = std::chrono::steady_clock::now();
    nlohmann::json motion_report;
    const int rc = run_motion_scenario(s.root, s.file, out, s.seed, motion_report);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    const nlohmann::json& m = motion_report.contains("motion") ? motion_report["motion"] : motion_report;
    // The error names the file and line already (main_cpu/motion/motion_scenario.h).
    if (rc == 2) throw ConfigError(m.value("error", s.file + ": bad motion section"));
    report = run_header(s, opt, wall);
    if (opt.reproducible) {
        // Output paths depend on where the run was started: keep the file names only.
        nlohmann::json clean = m;
        for (const char* k : {"trajectory_csv", "trajectory_svg"})
            if (clean.contains(k)) clean[k] = std::filesystem::path(clean[k].get<std::string>()).filename().string();
        report["motion"] = clean;
    } else {
        report["motion"] = m;
    }
    report["checks"] = nlohmann::json::array();
    for (const auto& c : m.value("checks", nlohmann::json::array())) report["checks"].push_back(c);
    report["passed"] = rc == 0;
    if (!opt.out_dir.empty()) write_report_json(out, report);
    return rc;
}

int run_scenario(Scenario s, const RunOptions& opt, nlohmann::json& report) {
    if (opt.seed) s.seed = *opt.seed;
    prepare_out_dir(opt.out_dir);
    if (s.has_motion) return run_motion_only(s, opt, report);
    for (unsigned p = 0; p < kPorts; ++p) s.ports[p].protocol.traffic.seed = s.seed * 1000 + p;
    std::string rom = opt.rom ? *opt.rom : s.rom;
    if (rom.empty()) rom = RCSIM_COMM_FW_ROM;

    Bench bench("bench", s);
    bench.ctl.comm.load_rom(rom);
    sc_core::sc_trace_file* vcd = nullptr;
    if (!opt.vcd.empty()) {
        vcd = open_vcd(opt.vcd);
        for (unsigned p = 0; p < kPorts; ++p)
            sc_core::sc_trace(vcd, bench.ctl.comm.uart_int[p], "ir" + std::to_string(p));
        sc_core::sc_trace(vcd, bench.ctl.int_l, "ir3_int_l");
        sc_core::sc_trace(vcd, bench.ctl.int_r, "int_r");
        sc_core::sc_trace(vcd, bench.ctl.comm.intr, "intr");
    }

    const auto wall0 = std::chrono::steady_clock::now();
    if (s.duration_s > 0) sc_core::sc_start(ps(static_cast<std::uint64_t>(s.duration_s * 1e12 + 0.5)));
    else sc_core::sc_start(); // duration_s 0: until a tcp client disconnects / a replay log ends (sc_pause)
    drain(bench, s.drain_s);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    if (vcd) sc_core::sc_close_vcd_trace_file(vcd);

    report = run_header(s, opt, wall);
    report["rom"] = std::filesystem::path(rom).filename().string();
    report["comm_cpu"] = {{"cycles", bench.ctl.comm.cpu.cycles()},
                          {"instructions", bench.ctl.comm.cpu.instructions()},
                          {"clock_hz", s.board.comm.cpu_hz},
                          {"quantum_us", to_us(s.board.comm.quantum)}};

    const Collected c = collect_interrupts(bench);
    report["interrupts"] = c.interrupts;

    const double budget = s.budget_us > 0 ? s.budget_us : default_budget_us(s);
    const double isr = c.rs232_rx_service.summary().mean;
    const double margin = budget - (isr + c.dpram_byte_us);
    report["table3"] = {{"rs232_isr_us", isr},
                        {"rs232_isr_max_us", c.rs232_rx_service.summary().max},
                        {"dpram_byte_us", c.dpram_byte_us},
                        {"dpram_bytes_measured", c.dpram_bytes},
                        {"paper_rs232_isr_us", kPaperRs232IsrUs},
                        {"paper_dpram_byte_us", kPaperDpramByteUs},
                        {"budget_us", budget},
                        {"margin_us", margin}};

    std::uint64_t overruns = 0, failed = 0, delivered = 0, mismatches = 0;
    report["ports"] = nlohmann::json::array();
    for (unsigned p = 0; p < kPorts; ++p) {
        nlohmann::json pj = port_json(bench, p);
        overruns += pj["overruns"].get<std::uint64_t>();
        failed += pj["frames_failed"].get<std::uint64_t>();
        delivered += pj["frames_delivered"].get<std::uint64_t>();
        if (bench.protocol[p]) mismatches += frame_mismatches(*bench.protocol[p], bench.ctl.main, p);
        report["ports"].push_back(pj);
    }
    report["main_cpu"] = bench.ctl.main.report();
    report["dpram"] = {{"collisions", bench.ctl.dpram.collisions()}};
    if (bench.pacer) {
        const auto& ps_ = bench.pacer->stats();
        const bool r = opt.reproducible; // the pacer's figures measure the host
        report["realtime"] = {{"rtf_target", ps_.rtf},
                              {"naps", r ? 0 : ps_.naps},
                              {"slept_s", r ? 0.0 : ps_.slept_s},
                              {"max_lag_ms", r ? 0.0 : ps_.max_lag_s * 1e3},
                              {"max_lead_ms", r ? 0.0 : ps_.max_lead_s * 1e3}};
    }
    if (bench.motion) {
        report["motion"] = {{"state", bench.motion->state()}, {"positions", bench.motion->positions()},
                            {"samples", bench.motion->recorder().samples().size()}};
        if (!opt.out_dir.empty()) {
            const std::filesystem::path out = opt.out_dir;
            write_trajectory_csv(bench.motion->recorder(), out / "trajectory.csv");
            write_trajectory_svg(bench.motion->recorder(), out / "trajectory.svg", 0, 1, "rcsim: " + s.name);
        }
    }

    const CheckLimits& L = s.checks;
    // A character may wait in the 4-byte RX FIFO: it is lost only when its read comes later than
    // the FIFO can hold the characters behind it (fifo_depth character times).
    double char_limit = L.max_char_latency_us;
    if (char_limit < 0) char_limit = kRxFifoDepth * default_budget_us(s) * kPorts;
    double lat_max = 0;
    for (unsigned p = 0; p < kPorts; ++p) lat_max = std::max(lat_max, bench.char_latency_us[p].summary().max);
    std::uint64_t malformed = 0;
    for (unsigned p = 0; p < kPorts; ++p) malformed += bench.ctl.main.port_stats(p).malformed;
    nlohmann::json checks = nlohmann::json::array();
    checks.push_back(check("overruns", overruns <= L.max_overruns, double(overruns), double(L.max_overruns)));
    checks.push_back(check("frames_failed", failed <= L.max_frames_failed, double(failed), double(L.max_frames_failed)));
    checks.push_back(check("frames_delivered_exactly_once", mismatches <= L.max_frame_mismatches,
                           double(mismatches), double(L.max_frame_mismatches)));
    checks.push_back(check("main_cpu_malformed_frames", malformed == 0, double(malformed), 0));
    checks.push_back(check("frames_delivered", delivered >= L.min_frames_delivered, double(delivered),
                           double(L.min_frames_delivered)));
    checks.push_back(check("char_latency_max_us", lat_max <= char_limit, lat_max, char_limit));
    checks.push_back(check("table3_margin_us", margin >= L.min_margin_us, margin, L.min_margin_us));
    for (unsigned p = 0; p < kPorts; ++p)
        if (const auto& h = bench.replay[p]) {
            // The replayed session must draw the recorded answers: same bytes at the same times.
            const double bad = double(h->counters().out_mismatched + h->out_missing());
            checks.push_back(check("replay_port" + std::to_string(p) + "_matches_record", bad == 0, bad, 0));
        }
    bool passed = true;
    for (const auto& ch : checks) passed = passed && ch["passed"].get<bool>();
    report["checks"] = checks;
    report["passed"] = passed;

    if (!opt.out_dir.empty()) {
        write_report_json(opt.out_dir, report);
        report::write_report_files(opt.out_dir, report, interrupt_rows(bench));
    }
    return passed ? 0 : 1;
}

namespace {
void print_motion_summary(const nlohmann::json& r, std::ostream& os) {
    const auto& m = r["motion"];
    os << "scenario " << r["scenario"].get<std::string>() << "  seed " << r["seed"] << "  simulated "
       << r["sim_time_s"].get<double>() << " s";
    if (r["wall_time_s"].get<double>() > 0)
        os << " in " << r["wall_time_s"].get<double>() << " s wall (" << r["rtf"].get<double>() << "x real time)";
    os << "\nmotion state " << m.value("state", std::string("?"));
    if (m.contains("final_cmd_pulses")) os << ", final command " << m["final_cmd_pulses"].dump();
    if (m.contains("final_act_pulses")) os << ", final actual " << m["final_act_pulses"].dump();
    if (m.contains("max_following_error_pulses"))
        os << "\nmax following error " << m["max_following_error_pulses"].get<double>() << " pulses";
    os << "\n\nchecks\n";
    for (const auto& c : r["checks"]) os << "  " << c.dump() << "\n";
    if (m.contains("trajectory_svg")) os << "trajectory: " << m["trajectory_svg"].get<std::string>() << "\n";
    os << (r["passed"].get<bool>() ? "PASSED" : "FAILED") << "\n";
}
} // namespace

void print_summary(const nlohmann::json& r, std::ostream& os) {
    if (!r.contains("interrupts")) return print_motion_summary(r, os);
    auto f = [](double v, int prec = 1) {
        std::ostringstream s;
        s << std::fixed << std::setprecision(prec) << v;
        return s.str();
    };
    os << "scenario " << r["scenario"].get<std::string>() << "  seed " << r["seed"] << "  simulated "
       << f(r["sim_time_s"].get<double>(), 3) << " s";
    if (r["wall_time_s"].get<double>() > 0)
        os << " in " << f(r["wall_time_s"].get<double>(), 3) << " s wall (" << f(r["rtf"].get<double>(), 1)
           << "x real time)";
    os << "\n\ninterrupts (us)      count   latency mean/p99/max        service mean/p99/max\n";
    for (const char* name : {"rs232_0", "rs232_1", "rs232_2", "dpram", "rs232_rx"}) {
        const auto& i = r["interrupts"][name];
        const auto& l = i["latency_us"];
        const auto& s = i["service_us"];
        os << "  " << std::left << std::setw(16) << name << std::right << std::setw(8) << i["count"].get<std::uint64_t>()
           << std::setw(10) << f(l["mean"]) << std::setw(9) << f(l["p99"]) << std::setw(9) << f(l["max"])
           << std::setw(12) << f(s["mean"]) << std::setw(9) << f(s["p99"]) << std::setw(9) << f(s["max"]) << "\n";
    }
    const auto& t = r["table3"];
    os << "\nTable 3               simulated      paper\n"
       << "  RS-232 interrupt  " << std::setw(10) << f(t["rs232_isr_us"], 3) << " us" << std::setw(10)
       << f(t["paper_rs232_isr_us"], 3) << " us   (max " << f(t["rs232_isr_max_us"], 3) << " us)\n"
       << "  DP-RAM (1 byte)   " << std::setw(10) << f(t["dpram_byte_us"], 3) << " us" << std::setw(10)
       << f(t["paper_dpram_byte_us"], 3) << " us\n"
       << "  sum               " << std::setw(10)
       << f(t["rs232_isr_us"].get<double>() + t["dpram_byte_us"].get<double>(), 3) << " us" << std::setw(10)
       << f(t["paper_rs232_isr_us"].get<double>() + t["paper_dpram_byte_us"].get<double>(), 3) << " us\n"
       << "  budget " << f(t["budget_us"], 3) << " us, margin " << f(t["margin_us"], 3) << " us\n";
    os << "\nport  sent  delivered  failed  naks  retries  overruns  parity  framing  fifo-hw  char-latency max us\n";
    for (std::size_t p = 0; p < r["ports"].size(); ++p) {
        const auto& j = r["ports"][p];
        os << "  " << p << std::setw(7) << j["frames_sent"].get<std::uint64_t>() << std::setw(11)
           << j["frames_delivered"].get<std::uint64_t>() << std::setw(8) << j["frames_failed"].get<std::uint64_t>()
           << std::setw(6) << j["naks"].get<std::uint64_t>() << std::setw(9) << j["retries"].get<std::uint64_t>()
           << std::setw(10) << j["overruns"].get<std::uint64_t>() << std::setw(8)
           << j["parity_errors"].get<std::uint64_t>() << std::setw(9) << j["framing_errors"].get<std::uint64_t>()
           << std::setw(9) << j["rx_fifo_high_water"].get<unsigned>() << std::setw(12)
           << f(j["char_latency_us"]["max"]) << "\n";
    }
    if (r.contains("main_cpu") && r["main_cpu"].contains("cycle_jitter_us")) {
        const auto& j = r["main_cpu"]["cycle_jitter_us"];
        os << "\nmain CPU control-cycle jitter: mean " << f(j["mean"]) << " us, max " << f(j["max"]) << " us\n";
    }
    os << "\nchecks\n";
    for (const auto& c : r["checks"])
        os << "  " << (c["passed"].get<bool>() ? "PASS" : "FAIL") << "  " << std::left << std::setw(32)
           << c["name"].get<std::string>() << std::right << " value " << f(c["value"], 3) << "  limit "
           << f(c["limit"], 3) << "\n";
    os << (r["passed"].get<bool>() ? "PASSED" : "FAILED") << "\n";
}

} // namespace rcsim
