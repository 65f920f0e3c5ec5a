#include "scenarios/config/scenario.h"

#include "scenarios/config/check_names.h"

#include "scenarios/config/yaml_map.h"

#include "main_cpu/motion/motion_controller.h"
#include "main_cpu/st/program.h"

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace rcsim {

namespace {

constexpr std::size_t kMaxRawSends = 100000;           // entries of a raw host's `send:` list
constexpr std::size_t kMaxRawSendBytes = 1u << 20;      // their bytes in all
constexpr std::size_t kMaxFaults = 10000;               // entries of a port's `faults:` list
constexpr double kMinCyclePeriodUs = 10;                // main_cpu.cycle_period_us
constexpr double kMinAckTimeoutUs = 1;                  // main_cpu.ack_timeout_us
constexpr double kMinRealtime = 0.01;                   // realtime (other than 0)

sc_core::sc_time ms_value(YamlMap& m, const std::string& key, double fallback_ms, double hi_ms = 1e7) {
    const double v = m.number(key, fallback_ms, 0, hi_ms);
    return ps(static_cast<std::uint64_t>(v * 1e9 + 0.5));
}

sc_core::sc_time us_value(YamlMap& m, const std::string& key, double fallback_us, double hi_us = 1e10) {
    const double v = m.number(key, fallback_us, 0, hi_us);
    return ps(static_cast<std::uint64_t>(v * 1e6 + 0.5));
}

SerialFormat format_value(YamlMap& m, const std::string& key) {
    const std::string text = m.get<std::string>(key, "9600,8E1");
    try {
        return SerialFormat::parse(text);
    } catch (const std::exception& e) {
        // parse() names the text itself; validate()'s messages do not.
        const std::string why = e.what();
        m.fail(m.child(key), why.find(text) != std::string::npos ? why : "bad serial format '" + text + "': " + why);
    }
}

/// An optional setting whose absence means "derived" (stored as -1): when present it must lie in
/// [lo, hi] (a written -1 or -0.5 is an error, not the default).
double optional_number(YamlMap& m, const std::string& key, double lo, double hi) {
    return m.has(key) ? m.number(key, 0, lo, hi) : -1;
}

constexpr std::size_t kMaxScriptSteps = 100000; // entries of a scripted host's `script:` list

/// One entry of a scripted host's `script:` (docs/scenarios.md "Scripted hosts"): exactly one of
/// `token` (a command), `wait_state` (poll ST until the robot state) and `delay_ms`.
ScriptStep read_script_step(const YAML::Node& n, const std::string& file, const std::string& ctx) {
    YamlMap s(n, file, ctx);
    ScriptStep st;
    st.line = YamlMap::line_of(n);
    const int kinds = s.has("token") + s.has("wait_state") + s.has("delay_ms");
    if (kinds != 1) s.fail("a script step has exactly one of 'token', 'wait_state' and 'delay_ms'");
    st.at = ms_value(s, "at_ms", 0);
    if (s.has("token")) {
        st.token = s.require<std::string>("token");
        st.data = s.get<std::string>("data", "");
        st.wait_response = s.choice("wait", "response", {"response", "none"}) == "response";
        if (s.has("expect_bch")) {
            if (!st.wait_response) s.fail(s.child("expect_bch"), "'" + s.context() + "expect_bch' needs 'wait: response'");
            st.expect_bch = static_cast<int>(s.integer("expect_bch", 0, 0, 255));
        }
        try {
            proto::encode(proto::Frame{st.token, 0, st.data});
        } catch (const std::exception& e) {
            s.fail(s.child(s.has("data") ? "data" : "token"), std::string("this command cannot be sent: ") + e.what());
        }
    } else if (s.has("wait_state")) {
        st.kind = ScriptStep::Kind::wait_state;
        st.token = "ST";
        st.state = s.require<std::string>("wait_state");
        if (st.state.empty() || st.state.find(',') != std::string::npos)
            s.fail(s.child("wait_state"), "'" + s.context() + "wait_state' must be one state name (no comma)");
        st.poll = ms_value(s, "poll_ms", 10, 3.6e6);
        if (st.poll == sc_core::SC_ZERO_TIME) s.fail(s.child("poll_ms"), "'" + s.context() + "poll_ms' must be > 0");
        st.timeout = ms_value(s, "timeout_ms", 10000, 3.6e6);
    } else {
        st.kind = ScriptStep::Kind::delay;
        st.duration = ms_value(s, "delay_ms", 0, 3.6e6);
    }
    s.finish();
    return st;
}

void read_traffic(YamlMap& m, HostTraffic& t) {
    const std::string pattern = m.get<std::string>("traffic", "none");
    try {
        t.pattern = HostTraffic::parse_pattern(pattern);
    } catch (const std::exception& e) {
        m.fail(m.child("traffic"), e.what());
    }
    t.rate = m.number("rate_hz", t.rate, 1e-6, 1e6);
    t.burst_size = static_cast<unsigned>(m.integer("burst_size", t.burst_size, 1, 1000000));
    t.burst_period = ms_value(m, "burst_period_ms", 1000);
    t.count = m.integer("count", 0, 0, 1000000000000);
    t.start = ms_value(m, "start_ms", 0);
    t.data_size = static_cast<std::size_t>(m.integer("data_size", t.data_size, 0, proto::max_data));
    t.random_size = m.get<bool>("random_size", false);
    t.wait_response = m.get<bool>("wait_response", true);
    t.response_timeout = ms_value(m, "response_timeout_ms", 1000);
    if (m.has("script")) {
        if (t.pattern != HostTraffic::Pattern::script)
            m.fail(m.child("script"), "'" + m.context() + "script' needs 'traffic: script'");
        const YAML::Node steps = m.child("script");
        if (!steps.IsSequence() || steps.size() > kMaxScriptSteps)
            m.fail(steps, "'" + m.context() + "script' must be a list of at most " + std::to_string(kMaxScriptSteps) +
                              " steps");
        for (std::size_t i = 0; i < steps.size(); ++i)
            t.script.push_back(read_script_step(steps[i], m.file(), m.context() + "script[" + std::to_string(i) + "]."));
    }
    if (t.pattern == HostTraffic::Pattern::script && t.script.empty())
        m.fail(m.has("script") ? m.child("script") : m.child("traffic"),
               "'" + m.context() + "traffic: script' needs a non-empty 'script' list");
    if (m.has("tokens")) {
        YAML::Node tokens = m.child("tokens");
        if (!tokens.IsMap() || tokens.size() == 0)
            m.fail(tokens, "'" + m.context() + "tokens' must map tokens to weights, e.g. {EC: 1, ST: 1}");
        t.tokens.clear();
        for (const auto& kv : tokens) {
            if (!kv.first.IsScalar()) m.fail(kv.first, "a token must be two characters, not '" + YAML::Dump(kv.first) + "'");
            const auto token = kv.first.Scalar();
            double weight = 0;
            try {
                weight = kv.second.as<double>();
            } catch (const YAML::Exception&) {
                m.fail(kv.second, "bad weight for token '" + token + "'");
            }
            if (token.size() != 2 || !(weight > 0) || !std::isfinite(weight))
                m.fail(kv.first, "token '" + token + "' must be two characters with a finite weight > 0");
            t.tokens.emplace_back(token, weight);
        }
    }
}

/// Faults are checked against the port's format (the line applies them to the sending side's
/// characters; the controller's 82510 runs the same format, docs/scenarios.md "Faults"):
/// flip_data_bit takes a data bit, flip_cell a cell through the first STOP bit (0 = START).
LineFault read_fault(const YAML::Node& n, const std::string& file, const std::string& ctx, const SerialFormat& fmt) {
    YamlMap m(n, file, ctx);
    LineFault f;
    f.kind = m.require<std::string>("kind");
    const std::string from = m.get<std::string>("from", "host");
    if (from == "host") f.from = LineFault::From::host;
    else if (from == "controller") f.from = LineFault::From::controller;
    else m.fail(m.child("from"), "'from' must be host or controller, not '" + from + "'");
    if (f.kind == "break") {
        f.at = ms_value(m, "at_ms", 0);
        f.duration = ms_value(m, "duration_ms", 10);
    } else if (f.kind == "flip_data_bit" || f.kind == "flip_cell" || f.kind == "drop" || f.kind == "corrupt_stop") {
        f.index = m.integer("index", 0, 0, 1000000000000000);
        const unsigned cells = 1 + fmt.data_bits + (fmt.parity == Parity::none ? 0 : 1) + 1;
        if (f.kind == "flip_data_bit" || f.kind == "flip_cell") {
            const bool cell = f.kind == "flip_cell";
            const unsigned limit = cell ? cells : fmt.data_bits;
            const std::uint64_t bit = m.integer("bit", 0, 0, 1000);
            if (bit >= limit)
                m.fail(m.child("bit"), "'" + ctx + "bit' = " + std::to_string(bit) + " is not " +
                                           (cell ? "a cell" : "a data bit") + " of a " + fmt.describe() +
                                           " character (0.." + std::to_string(limit - 1) + ")");
            f.bit = static_cast<unsigned>(bit);
        } else if (m.has("bit")) {
            m.fail(m.child("bit"), "'" + ctx + "bit' applies to flip_data_bit and flip_cell, not " + f.kind);
        }
    } else {
        m.fail(m.child("kind"), "unknown fault kind '" + f.kind +
                                    "' (flip_data_bit, flip_cell, drop, corrupt_stop, break)");
    }
    m.finish();
    return f;
}

std::string path_value(YamlMap& m, const std::string& key, const std::filesystem::path& dir) {
    std::filesystem::path f = m.require<std::string>(key);
    return f.is_absolute() ? f.string() : (dir / f).string();
}

/// A pty host's `link:`: a symlink rcsim may make there. Checked now, so that the error names
/// the scenario line: a symlink must be possible in its folder, and the path, if it exists, must be
/// a symlink (a stale link of an earlier run is replaced; a file or folder is never).
std::string pty_link_value(YamlMap& m, const std::filesystem::path& dir) {
    const std::string link = path_value(m, "link", dir);
    const std::filesystem::path folder = std::filesystem::path(link).parent_path();
    std::error_code ec;
    const auto st = std::filesystem::symlink_status(link, ec);
    if (std::filesystem::exists(st) && !std::filesystem::is_symlink(st))
        m.fail(m.child("link"), "'link' " + link + " exists and is not a symlink (rcsim replaces only a symlink)");
    if (!folder.empty() && !std::filesystem::is_directory(folder, ec))
        m.fail(m.child("link"), "'link' " + link + ": no folder " + folder.string());
    // Whether a symlink can be made there (permissions, a read-only or special file system) is
    // known only by making one: a probe beside the link, removed at once.
    const std::string probe = link + ".probe" + std::to_string(::getpid());
    const std::string where = folder.empty() ? "." : folder.string();
    if (::symlink("/dev/null", probe.c_str()) != 0)
        m.fail(m.child("link"), "'link' " + link + ": cannot make a symlink in " + where + ": " + std::strerror(errno));
    ::unlink(probe.c_str());
    return link;
}

PortScenario read_port(const YAML::Node& n, const std::string& file, const std::string& ctx,
                       const std::filesystem::path& dir) {
    YamlMap m(n, file, ctx);
    PortScenario p;
    const std::string host = m.get<std::string>("host", "none");
    const SerialFormat fmt = format_value(m, "format");
    if (host == "protocol") {
        p.host = PortScenario::Host::protocol;
        p.protocol.format = fmt;
        read_traffic(m, p.protocol.traffic);
        p.protocol.nak_enqs = static_cast<unsigned>(m.integer("nak_enqs", 0, 0, 1000000));
        try {
            p.protocol.validate();
        } catch (const std::exception& e) {
            m.fail(e.what());
        }
    } else if (host == "raw") {
        p.host = PortScenario::Host::raw;
        p.raw.format = fmt;
        if (m.has("send")) {
            YAML::Node sends = m.child("send");
            if (!sends.IsSequence() || sends.size() > kMaxRawSends)
                m.fail(sends, "'" + ctx + "send' must be a list of at most " + std::to_string(kMaxRawSends) +
                                  " {at_ms, bytes}");
            std::size_t total = 0;
            for (std::size_t i = 0; i < sends.size(); ++i) {
                YamlMap s(sends[i], file, ctx + "send[" + std::to_string(i) + "].");
                const auto at = ms_value(s, "at_ms", 0);
                const auto bytes = s.require<std::string>("bytes");
                try {
                    p.raw.add(at, bytes);
                } catch (const std::exception& e) {
                    s.fail(s.child("bytes"), e.what());
                }
                total += p.raw.sends.back().bytes.size();
                if (total > kMaxRawSendBytes)
                    s.fail(s.child("bytes"), "'" + ctx + "send' holds more than " + std::to_string(kMaxRawSendBytes) +
                                                 " bytes in all");
                s.finish();
            }
        }
        if (m.has("record")) p.raw.record_path = m.require<std::string>("record");
    } else if (host == "tcp") {
        p.host = PortScenario::Host::tcp;
        p.tcp.format = fmt;
        const std::string listen = m.get<std::string>("listen", "127.0.0.1:0");
        try {
            p.tcp.set_listen(listen);
        } catch (const std::exception& e) {
            m.fail(m.child("listen"), std::string("bad 'listen': ") + e.what());
        }
        if (m.has("record")) p.tcp.record_path = m.require<std::string>("record");
        if (m.has("port_file")) p.tcp.port_file = m.require<std::string>("port_file");
        p.tcp.telnet = m.get<bool>("telnet", false);
        if (m.has("break_ms") && !p.tcp.telnet)
            m.fail(m.child("break_ms"), "'" + ctx + "break_ms' is the length of a telnet IAC BRK: it needs 'telnet: true'");
        p.tcp.break_duration = ms_value(m, "break_ms", 250, 10000);
        // Shorter than one of the port's characters, the SPACE is no BREAK to the receiver but a
        // character read from the wire (docs/serial.md "BREAK").
        if (p.tcp.telnet && !(p.tcp.break_duration > fmt.receive_time()))
            m.fail(m.child("break_ms"), "'" + ctx + "break_ms' must be longer than one " + fmt.describe() +
                                            " character (" + std::to_string(to_us(fmt.receive_time()) / 1000) + " ms)");
    } else if (host == "replay") {
        p.host = PortScenario::Host::replay;
        p.replay.file = path_value(m, "file", dir);
        if (m.has("format")) p.replay.format = fmt;
        if (m.has("record")) p.replay.record_path = m.require<std::string>("record");
    } else if (host == "pty") {
        p.host = PortScenario::Host::pty;
        p.pty.format = fmt;
        if (m.has("link")) p.pty.link = pty_link_value(m, dir);
    } else if (host != "none") {
        m.fail(m.child("host"), "unknown host '" + host + "' (protocol, raw, tcp, replay, pty or none)");
    }
    if (m.has("log")) {
        if (p.host != PortScenario::Host::protocol)
            m.fail(m.child("log"), "'" + ctx + "log' is the protocol host's transaction log; this port's host is '" +
                                       host + "'");
        p.log_path = m.require<std::string>("log");
    }
    p.noise_per_bit = m.number("noise_per_bit", 0, 0, 1);
    if (m.has("faults")) {
        YAML::Node faults = m.child("faults");
        if (!faults.IsSequence() || faults.size() > kMaxFaults)
            m.fail(faults, "'" + ctx + "faults' must be a list of at most " + std::to_string(kMaxFaults));
        for (std::size_t i = 0; i < faults.size(); ++i)
            p.faults.push_back(read_fault(faults[i], file, ctx + "faults[" + std::to_string(i) + "].", fmt));
    }
    m.finish();
    return p;
}

void read_board(YamlMap m, ControllerConfig& b) {
    CommBoardConfig& c = b.comm;
    c.cpu_hz = m.integer("cpu_hz", c.cpu_hz, 100000, 100000000);
    c.uart_clock_hz = m.integer("uart_clock_hz", c.uart_clock_hz, 100000, 100000000);
    // At least one CPU clock: a shorter slice cannot hold a cycle and the decoupling would spin.
    const double clock_us = 1e6 / static_cast<double>(c.cpu_hz);
    // The default is the board's (CommBoardConfig::quantum), read once.
    const double quantum_us = m.number("quantum_us", to_us(c.quantum), 0, 1e6);
    if (!(quantum_us >= clock_us)) {
        std::ostringstream os;
        os << "'board.quantum_us' = " << quantum_us << " must be at least one CPU clock (" << clock_us << " us at "
           << c.cpu_hz << " Hz) and at most 1e6";
        m.fail(m.child("quantum_us"), os.str());
    }
    c.quantum = ps(static_cast<std::uint64_t>(quantum_us * 1e6 + 0.5));
    c.lookahead = m.get<bool>("lookahead", true);
    c.fast_sync = m.get<bool>("fast_sync", true); // speed-ups: off gives the same results, slower
    c.fast_forward = m.get<bool>("fast_forward", true);
    c.stable_reads = m.get<bool>("stable_reads", true);
    c.slice_chain = m.get<bool>("slice_chain", true);
    YamlMap w = m.map("wait_states");
    c.ram_wait = static_cast<unsigned>(w.integer("ram", c.ram_wait, 0, 64));
    c.rom_wait = static_cast<unsigned>(w.integer("rom", c.rom_wait, 0, 64));
    c.dpram_wait = static_cast<unsigned>(w.integer("dpram", c.dpram_wait, 0, 64));
    c.io_wait = static_cast<unsigned>(w.integer("io", c.io_wait, 0, 64));
    w.finish();
    const double grade = m.number("dpram_speed_grade_ns", b.dpram_speed_grade_ns, 20, 100);
    if (grade != 20 && grade != 25 && grade != 35 && grade != 55 && grade != 100)
        m.fail(m.child("dpram_speed_grade_ns"), "'board.dpram_speed_grade_ns' must be 20, 25, 35, 55 or 100");
    b.dpram_speed_grade_ns = static_cast<unsigned>(grade);
    m.finish();
}

/// The largest Structured Text program rcsim reads (a program is a few kilobytes).
constexpr std::uintmax_t kMaxProgramBytes = 1u << 20;

/// main_cpu.program (relative to the scenario's folder) and main_cpu.statement_budget. The text
/// is compiled here, for the four axes of the motion layer or none without it, so that a parse or
/// type error ends the run before anything is built: one message, file:line:column.
std::optional<Scenario::Program> read_program(YamlMap& m, const std::filesystem::path& dir, bool motion) {
    namespace fs = std::filesystem;
    if (!m.has("program")) {
        if (m.has("statement_budget"))
            m.fail(m.child("statement_budget"), "'main_cpu.statement_budget' bounds a program: it needs 'main_cpu.program'");
        return std::nullopt;
    }
    Scenario::Program p;
    const fs::path rel = m.require<std::string>("program");
    p.path = (rel.is_absolute() ? rel : dir / rel).string();
    const std::string cannot = "cannot read the Structured Text program '" + p.path + "'";
    std::error_code ec;
    if (!fs::is_regular_file(p.path, ec)) m.fail(m.child("program"), cannot + " (no such regular file)");
    const std::uintmax_t size = fs::file_size(p.path, ec);
    if (!ec && size > kMaxProgramBytes)
        m.fail(m.child("program"), cannot + ": it is " + std::to_string(size) + " bytes, a program is at most " +
                                       std::to_string(kMaxProgramBytes));
    std::ifstream in(p.path);
    std::stringstream text;
    text << in.rdbuf();
    if (!in) m.fail(m.child("program"), cannot);
    p.text = text.str();
    p.budget = static_cast<std::uint64_t>(m.integer("statement_budget", 100000, 1, 1000000000));
    try {
        st::StProgram(p.text, p.path, std::vector<motion::McAxis*>(motion ? motion::MotionController::axes : 0));
    } catch (const st::CompileError& e) {
        throw ConfigError(e.what());
    }
    return p;
}

void read_main_cpu(YamlMap m, MainCpuConfig& c, bool& motion, std::optional<Scenario::Csp>& csp,
                   TrajectoryOptions& trajectory, const std::filesystem::path& dir,
                   std::optional<Scenario::Program>& program) {
    motion = m.get<bool>("motion", false);
    program = read_program(m, dir, motion);
    if (m.has("trajectory")) {
        if (!motion) m.fail(m.child("trajectory"), "'main_cpu.trajectory' needs 'main_cpu.motion: true'");
        trajectory = read_trajectory_options(m.map("trajectory"));
    }
    if (m.has("csp")) {
        if (!motion) m.fail(m.child("csp"), "'main_cpu.csp' is a path of the motion layer: it needs 'main_cpu.motion: true'");
        YamlMap p = m.map("csp");
        Scenario::Csp k;
        k.radius = p.number("radius", k.radius, 1, 1e9);
        k.velocity = p.number("velocity", k.velocity, 1, 1e7);
        k.start_ms = p.number("start_ms", k.start_ms, 0, 3.6e6);
        k.sync_offset_us = p.number("sync_offset_us", k.sync_offset_us, 0, 3.6e9);
        p.finish();
        csp = k;
    }
    c.bus_clock_hz = m.integer("bus_clock_hz", c.bus_clock_hz, 100000, 1000000000);
    // Upper bounds: one hour, the longest run. Lower bounds keep the main CPU's threads from
    // waking more often than its bus could act (a 1 ps control cycle would never let time pass).
    c.irq_entry = us_value(m, "irq_entry_us", to_us(c.irq_entry), 3.6e9);
    c.command_time = us_value(m, "command_time_us", to_us(c.command_time), 3.6e9);
    if (m.has("cycle_period_us")) m.number("cycle_period_us", 0, kMinCyclePeriodUs, 3.6e9);
    c.cycle_period = us_value(m, "cycle_period_us", to_us(c.cycle_period), 3.6e9);
    c.cycle_time = us_value(m, "cycle_time_us", to_us(c.cycle_time), 3.6e9);
    if (m.has("ack_timeout_us")) m.number("ack_timeout_us", 0, kMinAckTimeoutUs, 3.6e9);
    c.ack_timeout = us_value(m, "ack_timeout_us", to_us(c.ack_timeout), 3.6e9);
    c.fb_call = us_value(m, "fb_call_us", to_us(c.fb_call), 1e6);
    c.statement_time = us_value(m, "statement_us", to_us(c.statement_time), 1000);
    try {
        c.validate();
    } catch (const std::exception& e) {
        m.fail(e.what());
    }
    m.finish();
}

void read_checks(YamlMap m, CheckLimits& c, bool main_motion) {
    for (const char* k : {"circle", "final_state", "max_cycle_jitter_us", "max_command_latency_us", "max_csp_missed_sync"})
        if (m.has(k) && !main_motion)
            m.fail(m.child(k), "'checks." + std::string(k) + "' judges the motion layer: it needs 'main_cpu: {motion: true}'");
    c.max_overruns = m.integer("max_overruns", 0, 0, 1000000000000000);
    c.max_frames_failed = m.integer("max_frames_failed", 0, 0, 1000000000000000);
    c.max_frame_mismatches = m.integer("max_frame_mismatches", 0, 0, 1000000000000000);
    c.max_bus_errors = m.integer("max_bus_errors", 0, 0, 1000000000000000);
    c.max_char_latency_us = optional_number(m, "max_char_latency_us", 0, 1e9);
    c.min_margin_us = m.number("min_margin_us", 0, -1e9, 1e9);
    c.min_worst_margin_us = m.number("min_worst_margin_us", 0, -1e9, 1e9);
    if (m.has("min_frames_delivered"))
        c.min_frames_delivered = m.integer("min_frames_delivered", 0, 0, 1000000000000000);
    if (m.has("circle")) {
        YamlMap cc = m.map("circle");
        CheckLimits::Circle c2;
        c2.center_x = cc.require_number("center_x", -1e10, 1e10);
        c2.center_y = cc.require_number("center_y", -1e10, 1e10);
        c2.radius = cc.require_number("radius", 0, 1e10);
        c2.max_radial_error = cc.number("max_radial_error", 1, 0, 1e10);
        c2.max_end_error = cc.number("max_end_error", 0, 0, 1e10);
        cc.finish();
        c.circle = c2;
    }
    c.motion_final_state = m.get<std::string>("final_state", "");
    if (m.has("max_cycle_jitter_us")) c.max_cycle_jitter_us = m.number("max_cycle_jitter_us", 0, 0, 1e9);
    if (m.has("max_command_latency_us")) c.max_command_latency_us = m.number("max_command_latency_us", 0, 0, 1e9);
    c.max_csp_missed_sync = m.integer("max_csp_missed_sync", 0, 0, 1000000000000000);
    // `NAME: off` switches a check off; any other value for a check's name is an error.
    for (const std::string& name : communication_check_names()) {
        if (!m.has(name)) continue;
        if (m.get<std::string>(name, "") != "off")
            m.fail(m.child(name), "checks." + name + ": the only value a check name takes is 'off'");
        c.off.insert(name);
    }
    // An optional check (the static bound's) is off unless switched on; `off` says so explicitly.
    for (const std::string& name : optional_check_names()) {
        if (!m.has(name)) continue;
        const std::string v = m.get<std::string>(name, "");
        if (v != "on" && v != "off")
            m.fail(m.child(name), "checks." + name + ": 'on' or 'off' (it is off unless switched on)");
        if (v == "on") c.on.insert(name);
    }
    m.finish();
}


/// `rom: FILE` or `rom: {even: FILE, odd: FILE}` (an EPROM pair); relative to the scenario's folder.
RomSource read_rom(YamlMap& top, const std::filesystem::path& dir) {
    if (top.child("rom").IsMap()) {
        YamlMap pair = top.map("rom");
        RomSource rom{path_value(pair, "even", dir), path_value(pair, "odd", dir)};
        pair.finish();
        return rom;
    }
    if (top.get<std::string>("rom", "").empty()) top.fail(top.child("rom"), "'rom' is empty (leave it out for the built firmware)");
    return {path_value(top, "rom", dir), {}};
}
} // namespace

motion::MotionConfig motion_config(const Scenario& s) {
    motion::MotionConfig c;
    const MainCpuConfig& m = s.board.main;
    c.cost.bus_cycle = sc_core::sc_time(1.0 / static_cast<double>(m.bus_clock_hz), sc_core::SC_SEC);
    c.cost.access_cycles = m.access_cycles;
    c.cost.fb_call = m.fb_call;
    c.first_pulse_poll = sc_core::sc_time(1, sc_core::SC_US);
    if (s.csp) {
        motion::MotionConfig::Csp k;
        k.radius = s.csp->radius, k.velocity = s.csp->velocity;
        k.start = sc_core::sc_time(s.csp->start_ms * 1e9, sc_core::SC_PS);
        k.sync_offset = sc_core::sc_time(s.csp->sync_offset_us * 1e6, sc_core::SC_PS);
        k.period = m.cycle_period;
        c.csp = k;
    }
    return c;
}

std::vector<std::string*> Scenario::output_files() {
    std::vector<std::string*> out;
    for (PortScenario& p : ports)
        for (std::string* f : {&p.log_path, &p.raw.record_path, &p.tcp.record_path, &p.tcp.port_file, &p.replay.record_path})
            if (!f->empty()) out.push_back(f);
    return out;
}

void Scenario::place_outputs(const std::filesystem::path& out_dir) {
    std::set<std::string> seen;
    for (std::string* f : output_files()) {
        const std::filesystem::path p = *f;
        if (p.is_relative()) *f = (out_dir / p).lexically_normal().string();
        // Two outputs in one file would interleave or overwrite each other: bad input.
        std::error_code ec;
        const std::filesystem::path key = std::filesystem::weakly_canonical(*f, ec);
        if (!seen.insert(ec ? *f : key.string()).second)
            throw ConfigError(file, 0, "two outputs of the run are the same file '" + *f + "' (log:, record:, port_file:)");
    }
}

void Scenario::set_seed(std::uint64_t run_seed) {
    seed = run_seed;
    for (unsigned p = 0; p < ports.size(); ++p) ports[p].protocol.traffic.seed = traffic_seed(p);
}

SerialFormat PortScenario::format() const {
    switch (host) {
    case Host::raw: return raw.format;
    case Host::tcp: return tcp.format;
    case Host::replay: return replay.format ? *replay.format : SerialFormat::rs232(9600);
    case Host::pty: return pty.format;
    default: return protocol.format;
    }
}

Scenario load_scenario(const std::string& path) {
    Scenario s;
    s.file = path;
    s.root = load_yaml_file(path);
    if (!s.root.IsDefined() || s.root.IsNull())
        throw ConfigError(path, 0, "the scenario file is empty (write {} for a run with every default)");
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    YamlMap top(s.root, path, "");
    s.name = top.get<std::string>("name", std::filesystem::path(path).stem().string());
    s.duration_s = top.number("duration_s", 1.0, 0, 3600);
    if (top.has("realtime")) {
        // 0 is off; a factor below kMinRealtime would stretch the run without bound in wall time.
        s.realtime = top.get<double>("realtime", 0);
        if (!(s.realtime == 0 || (s.realtime >= kMinRealtime && s.realtime <= 1e6)))
            top.fail(top.child("realtime"), "'realtime' = " + top.get<std::string>("realtime", "") +
                                                " must be 0 (off) or in [0.01, 1e6]");
    }
    s.drain_s = top.number("drain_s", 1.0, 0, 3600);
    const std::uint64_t seed = top.get<std::uint64_t>("seed", 1);
    if (top.has("rom")) s.rom = read_rom(top, dir);
    s.budget_us = optional_number(top, "budget_us", 0, 1e9);
    if (s.budget_us == 0) top.fail(top.child("budget_us"), "'budget_us' must be > 0");
    read_board(top.map("board"), s.board);
    read_main_cpu(top.map("main_cpu"), s.board.main, s.main_motion, s.csp, s.trajectory, dir, s.program);
    if (s.csp && s.csp->sync_offset_us >= to_us(s.board.main.cycle_period))
        top.fail(top.child("main_cpu"), "'main_cpu.csp.sync_offset_us' must be shorter than 'main_cpu.cycle_period_us'");
    read_checks(top.map("checks"), s.checks, s.main_motion);
    if (top.has("ports")) {
        YAML::Node ports = top.child("ports");
        if (!ports.IsSequence() || ports.size() > CommBoard::kPorts)
            top.fail(ports, "'ports' must be a list of at most 3 ports");
        for (std::size_t i = 0; i < ports.size(); ++i)
            s.ports[i] = read_port(ports[i], path, "ports[" + std::to_string(i) + "].", dir);
    }
    bool interactive = false; // a tcp or replay host can end the run by itself
    for (auto& p : s.ports) {
        if (p.host == PortScenario::Host::tcp || p.host == PortScenario::Host::replay ||
            p.host == PortScenario::Host::pty)
            interactive = true;
        p.tcp.end_on_disconnect = s.duration_s == 0;
        p.pty.end_on_disconnect = s.duration_s == 0;
        p.replay.end_at_log_end = s.duration_s == 0;
    }
    if (s.duration_s == 0 && !interactive)
        top.fail(top.child("duration_s"), "'duration_s: 0' (run until the session ends) needs a tcp, pty or replay host");
    if (s.duration_s > 0 && s.duration_s < 1e-6) top.fail(top.child("duration_s"), "'duration_s' must be 0 or >= 1e-6");
    s.set_seed(seed);
    s.has_motion = top.has("motion");
    if (s.has_motion && top.has("ports"))
        top.fail(top.child("motion"), "a 'motion' section runs the motion side alone; with 'ports' use "
                                      "'main_cpu: {motion: true}' and motion tokens from the hosts");
    if (s.has_motion) s.motion = read_motion_plan(s.root, path);
    top.child("motion");
    s.monitor = monitor::read_monitor_section(s.root, path);
    top.child("monitor");
    s.search = read_search_section(s.root, path);
    top.child("search");
    top.finish();
    return s;
}

} // namespace rcsim
