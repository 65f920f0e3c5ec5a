// rcsim — the Modbus TCP register map (see register_map.h, docs/monitor.md "Modbus TCP").
#include "scenarios/modbus/register_map.h"

#include "scenarios/monitor/board_monitor.h"
#include "scenarios/verdict/measure.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace rcsim::modbus {

namespace {

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
constexpr unsigned kParams = 8; // the mailbox's parameters: MC has the most, 6

double measured(const Samples& s, double Summary::*field) { return s.count() ? s.summary().*field : kNone; }

// ---- the run ----
double sim_time(monitor::BoardMonitor&, unsigned) { return sc_core::sc_time_stamp().to_seconds(); }
double rtf(monitor::BoardMonitor& m, unsigned) { return m.rtf(); }
double paused(monitor::BoardMonitor& m, unsigned) { return m.paused() ? 1 : 0; }
double zero(monitor::BoardMonitor&, unsigned) { return 0; }

// ---- Table 3 and the verdict: the one judge's, so far (scenarios/verdict/judge.h) ----
double table3(monitor::BoardMonitor& m, const char* key) {
    const nlohmann::json& v = m.judgement().table3[key];
    return v.is_number() ? v.get<double>() : kNone;
}
double budget(monitor::BoardMonitor& m, unsigned) { return table3(m, "budget_us"); }
double isr_mean(monitor::BoardMonitor& m, unsigned) { return table3(m, "rs232_isr_us"); }
double isr_max(monitor::BoardMonitor& m, unsigned) { return table3(m, "rs232_isr_max_us"); }
double dpram_byte(monitor::BoardMonitor& m, unsigned) { return table3(m, "dpram_byte_us"); }
double margin(monitor::BoardMonitor& m, unsigned) { return table3(m, "margin_us"); }
double worst_margin(monitor::BoardMonitor& m, unsigned) { return table3(m, "worst_margin_us"); }
double over_budget(monitor::BoardMonitor& m, unsigned) {
    const std::optional<double> b = m.judgement().budget.value;
    if (!b) return kNone;
    std::uint64_t n = 0;
    for (unsigned l = 0; l < 4; ++l) n += m.world().probe.latency_us(l).count_above(*b);
    return static_cast<double>(n);
}
// The run's verdict so far, as the run's end, the page and the API judge it: 0 not measured yet
// (inconclusive), 1 passing so far, 2 failing so far (a check failed that no later event can undo).
double verdict(monitor::BoardMonitor& m, unsigned) {
    switch (m.judgement().verdict.verdict) {
    case Verdict::passed: return 1;
    case Verdict::failed: return 2;
    default: return 0;
    }
}

// ---- per port ----
double host_step(monitor::BoardMonitor& m, unsigned p) {
    return static_cast<double>(m.world().observers[p].state(LineObserver::host_to_controller));
}
double controller_step(monitor::BoardMonitor& m, unsigned p) {
    return static_cast<double>(m.world().observers[p].state(LineObserver::controller_to_host));
}
double in_frame(monitor::BoardMonitor& m, unsigned p) {
    return host_step(m, p) == 2 || controller_step(m, p) == 2 ? 1 : 0;
}
template <std::uint64_t ProtocolHost::Counters::*Field>
double host_counter(monitor::BoardMonitor& m, unsigned p) {
    const auto& h = m.world().protocol[p];
    return h ? static_cast<double>(h->counters().*Field) : kNone;
}
double overruns(monitor::BoardMonitor& m, unsigned p) {
    return static_cast<double>(m.world().ctl.comm.uart[p].stats().overruns);
}
double frames_received(monitor::BoardMonitor& m, unsigned p) {
    return static_cast<double>(m.world().ctl.main.port_stats(p).frames_received);
}
double char_latency_max(monitor::BoardMonitor& m, unsigned p) {
    return measured(m.world().char_latency_us[p], &Summary::max);
}
double irq_latency_max(monitor::BoardMonitor& m, unsigned p) {
    return measured(m.world().probe.latency_us(p), &Summary::max);
}
double irq_latency_p99(monitor::BoardMonitor& m, unsigned p) {
    return measured(m.world().probe.latency_us(p), &Summary::p99);
}
double irq_service_max(monitor::BoardMonitor& m, unsigned p) {
    return measured(m.world().probe.service_us(p), &Summary::max);
}

// ---- per axis (none without the motion layer) ----
const motion::TrajectorySample* last_sample(monitor::BoardMonitor& m, unsigned a, std::size_t back = 0) {
    if (!m.world().motion) return nullptr;
    const motion::TrajectorySample* s = m.world().motion->recorder().last(back);
    return s && a < s->cmd.size() ? s : nullptr;
}
double cmd_pos(monitor::BoardMonitor& m, unsigned a) {
    const auto* s = last_sample(m, a);
    return s ? static_cast<double>(s->cmd[a]) : kNone;
}
double act_pos(monitor::BoardMonitor& m, unsigned a) {
    const auto* s = last_sample(m, a);
    return s ? static_cast<double>(s->act[a]) : kNone;
}
// The drive's actual velocity over the last control cycle.
double act_vel(monitor::BoardMonitor& m, unsigned a) {
    const auto *s = last_sample(m, a), *prev = last_sample(m, a, 1);
    if (!s || !prev || s->t_s <= prev->t_s) return kNone;
    return static_cast<double>(s->act[a] - prev->act[a]) / (s->t_s - prev->t_s);
}
double axis_state(monitor::BoardMonitor& m, unsigned a) {
    return m.world().motion ? static_cast<double>(m.world().motion->axis(a).state()) : kNone;
}
double axis_error_id(monitor::BoardMonitor& m, unsigned a) {
    return m.world().motion ? static_cast<double>(m.world().motion->axis(a).error_id()) : kNone;
}
double servo_on(monitor::BoardMonitor& m, unsigned a) {
    return m.world().motion && m.world().motion->power(a).Enable ? 1 : 0;
}
double power_status(monitor::BoardMonitor& m, unsigned a) {
    return m.world().motion && m.world().motion->power(a).Status ? 1 : 0;
}
// The axis's motion blocks, and the path blocks on the axes they drive (0 and 1; LM: its mask).
template <bool motion::McExecuteFb::*Flag>
bool any_block(monitor::BoardMonitor& m, unsigned a) {
    motion::MotionController* mc = m.world().motion.get();
    if (!mc) return false;
    auto& b = mc->blocks(a);
    bool on = b.home.*Flag || b.move_abs.*Flag || b.move_rel.*Flag || b.move_vel.*Flag || b.halt.*Flag || b.stop.*Flag;
    if (a < 2) on = on || mc->line_move().*Flag || mc->circle_move().*Flag;
    return on;
}
double axis_busy(monitor::BoardMonitor& m, unsigned a) { return any_block<&motion::McExecuteFb::Busy>(m, a) ? 1 : 0; }
// A token-driven block's Done lasts one control cycle (its Execute drops then), so what a client
// polling now and then can see is the axis standing still again with nothing busy.
double axis_done(monitor::BoardMonitor& m, unsigned a) {
    return m.world().motion && m.world().motion->axis(a).state() == motion::AxisState::standstill && !axis_busy(m, a) ? 1 : 0;
}
double axis_error(monitor::BoardMonitor& m, unsigned a) {
    return any_block<&motion::McExecuteFb::Error>(m, a) ||
                   (m.world().motion && m.world().motion->axis(a).state() == motion::AxisState::error_stop)
               ? 1
               : 0;
}

using T = Table;
using Y = Type;
constexpr Access R = Access::read, RW = Access::read_write;
constexpr Repeat once = Repeat::once, port = Repeat::per_port, axis = Repeat::per_axis;

const std::vector<Entry> kMap = {
    // coils
    {"pause", T::coil, 0, once, 0, Y::bit, 1, "", RW, "1 = paused: simulated time stands still; write 1 to pause and 0 to resume", paused},
    {"step", T::coil, 1, once, 0, Y::bit, 1, "", RW, "write 1: run step_ms of simulated time unpaced and stay paused; reads 0", zero},
    {"axis{n}.servo_on", T::coil, 2, axis, 1, Y::bit, 1, "", RW, "MC_Power.Enable of the axis: write 1 to enable and 0 to disable", servo_on},
    // discrete inputs
    {"axis{n}.done", T::discrete_input, 0, axis, 4, Y::bit, 1, "", R, "the axis stands still (PLCopen Standstill) with no block Busy: its last motion command is done", axis_done},
    {"axis{n}.busy", T::discrete_input, 1, axis, 4, Y::bit, 1, "", R, "a motion block of the axis (MC_LineMove2 and MC_CircleCenterMove on axes 0 and 1) is Busy", axis_busy},
    {"axis{n}.error", T::discrete_input, 2, axis, 4, Y::bit, 1, "", R, "a motion block of the axis has Error or the axis is in ErrorStop", axis_error},
    {"axis{n}.powered", T::discrete_input, 3, axis, 4, Y::bit, 1, "", R, "MC_Power.Status: the drive is in Operation enabled", power_status},
    {"port{n}.in_frame", T::discrete_input, 16, port, 1, Y::bit, 1, "", R, "a frame (SOH..ETX) is on the port's line in either direction", in_frame},
    // input registers: the run and Table 3
    {"sim_time", T::input_register, 0, once, 0, Y::u32, 1000, "s", R, "simulated time", sim_time},
    {"rtf", T::input_register, 2, once, 0, Y::u32, 1000, "", R, "real-time factor measured over the last half second of running wall time (0 while paused)", rtf},
    {"verdict", T::input_register, 4, once, 0, Y::u16, 1, "", R, "the run's verdict so far (the same judge as report.json): 0 not measured yet; 1 passing so far; 2 failing so far (a check failed that no later event can undo)", verdict},
    {"rs232_isr_mean", T::input_register, 6, once, 0, Y::u32, 1000, "us", R, "Table 3: RS-232 receive service mean so far", isr_mean},
    {"rs232_isr_max", T::input_register, 8, once, 0, Y::u32, 1000, "us", R, "Table 3: RS-232 receive service max so far", isr_max},
    {"dpram_byte", T::input_register, 10, once, 0, Y::u32, 1000, "us", R, "Table 3: DP-RAM time per byte", dpram_byte},
    {"budget", T::input_register, 12, once, 0, Y::u32, 1000, "us", R, "Table 3: the budget (the mean character arrival period or the scenario's budget_us)", budget},
    {"margin", T::input_register, 14, once, 0, Y::i32, 1000, "us", R, "Table 3: budget - (rs232_isr_mean + dpram_byte)", margin},
    {"worst_margin", T::input_register, 16, once, 0, Y::i32, 1000, "us", R, "budget - (rs232_isr_max + dpram_byte)", worst_margin},
    {"latency_over_budget", T::input_register, 18, once, 0, Y::u32, 1, "", R, "interrupt latencies (IR0..IR3) over the budget so far (reported, not judged: docs/scenarios.md \"Checks\")", over_budget},
    // input registers: per port
    {"port{n}.host_step", T::input_register, 100, port, 20, Y::u16, 1, "", R, "the host's protocol step: 0 idle; 1 ENQ sent; 2 frame on the line; 3 awaiting EOT", host_step},
    {"port{n}.controller_step", T::input_register, 101, port, 20, Y::u16, 1, "", R, "the controller's protocol step (as host_step)", controller_step},
    {"port{n}.frames_sent", T::input_register, 102, port, 20, Y::u32, 1, "", R, "frames the port's protocol host sent", host_counter<&ProtocolHost::Counters::frames_sent>},
    {"port{n}.frames_delivered", T::input_register, 104, port, 20, Y::u32, 1, "", R, "frames the protocol host had acknowledged (EOT)", host_counter<&ProtocolHost::Counters::frames_delivered>},
    {"port{n}.frames_failed", T::input_register, 106, port, 20, Y::u32, 1, "", R, "frames the protocol host gave up on", host_counter<&ProtocolHost::Counters::frames_failed>},
    {"port{n}.overruns", T::input_register, 108, port, 20, Y::u32, 1, "", R, "82510 receive overruns", overruns},
    {"port{n}.char_latency_max", T::input_register, 110, port, 20, Y::u32, 1000, "us", R, "longest wait of a character in the RX FIFO (stop bit to RXD read)", char_latency_max},
    {"port{n}.irq_latency_max", T::input_register, 112, port, 20, Y::u32, 1000, "us", R, "the port's interrupt (IR0..IR2): longest latency (IR rise to the handler's first fetch)", irq_latency_max},
    {"port{n}.irq_latency_p99", T::input_register, 114, port, 20, Y::u32, 1000, "us", R, "the port's interrupt: 99th percentile latency", irq_latency_p99},
    {"port{n}.irq_service_max", T::input_register, 116, port, 20, Y::u32, 1000, "us", R, "the port's interrupt: longest service", irq_service_max},
    {"port{n}.frames_received", T::input_register, 118, port, 20, Y::u32, 1, "", R, "valid frames the main CPU received from the port", frames_received},
    // input registers: per axis
    {"axis{n}.command_position", T::input_register, 200, axis, 10, Y::i32, 1, "pulses", R, "CAMC-QI command counter (CNT1)", cmd_pos},
    {"axis{n}.actual_position", T::input_register, 202, axis, 10, Y::i32, 1, "pulses", R, "the drive's actual position (0x6064)", act_pos},
    {"axis{n}.velocity", T::input_register, 204, axis, 10, Y::i32, 1, "pulses/s", R, "actual velocity over the last control cycle", act_vel},
    {"axis{n}.state", T::input_register, 206, axis, 10, Y::u16, 1, "", R, "PLCopen state: 0 Disabled; 1 Standstill; 2 Homing; 3 DiscreteMotion; 4 ContinuousMotion; 5 SynchronizedMotion; 6 Stopping; 7 ErrorStop", axis_state},
    {"axis{n}.error_id", T::input_register, 207, axis, 10, Y::u16, 1, "", R, "the axis's ErrorID (0 none)", axis_error_id},
    // holding registers: the command mailbox
    {"mailbox.token", T::holding_register, 0, once, 0, Y::u16, 1, "", RW, "the command's two ASCII characters; the first in the high byte ('MA' = 0x4D41)", nullptr},
    {"mailbox.count", T::holding_register, 1, once, 0, Y::u16, 1, "", RW, "how many parameters the command has (0..8)", nullptr},
    {"mailbox.param{n}", T::holding_register, 2, once, 0, Y::i32, 1, "", RW, "", nullptr}, // expanded below
    {"mailbox.go", T::holding_register, 18, once, 0, Y::u16, 1, "", RW, "write 1: the main CPU executes token count params as a frame's command; reads 1 until it did and then 0", nullptr},
    {"mailbox.result", T::holding_register, 19, once, 0, Y::u16, 1, "", R, "BCH of the last command: 0 ok; 1 unknown token; 2 bad data; 3 busy; 4 not allowed; 5 axis error; 65535 none yet", nullptr},
    {"mailbox.error_id", T::holding_register, 20, once, 0, Y::u16, 1, "", R, "the ErrorID the last command's reply carried (BCH 2 and 5); else 0", nullptr},
    {"mailbox.sequence", T::holding_register, 21, once, 0, Y::u16, 1, "", R, "commands the mailbox executed (modulo 65536)", nullptr},
    {"step_ms", T::holding_register, 22, once, 0, Y::u16, 1, "ms", RW, "what the step coil runs: 1..60000 (default 10)", nullptr},
};

// The mailbox's parameters are their own entries: "once" each, two registers apart.
std::vector<Entry> with_params() {
    std::vector<Entry> out;
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (unsigned i = 0; i < kParams; ++i) n.push_back("mailbox.param" + std::to_string(i));
        return n;
    }();
    for (const Entry& e : kMap) {
        if (std::strcmp(e.name, "mailbox.param{n}") != 0) {
            out.push_back(e);
            continue;
        }
        for (unsigned i = 0; i < kParams; ++i) {
            Entry p = e;
            p.name = names[i].c_str();
            p.address = static_cast<std::uint16_t>(e.address + 2 * i);
            p.description = "a parameter: a whole number as the command's data field (docs/system.md section 7)";
            out.push_back(p);
        }
    }
    return out;
}

