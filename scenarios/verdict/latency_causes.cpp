// rcsim — the latency causes in report.json and in words. See latency_causes.h.
#include "scenarios/verdict/latency_causes.h"

#include "scenarios/world/world.h"
#include "comm_cpu/i8086/disasm.h"
#include "models/plumbing/hex.h"
#include "models/plumbing/sim_time_text.h"

#include <cstdio>

namespace rcsim {

namespace {

using Kind = LatencyPhase::Kind;
using nlohmann::json;

std::string fmt(const char* f, double v) {
    char buf[48];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}
std::string at_text(const sc_core::sc_time& t) { return sim_time_text(t.to_seconds()); }
std::string dur_us(const sc_core::sc_time& t) { return fmt("%.1f", to_us(t)); }
std::string seg_off(std::uint16_t cs, std::uint16_t ip) { return hex(cs, 4) + ":" + hex(ip, 4); }
std::string hex2(unsigned v) { return hex(v & 0xFF, 2); }

// What an IF change was: "reset", "interrupt entry", or the instruction.
std::string change_name(const i8086::IfChange& c) {
    switch (c.how) {
    case i8086::IfChange::How::reset: return "reset";
    case i8086::IfChange::How::entry: return "interrupt entry";
    case i8086::IfChange::How::instruction: break;
    }
    switch (c.opcode) {
    case 0xFA: return "CLI";
    case 0xFB: return "STI";
    case 0x9D: return "POPF";
    case 0xCF: return "IRET";
    case 0xCC: return "INT3";
    case 0xCD: return "INT " + hex2(c.vector) + "h";
    case 0xCE: return "INTO";
    default: return "divide error (type 0)"; // F6/F7 DIV/IDIV, D4 AAM
    }
}

// "F000:0010" and its symbol, as "F000:0010 (start)" or "F000:0010".
std::string where(std::uint16_t cs, std::uint16_t ip, const SymbolOf& symbol) {
    const std::string s = symbol ? symbol(i8086::Cpu::linear(cs, ip)) : std::string();
    return seg_off(cs, ip) + (s.empty() ? "" : " (" + s + ")");
}

// The level an interrupt entry was for (its vector in the 8259A's range), -1 when another.
int entry_level(const i8086::IfChange& c, unsigned vector_base) {
    if (c.how != i8086::IfChange::How::entry) return -1;
    const unsigned v = c.vector;
    return (v & 0xF8) == (vector_base & 0xF8) ? int(v & 7) : -1;
}

// An IF change in words: "CLI at F000:011A, cli_here", "reset at FFFF:0000", "entry of the rs232_0
// interrupt" (where it interrupted is no place IF = 0 was held at: said apart, "interrupted at").
std::string change_at(const i8086::IfChange& c, unsigned vector_base, const SymbolOf& symbol) {
    std::string what = change_name(c);
    if (c.how == i8086::IfChange::How::entry) {
        const int level = entry_level(c, vector_base);
        return "entry of the " + (level >= 0 ? source_name(unsigned(level)) : "vector " + hex2(c.vector) + "h") +
               " interrupt";
    }
    std::string s = what + " at " + seg_off(c.cs, c.ip);
    const std::string name =
        c.how == i8086::IfChange::How::reset || !symbol ? std::string() : symbol(i8086::Cpu::linear(c.cs, c.ip));
    return name.empty() ? s : s + ", " + name;
}

void put_code(json& j, const char* at_key, const char* symbol_key, std::uint16_t cs, std::uint16_t ip,
              const SymbolOf& symbol) {
    j[at_key] = seg_off(cs, ip);
    const std::string s = symbol ? symbol(i8086::Cpu::linear(cs, ip)) : std::string();
    if (!s.empty()) j[symbol_key] = s;
}

std::string joined(const std::vector<std::string>& names) {
    std::string s;
    for (const std::string& n : names) s += (s.empty() ? "" : " > ") + n;
    return s;
}

// The location the service that held IF = 0 had interrupted (its entry's return address).
bool interrupted_at(const InterruptRecord& r, std::uint16_t* cs, std::uint16_t* ip) {
    const auto& f = r.cause.if_off;
    if (r.holder_service) {
        if (r.holder_ret_cs == 0 && r.holder_ret_ip == 0) return false; // its entry was not seen whole
        *cs = r.holder_ret_cs;
        *ip = r.holder_ret_ip;
        return true;
    }
    if (r.cause.cause == LatencyPhase::Kind::interrupts_disabled && f.valid && f.has_off &&
        f.off.how == i8086::IfChange::How::entry) {
        *cs = f.off.cs;
        *ip = f.off.ip;
        return true;
    }
    return false;
}

// "; held by isr0 > routine_a > routine_b, interrupted at F000:0119 (idle+0x3)" for the IF = 0
// stretch, "" when nothing names its holder.
std::string held_by(const InterruptRecord& r, const SymbolOf& symbol) {
    std::string s;
    const std::string path = joined(path_names(r.holder_path.data(), r.holder_path_len, symbol));
    if (!path.empty()) s = r.holder_service ? "; held by " + path : "; held by main-program code " + path;
    std::uint16_t cs = 0, ip = 0;
    if (interrupted_at(r, &cs, &ip)) s += (s.empty() ? "; " : ", ") + std::string("interrupted at ") + where(cs, ip, symbol);
    return s;
}

json detail_json(const LatencyCause& c, unsigned vector_base, const SymbolOf& symbol) {
    json d = json::object();
    if (c.if_off.valid) {
        const auto& f = c.if_off;
        json j;
        j["from_us"] = to_us(f.from);
        j["until_us"] = to_us(f.until);
        if (f.has_on) {
            j["enabled_by"] = change_name(f.on);
            put_code(j, "enabled_at", "enabled_symbol", f.on.cs, f.on.ip, symbol);
        }
        if (f.has_off) {
            j["since_us"] = to_us(f.since);
            j["by"] = change_name(f.off);
            put_code(j, "at", "symbol", f.off.cs, f.off.ip, symbol);
            const int level = entry_level(f.off, vector_base);
            if (level >= 0) j["entry_of"] = source_name(unsigned(level));
        } else {
            j["since_us"] = nullptr; // before from_us: the core's history does not reach back
        }
        d["interrupts_disabled"] = j;
    }
    if (c.instruction.valid) {
        const auto& i = c.instruction;
        json j;
        put_code(j, "at", "symbol", i.cs, i.ip, symbol);
        j["mnemonic"] = i8086::mnemonic(i.bytes.data(), i.nbytes);
        std::string bytes;
        for (unsigned k = 0; k < i.nbytes; ++k) bytes += (k ? " " : "") + hex2(i.bytes[k]);
        j["bytes"] = bytes;
        j["began_us"] = to_us(i.start);
        j["halted"] = i.halted;
        j["after_sti"] = i.sti_shadow;
        d["instruction"] = j;
    }
    if (c.busy.wait_states) d["dpram_busy"] = {{"wait_states", c.busy.wait_states}, {"address", hex(c.busy.address, 5)}};
    if (c.cause_level >= 0) d["held_by"] = source_name(unsigned(c.cause_level));
    if (c.truncated) d["truncated"] = true;
    return d;
}

} // namespace

std::string latency_cause_text(const InterruptRecord& r, unsigned vector_base, const SymbolOf& symbol) {
    const LatencyCause& c = r.cause;
    if (!c.known) return "no IR rise: no latency";
    const std::string held = c.cause_level >= 0 ? source_name(unsigned(c.cause_level)) : "";
    const std::string took = dur_us(c.cause_time) + " us";
    switch (c.cause) {
    case Kind::interrupts_disabled: {
        const auto& f = c.if_off;
        std::string s = "interrupts disabled (IF=0)";
        if (!f.valid) return s + " for " + took;
        s += f.has_off ? " since " + at_text(f.since) + " (" + change_at(f.off, vector_base, symbol) + ")"
                       : " since before " + at_text(f.from);
        s += " until " + at_text(f.until);
        if (f.has_on) s += " (" + change_at(f.on, vector_base, symbol) + ")";
        return s + held_by(r, symbol) + "; " + took + " of the latency";
    }
    case Kind::in_service:
        if (c.cause_level == int(r.level))
            return "its own previous interrupt still in service in the 8259A (no EOI yet) for " + took + held_by(r, symbol);
        return "the " + held + " interrupt in service in the 8259A (higher priority) for " + took + held_by(r, symbol);
    case Kind::priority: return "the " + held + " request (higher priority) taken first, for " + took;
    case Kind::masked: return "masked in the 8259A (IMR) for " + took;
    case Kind::not_ready: return "the 8259A not initialised for " + took;
    case Kind::instruction: {
        const auto& i = c.instruction;
        if (!i.valid) return "the instruction in progress: " + took;
        const std::string what = i8086::mnemonic(i.bytes.data(), i.nbytes) + " at " + where(i.cs, i.ip, symbol);
        if (i.halted) return "waking from " + what + ": " + took;
        return std::string(i.sti_shadow ? "the instruction after STI, " : "the instruction in progress, ") + what +
               " begun at " + at_text(i.start) + ": " + took + " to its end";
    }
    case Kind::dpram_busy:
        return "the bus held by DP-RAM BUSY for " + took + " (" + std::to_string(c.busy.wait_states) +
               " wait states at " + hex(c.busy.address, 5) + ")";
    case Kind::entry: return "no wait: the interrupt entry itself (INTA cycles, vector, pushes), " + took;
    case Kind::presented: break;
    }
    return took;
}

json latency_cause_json(const InterruptRecord& r, unsigned vector_base, const SymbolOf& symbol) {
    json j;
    j["latency_us"] = r.has_rise ? json(to_us(r.first_isr - r.ir_rise)) : json();
    j["ir_rise_us"] = r.has_rise ? json(to_us(r.ir_rise)) : json();
    j["first_isr_us"] = to_us(r.first_isr);
    j["service_us"] = r.service_us();
    j["blocking_us"] = r.blocking_us();
    j["path"] = path_names(r.path.data(), r.path_len, symbol);
    if (r.level < 3) j["rx_fifo_level"] = r.rx_fifo_level;
    const LatencyCause& c = r.cause;
    if (!c.known) return j;
    j["boundary_us"] = to_us(c.boundary);
    j["cause"] = to_string(c.cause);
    j["text"] = latency_cause_text(r, vector_base, symbol);
    j["detail"] = detail_json(c, vector_base, symbol);
    json phases = json::array();
    for (unsigned k = 0; k < c.phases; ++k) {
        const LatencyPhase& p = c.phase[k];
        json q = {{"phase", to_string(p.kind)}, {"from_us", to_us(p.from)}, {"to_us", to_us(p.to)}, {"us", p.us()}};
        if (p.level >= 0) q["source"] = source_name(unsigned(p.level));
        phases.push_back(q);
    }
    j["phases"] = phases;
    if (c.if_off.valid) j["if_on_us"] = to_us(c.if_off.until);
    if (r.holder_path_len) {
        j["holder"] = path_names(r.holder_path.data(), r.holder_path_len, symbol);
        j["holder_source"] = r.holder_service ? source_name(unsigned(r.holder_level)) : "main";
    }
    std::uint16_t cs = 0, ip = 0;
    if (interrupted_at(r, &cs, &ip)) put_code(j, "interrupted_at", "interrupted_symbol", cs, ip, symbol);
    return j;
}

std::vector<std::string> path_names(const std::uint32_t* path, unsigned n, const SymbolOf& symbol) {
    std::vector<std::string> out;
    for (unsigned k = 0; k < n; ++k) {
        std::string s = symbol ? symbol(path[k]) : std::string();
        const std::size_t plus = s.find('+');
        if (plus != std::string::npos) s.resize(plus);
        if (s.empty()) s = hex(path[k], 5);
        if (out.empty() || out.back() != s) out.push_back(s);
    }
    return out;
}

void add_latency_causes(json& interrupts, const World& w, std::optional<double> budget_us, const SymbolOf& symbol) {
    const unsigned base = w.ctl.comm.pic.vector_base();
    const auto put = [&](const char* name, const Samples& latency, const WorstLatencies& worst) {
        json list = json::array();
        for (const InterruptRecord& r : worst.records())
            if (list.empty() || (budget_us && to_us(r.first_isr - r.ir_rise) > *budget_us))
                list.push_back(latency_cause_json(r, base, symbol));
        interrupts[name]["worst"] = list;
        // No budget, no count over it: not measured, never a reassuring 0.
        interrupts[name]["over_budget"] = budget_us ? json(latency.count_above(*budget_us)) : json(nullptr);
    };
    for (unsigned level = 0; level < 4; ++level)
        put(source_name(level).c_str(), w.probe.latency_us(level), w.probe.worst(level));
    put("rs232_rx", w.rs232_rx_latency_us(), w.rs232_rx_worst());
    // Start-up interrupts (interrupts.startup.records, in the probe's order) each have theirs:
    // none is judged, but a firmware engineer still asks why one waited.
    json& startup = interrupts["startup"]["records"];
    const auto& records = w.probe.startup_records();
    for (std::size_t k = 0; k < records.size() && k < startup.size(); ++k)
        if (records[k].has_rise) {
            json cause = latency_cause_json(records[k], base, symbol);
            cause.erase("latency_us"); // the record has them already, to the picosecond
            cause.erase("ir_rise_us");
            // Its service is not judged either: the blocking figures and paths are the judged
            // services' (a start-up record keeps its figures as they were, for `rcsim compare`).
            for (const char* key : {"service_us", "blocking_us", "path", "rx_fifo_level", "if_on_us"}) cause.erase(key);
            startup[k].update(cause);
        }
}

} // namespace rcsim
