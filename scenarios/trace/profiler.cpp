#include "scenarios/trace/profiler.h"

#include "comm_cpu/i8086/disasm.h"

#include <algorithm>
#include <cstdio>
#include <ostream>

namespace rcsim::trace {

using i8086::Cpu;
using i8086::cycles_t;

namespace {

std::uint32_t linear_plus(std::uint16_t seg, std::uint16_t off, int delta) {
    return Cpu::linear(seg, static_cast<std::uint16_t>(off + delta));
}

/// A byte of directly mapped memory (code and stack live there), or -1.
int byte_at(const Cpu& cpu, std::uint32_t linear) {
    const MemRegion* m = cpu.memory().find(linear);
    return m ? m->data[linear - m->base] : -1;
}

} // namespace

CycleProfiler::CycleProfiler(NameOf name_of) : name_of_(std::move(name_of)) { tree_.push_back(Node{"", 0, {}}); }

unsigned CycleProfiler::function_at(std::uint32_t linear) {
    const auto it = fn_at_.find(linear);
    if (it != fn_at_.end()) return it->second;
    const std::string name = name_of_(linear);
    // Two entry points of one symbol are one function.
    const auto same = std::find(functions_.begin(), functions_.end(), name);
    const auto id = static_cast<unsigned>(same == functions_.end() ? functions_.size() : same - functions_.begin());
    if (same == functions_.end()) functions_.push_back(name);
    fn_at_.emplace(linear, id);
    return id;
}

unsigned CycleProfiler::context_id(const std::string& name) {
    const auto it = std::find(contexts_.begin(), contexts_.end(), name);
    if (it != contexts_.end()) return static_cast<unsigned>(it - contexts_.begin());
    contexts_.push_back(name);
    return static_cast<unsigned>(contexts_.size() - 1);
}

unsigned CycleProfiler::child(unsigned node, const std::string& name) {
    const auto it = tree_[node].children.find(name);
    if (it != tree_[node].children.end()) return it->second;
    const auto id = static_cast<unsigned>(tree_.size());
    tree_[node].children.emplace(name, id);
    tree_.push_back(Node{name, 0, {}});
    return id;
}

void CycleProfiler::charge(cycles_t clocks) {
    total_ += clocks;
    const Frame& f = frames_.back();
    stats_[f.stat].self += clocks;
    tree_[f.node].self += clocks;
}

void CycleProfiler::open(std::uint32_t target, std::uint32_t sp, unsigned context, unsigned parent_node, cycles_t at,
                         bool isr) {
    const unsigned fn = function_at(target);
    const auto key = std::make_pair(fn, context);
    auto it = stat_of_.find(key);
    if (it == stat_of_.end()) {
        it = stat_of_.emplace(key, static_cast<unsigned>(stats_.size())).first;
        stats_.emplace_back();
    }
    ++stats_[it->second].active;
    Frame f;
    f.stat = it->second;
    f.node = child(parent_node, functions_[fn]);
    f.context = context;
    f.entry = at;
    f.sp = sp;
    f.isr = isr;
    frames_.push_back(f);
}

void CycleProfiler::close(cycles_t at, bool completed) {
    const Frame f = frames_.back();
    frames_.pop_back();
    const cycles_t duration = at - f.entry, inclusive = duration - f.interrupted;
    Stat& s = stats_[f.stat];
    if (completed) {
        ++s.calls;
        s.sum += inclusive;
        s.min = std::min<std::uint64_t>(s.min, inclusive);
        s.max = std::max<std::uint64_t>(s.max, inclusive);
    }
    if (--s.active == 0) s.inclusive += inclusive; // the outermost activation of a recursion
    // The caller's call lasted as long, but an ISR's clocks are not the interrupted code's.
    if (!frames_.empty()) frames_.back().interrupted += f.isr ? duration : f.interrupted;
}

// What the instruction at CS:IP will do to the call stack.
CycleProfiler::Transfer CycleProfiler::decode(const Cpu& cpu) {
    const auto& r = cpu.regs();
    // Enough bytes for a few prefixes, the opcode and its ModR/M byte (what decides the flow),
    // up to the first byte that is not directly mapped.
    std::uint8_t bytes[8];
    unsigned n = 0;
    for (; n < sizeof bytes; ++n) {
        const int b = byte_at(cpu, linear_plus(r.s[i8086::CS], r.ip, static_cast<int>(n)));
        if (b < 0) break;
        bytes[n] = static_cast<std::uint8_t>(b);
    }
    switch (i8086::decode(bytes, n).flow) {
    case i8086::Flow::call_near: return Transfer::call_near;
    case i8086::Flow::call_far: return Transfer::call_far;
    case i8086::Flow::ret_near: case i8086::Flow::ret_far: case i8086::Flow::iret: return Transfer::ret;
    case i8086::Flow::int_sw: return Transfer::int_sw;
    default: return Transfer::none;
    }
}

void CycleProfiler::bus(const i8086::BusRecord& r) {
    if (r.kind != i8086::Bus::int_ack) return;
    if (intas_++ == 0) inta_start_ = r.start;
    else inta_vector_ = r.data & 0xFF; // the second INTA carries the vector
}

void CycleProfiler::step(const Cpu& cpu) {
    const auto& r = cpu.regs();
    const cycles_t now = cpu.cycles();
    const std::uint32_t sp = Cpu::linear(r.s[i8086::SS], r.r[i8086::SP]);
    if (!started_) {
        // The root frame: the code the CPU starts in, never closed by a return.
        started_ = true;
        last_ = now;
        open(cpu.pc(), ~std::uint32_t(0), context_id("main"), child(0, "main"), now, false);
        prev_ = decode(cpu);
        prev_sp_ = sp;
        return;
    }
    const bool irq = intas_ >= 2;
    // Up to the first INTA the clocks are the interrupted code's; from it, the handler's.
    const cycles_t split = irq ? std::clamp(inta_start_, last_, now) : now;
    charge(split - last_);
    // The stack as the last instruction left it: before the interrupt entry's three pushes.
    const std::uint32_t sp_before = irq ? linear_plus(r.s[i8086::SS], r.r[i8086::SP], 6) : sp;
    switch (prev_) {
    case Transfer::call_near:
    case Transfer::call_far:
    case Transfer::int_sw: {
        const std::uint32_t pushed = prev_ == Transfer::call_near ? 2 : prev_ == Transfer::call_far ? 4 : 6;
        if (sp_before + pushed != prev_sp_) break; // not taken (INTO), or not a call after all
        std::uint32_t target = cpu.pc();
        if (irq) {
            // The interrupt came right after the call: the callee's first instruction is the
            // return address the entry pushed (IP at SS:SP, CS above it).
            auto word = [&](int d) {
                return static_cast<std::uint16_t>(byte_at(cpu, linear_plus(r.s[i8086::SS], r.r[i8086::SP], d)) |
                                                  byte_at(cpu, linear_plus(r.s[i8086::SS], r.r[i8086::SP], d + 1)) << 8);
            };
            target = Cpu::linear(word(2), word(0));
        }
        open(target, sp_before, frames_.back().context, frames_.back().node, split, false);
        break;
    }
    case Transfer::ret:
        while (frames_.size() > 1 && frames_.back().sp < sp_before) close(split, true);
        break;
    default: break;
    }
    if (irq) {
        const bool nested = std::any_of(frames_.begin(), frames_.end(), [](const Frame& f) { return f.isr; });
        const std::string ctx = "IR" + std::to_string(inta_vector_ & 7) + (nested ? " nested" : "");
        open(cpu.pc(), sp, context_id(ctx), child(0, ctx), split, true);
        charge(now - split);
        intas_ = 0;
    }
    last_ = now;
    prev_ = decode(cpu);
    prev_sp_ = sp;
}

void CycleProfiler::finish(cycles_t end) {
    if (!started_ || frames_.empty()) return;
    if (end > last_) charge(end - last_);
    last_ = std::max(last_, end);
    while (!frames_.empty()) close(last_, false);
}

// ---------------------------------------------------------------------------------------------
// Results

std::vector<CycleProfiler::Row> CycleProfiler::rows() const {
    std::vector<Row> out;
    for (const auto& [key, index] : stat_of_) {
        const Stat& s = stats_[index];
        Row row;
        row.function = functions_[key.first];
        row.context = contexts_[key.second];
        row.calls = s.calls;
        row.self = s.self;
        row.inclusive = s.inclusive;
        if (s.calls) {
            row.min = s.min;
            row.max = s.max;
            row.mean = static_cast<double>(s.sum) / static_cast<double>(s.calls);
        }
        out.push_back(row);
    }
    std::sort(out.begin(), out.end(), [](const Row& a, const Row& b) {
        if (a.self != b.self) return a.self > b.self;
        if (a.function != b.function) return a.function < b.function;
        return a.context < b.context;
    });
    return out;
}

std::uint64_t CycleProfiler::total_of(unsigned node) const {
    std::uint64_t t = tree_[node].self;
    for (const auto& [name, c] : tree_[node].children) t += total_of(c);
    return t;
}

void CycleProfiler::write_table(std::ostream& os, double clock_hz) const {
    const double us = 1e6 / clock_hz;
    char line[512];
    std::snprintf(line, sizeof line, "# rcsim cycle profile: %llu clocks = %.3f us of the comm CPU at %.3f MHz\n",
                  static_cast<unsigned long long>(total_), static_cast<double>(total_) * us, clock_hz / 1e6);
    os << line
       << "# self: clocks of the function's own instructions; inclusive: with its callees, without the interrupts\n"
          "# that came in meanwhile (those are in their own context). min/mean/max: inclusive clocks of one\n"
          "# completed call. An ISR's clocks start at the first INTA cycle. Sorted by self clocks.\n";
    std::size_t fw = 8, cw = 7;
    const auto rs = rows();
    for (const Row& r : rs) {
        fw = std::max(fw, r.function.size());
        cw = std::max(cw, r.context.size());
    }
    std::snprintf(line, sizeof line, "%-*s  %-*s %9s %12s %6s %12s %9s %11s %9s %10s %10s\n", static_cast<int>(fw),
                  "function", static_cast<int>(cw), "context", "calls", "self", "self%", "inclusive", "min", "mean",
                  "max", "mean_us", "max_us");
    os << line;
    for (const Row& r : rs) {
        std::snprintf(line, sizeof line, "%-*s  %-*s %9llu %12llu %6.2f %12llu %9llu %11.1f %9llu %10.2f %10.2f\n",
                      static_cast<int>(fw), r.function.c_str(), static_cast<int>(cw), r.context.c_str(),
                      static_cast<unsigned long long>(r.calls), static_cast<unsigned long long>(r.self),
                      total_ ? 100.0 * static_cast<double>(r.self) / static_cast<double>(total_) : 0.0,
                      static_cast<unsigned long long>(r.inclusive), static_cast<unsigned long long>(r.min), r.mean,
                      static_cast<unsigned long long>(r.max), r.mean * us, static_cast<double>(r.max) * us);
        os << line;
    }
}

namespace {
// flamegraph.pl splits frames at ';' and the count at the last space.
std::string frame_name(const std::string& s) {
    std::string o = s;
    for (char& c : o)
        if (c == ';' || c == ' ') c = '_';
    return o;
}
} // namespace

void CycleProfiler::write_folded(std::ostream& os) const {
    struct Walk {
        const CycleProfiler& p;
        std::ostream& os;
        void operator()(unsigned node, const std::string& path) const {
            const Node& n = p.tree_[node];
            if (n.self && !path.empty()) os << path << ' ' << n.self << '\n';
            for (const auto& [name, c] : n.children) (*this)(c, path.empty() ? frame_name(name) : path + ";" + frame_name(name));
        }
    };
    Walk{*this, os}(0, "");
}

} // namespace rcsim::trace