unsigned count_of(Repeat r) {
    switch (r) {
    case Repeat::per_port: return World::kPorts;
    case Repeat::per_axis: return motion::MotionController::axes;
    default: return 1;
    }
}

std::string csv_field(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

} // namespace

const std::vector<Entry>& register_map() {
    static const std::vector<Entry> map = with_params();
    return map;
}

unsigned words(Type t) { return t == Type::u32 || t == Type::i32 ? 2 : 1; }

const char* to_string(Table t) {
    switch (t) {
    case Table::coil: return "coil";
    case Table::discrete_input: return "discrete_input";
    case Table::input_register: return "input_register";
    default: return "holding_register";
    }
}

const char* to_string(Type t) {
    switch (t) {
    case Type::bit: return "bit";
    case Type::u16: return "u16";
    case Type::i16: return "i16";
    case Type::u32: return "u32";
    default: return "i32";
    }
}

std::vector<Row> map_rows() {
    std::vector<Row> rows;
    for (const Entry& e : register_map())
        for (unsigned i = 0; i < count_of(e.repeat); ++i) {
            std::string name = e.name;
            if (const auto at = name.find("{n}"); at != std::string::npos) name.replace(at, 3, std::to_string(i));
            rows.push_back({name, &e, i, static_cast<std::uint16_t>(e.address + i * e.stride)});
        }
    std::stable_sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) {
        return a.entry->table != b.entry->table ? a.entry->table < b.entry->table : a.address < b.address;
    });
    return rows;
}

