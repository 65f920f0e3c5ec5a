#include "scenarios/scenario.h"

#include "scenarios/checks.h"

#include "scenarios/yaml_map.h"

#include <cmath>
#include <filesystem>
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

void read_traffic(YamlMap& m, HostTraffic& t, std::uint64_t seed) {
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
    t.seed = seed;
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

PortScenario read_port(const YAML::Node& n, const std::string& file, const std::string& ctx,
                       const std::filesystem::path& dir, std::uint64_t seed) {
    YamlMap m(n, file, ctx);
    PortScenario p;
    const std::string host = m.get<std::string>("host", "none");
    const SerialFormat fmt = format_value(m, "format");
    if (host == "protocol") {
        p.host = PortScenario::Host::protocol;
        p.protocol.format = fmt;
        read_traffic(m, p.protocol.traffic, seed);
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
        if (m.has("record")) {
            std::filesystem::path rec = m.get<std::string>("record", "");
            p.raw.record_path = rec.is_absolute() ? rec.string() : (dir / rec).string();
        }
    } else if (host == "tcp") {
        p.host = PortScenario::Host::tcp;
        p.tcp.format = fmt;
        const std::string listen = m.get<std::string>("listen", "127.0.0.1:0");
        try {
            p.tcp.set_listen(listen);
        } catch (const std::exception& e) {
            m.fail(m.child("listen"), std::string("bad 'listen': ") + e.what());
        }
        if (m.has("record")) p.tcp.record_path = path_value(m, "record", dir);
        if (m.has("port_file")) p.tcp.port_file = path_value(m, "port_file", dir);
    } else if (host == "replay") {
        p.host = PortScenario::Host::replay;
        p.replay.file = path_value(m, "file", dir);
        if (m.has("format")) p.replay.format = fmt;
        if (m.has("record")) p.replay.record_path = path_value(m, "record", dir);
    } else if (host != "none") {
        m.fail(m.child("host"), "unknown host '" + host + "' (protocol, raw, tcp, replay or none)");
    }
    if (m.has("log")) {
        if (p.host != PortScenario::Host::protocol)
            m.fail(m.child("log"), "'" + ctx + "log' is the protocol host's transaction log; this port's host is '" +
                                       host + "'");
        std::filesystem::path log = m.get<std::string>("log", "");
        p.log_path = log.is_absolute() ? log.string() : (dir / log).string();
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
    if (m.has("quantum_us") && !(m.number("quantum_us", 10, 0, 1e6) >= clock_us)) {
        std::ostringstream os;
        os << "'board.quantum_us' = " << m.number("quantum_us", 10, 0, 1e6) << " must be at least one CPU clock ("
           << clock_us << " us at " << c.cpu_hz << " Hz) and at most 1e6";
        m.fail(m.child("quantum_us"), os.str());
    }
    c.quantum = us_value(m, "quantum_us", to_us(c.quantum), 1e6);
    c.lookahead = m.get<bool>("lookahead", true);
    c.fast_sync = m.get<bool>("fast_sync", true); // speed-ups: off gives the same results, slower
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

void read_main_cpu(YamlMap m, MainCpuConfig& c, bool& motion) {
    motion = m.get<bool>("motion", false);
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
    try {
        c.validate();
    } catch (const std::exception& e) {
        m.fail(e.what());
    }
    m.finish();
}

void read_checks(YamlMap m, CheckLimits& c) {
    c.max_overruns = m.integer("max_overruns", 0, 0, 1000000000000000);
    c.max_frames_failed = m.integer("max_frames_failed", 0, 0, 1000000000000000);
    c.max_frame_mismatches = m.integer("max_frame_mismatches", 0, 0, 1000000000000000);
    c.max_bus_errors = m.integer("max_bus_errors", 0, 0, 1000000000000000);
    c.max_char_latency_us = optional_number(m, "max_char_latency_us", 0, 1e9);
    c.min_margin_us = m.number("min_margin_us", 0, -1e9, 1e9);
    if (m.has("min_worst_margin_us")) c.min_worst_margin_us = m.number("min_worst_margin_us", 0, -1e9, 1e9);
    if (m.has("min_frames_delivered"))
        c.min_frames_delivered = m.integer("min_frames_delivered", 0, 0, 1000000000000000);
    // `NAME: off` switches a check off; any other value for a check's name is an error.
    for (const std::string& name : communication_check_names()) {
        if (!m.has(name)) continue;
        if (m.get<std::string>(name, "") != "off")
            m.fail(m.child(name), "checks." + name + ": the only value a check name takes is 'off'");
        c.off.insert(name);
    }
    m.finish();
}

} // namespace

SerialFormat PortScenario::format() const {
    switch (host) {
    case Host::raw: return raw.format;
    case Host::tcp: return tcp.format;
    case Host::replay: return replay.format ? *replay.format : SerialFormat::rs232(9600);
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
    s.seed = top.get<std::uint64_t>("seed", 1);
    if (top.has("rom")) {
        std::filesystem::path rom = top.get<std::string>("rom", "");
        s.rom = rom.is_absolute() ? rom.string() : (dir / rom).string();
    }
    s.budget_us = optional_number(top, "budget_us", 0, 1e9);
    if (s.budget_us == 0) top.fail(top.child("budget_us"), "'budget_us' must be > 0");
    read_board(top.map("board"), s.board);
    read_main_cpu(top.map("main_cpu"), s.board.main, s.main_motion);
    read_checks(top.map("checks"), s.checks);
    if (top.has("ports")) {
        YAML::Node ports = top.child("ports");
        if (!ports.IsSequence() || ports.size() > CommBoard::kPorts)
            top.fail(ports, "'ports' must be a list of at most 3 ports");
        for (std::size_t i = 0; i < ports.size(); ++i)
            s.ports[i] = read_port(ports[i], path, "ports[" + std::to_string(i) + "].", dir, s.seed * 1000 + i);
    }
    bool interactive = false; // a tcp or replay host can end the run by itself
    for (auto& p : s.ports) {
        if (p.host == PortScenario::Host::tcp || p.host == PortScenario::Host::replay) interactive = true;
        p.tcp.end_on_disconnect = s.duration_s == 0;
        p.replay.end_at_log_end = s.duration_s == 0;
    }
    if (s.duration_s == 0 && !interactive)
        top.fail(top.child("duration_s"), "'duration_s: 0' (run until the session ends) needs a tcp or replay host");
    if (s.duration_s > 0 && s.duration_s < 1e-6) top.fail(top.child("duration_s"), "'duration_s' must be 0 or >= 1e-6");
    s.has_motion = top.has("motion");
    top.child("motion"); // read by the motion layer
    top.child("monitor"); // read by the remote monitor (scenarios/monitor/board_monitor.h)
    if (s.has_motion && top.has("ports"))
        top.fail(top.child("motion"), "a 'motion' section runs the motion side alone; with 'ports' use "
                                      "'main_cpu: {motion: true}' and motion tokens from the hosts");
    top.finish();
    return s;
}

} // namespace rcsim