std::uint16_t table_size(Table t) {
    unsigned end = 0;
    for (const Row& r : map_rows())
        if (r.entry->table == t) end = std::max(end, r.address + words(r.entry->type));
    return static_cast<std::uint16_t>(end);
}

std::uint16_t address_of(const char* name) {
    for (const Entry& e : register_map())
        if (std::strcmp(e.name, name) == 0) return e.address;
    throw std::logic_error(std::string("no Modbus entry ") + name); // a typo in the server's code
}

bool accepts(Table t, std::uint16_t address, std::uint16_t value) {
    if (t != Table::holding_register) return true;
    if (address == address_of("mailbox.count")) return value <= kParams;
    if (address == address_of("step_ms")) return value >= 1 && value <= 60000;
    return true;
}

void write_map_csv(std::ostream& out) {
    out << "name,table,address,type,words,scale,unit,access,description\n";
    for (const Row& r : map_rows()) {
        const Entry& e = *r.entry;
        out << r.name << ',' << to_string(e.table) << ',' << r.address << ',' << to_string(e.type) << ','
            << words(e.type) << ',' << e.scale << ',' << e.unit << ',' << (e.access == Access::read ? "R" : "RW") << ','
            << csv_field(e.description) << '\n';
    }
}

std::vector<std::uint16_t> encode(Type t, double scale, double value) {
    const bool none = std::isnan(value);
    const double v = std::round(value * scale);
    switch (t) {
    case Type::bit: return {static_cast<std::uint16_t>(!none && v != 0 ? 1 : 0)};
    case Type::u16: return {none ? kNotMeasured16 : static_cast<std::uint16_t>(std::clamp(v, 0.0, 65534.0))};
    case Type::i16: return {none ? std::uint16_t{0x8000} : static_cast<std::uint16_t>(static_cast<std::int16_t>(std::clamp(v, -32767.0, 32767.0)))};
    case Type::u32: {
        const std::uint32_t r = none ? kNotMeasured32 : static_cast<std::uint32_t>(std::clamp(v, 0.0, 4294967294.0));
        return {static_cast<std::uint16_t>(r >> 16), static_cast<std::uint16_t>(r & 0xFFFF)};
    }
    default: {
        const std::uint32_t r = none ? kNotMeasuredI32
                                     : static_cast<std::uint32_t>(static_cast<std::int32_t>(std::clamp(v, -2147483647.0, 2147483647.0)));
        return {static_cast<std::uint16_t>(r >> 16), static_cast<std::uint16_t>(r & 0xFFFF)};
    }
    }
}

} // namespace rcsim::modbus
