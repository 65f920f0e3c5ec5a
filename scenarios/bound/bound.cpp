// rcsim — the static worst case of every interrupt path. See bound.h.
#include "scenarios/bound/bound.h"

#include "models/plumbing/config_error.h"
#include "models/plumbing/hex.h"
#include "scenarios/bound/flow.h"
#include "scenarios/bound/paths.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

namespace rcsim::bound {
namespace {

constexpr int CX = 1;

bool is_string_op(const Insn& i) { return i.opcode >= 0xA4 && i.opcode <= 0xAF; }
bool is_shift_by_cl(const Insn& i) { return i.opcode == 0xD2 || i.opcode == 0xD3; }
bool uses_cx_count(const Insn& i) {
    return (i.rep && is_string_op(i)) || is_shift_by_cl(i) || (i.opcode >= 0xE0 && i.opcode <= 0xE3);
}

std::string address_hex(std::uint32_t v) { return "0x" + hex(v, 5); }

double to_us(std::uint64_t clocks, double mhz) { return std::round(double(clocks) / mhz * 10.0) / 10.0; }

/// The worst clocks of one instruction alone, with the count CX gives a REP string instruction
/// or a shift by CL (an annotation's for a REP whose count the code does not state).
std::uint64_t single_cost(const FlowGraph& g, i8086::WorstClocks& clocks, const Node& n) {
    const Insn& i = *n.insn;
    std::uint32_t cx_max = 0xFFFF;
    if (uses_cx_count(i)) {
        cx_max = is_shift_by_cl(i) ? n.in.b8[CX].hi : n.in.reg[CX].hi; // a shift counts by CL alone
        if (i.rep && is_string_op(i)) {
            if (const Annotation* a = g.annotation(i.address, Annotation::Kind::iterations))
                cx_max = std::uint32_t(std::min<std::uint64_t>(a->iterations, 0xFFFF));
            else if (n.in.reg[CX].lo == 0 && n.in.reg[CX].hi == 0xFFFF)
                throw ConfigError("bound: a " + i.text + " at " + g.where(i.address) + " (" + address_hex(i.address) +
                                  ") whose count CX the code does not state: add `" + g.where(i.address) +
                                  " iterations N  # why` to the annotations");
        }
    }
    return clocks.instruction(i.bytes, i.length, n.ip, cx_max);
}

/// single_cost() of every node `want` selects (the others 0).
std::vector<std::uint64_t> single_costs(const FlowGraph& g, i8086::WorstClocks& clocks, const std::vector<bool>& want) {
    std::vector<std::uint64_t> c(g.nodes().size(), 0);
    for (std::size_t v = 0; v < c.size(); ++v)
        if (want[v]) c[v] = single_cost(g, clocks, g.nodes()[v]);
    return c;
}

/// Whether the instruction can run inside a straight line measured as a whole: no choice of
/// successor, no time that depends on a value (those are bounded alone).
bool in_straight_line(const Insn& i) {
    using F = i8086::Flow;
    switch (i.flow) {
    case F::branch: case F::ret_near: case F::ret_far: case F::iret: case F::int_sw: case F::halt: return false;
    case F::jump: case F::call_near: case F::jump_far: case F::call_far:
        return i8086::direct_target(i.bytes, i8086::decode(i.bytes, i.length), i.ip).has_value();
    default: break;
    }
    if ((i.rep && is_string_op(i)) || is_shift_by_cl(i)) return false;
    if ((i.opcode == 0xF6 || i.opcode == 0xF7) && i.reg >= 4) return false;
    return i.opcode != 0xD4 && i.opcode != 0xD5;
}

constexpr unsigned kLongestLine = 16; // instructions measured as one straight line at most

/// A conditional transfer or a return: the last instruction a straight line can hold.
bool ends_line(const Insn& i) {
    using F = i8086::Flow;
    return i.flow == F::branch || i.flow == F::ret_near || i.flow == F::ret_far || i.flow == F::iret;
}

/// The costs a path adds up. A straight line of instructions that always run together (each the
/// only successor of the one before and its only predecessor, of the same `kind`), perhaps ended
/// by a conditional transfer or a return, is measured as one on the core
/// (i8086::WorstClocks::sequence, ::branch): its clocks on its last node (`line` = how many
/// instructions they cover), 0 on the rest. A line ending in a conditional transfer costs
/// `clocks` when it is taken and `fall` when it falls through; elsewhere the two are equal.
struct Costs {
    std::vector<std::uint64_t> clocks, fall;
    std::vector<unsigned> line;
};

Costs line_costs(const FlowGraph& g, i8086::WorstClocks& clocks, const std::vector<bool>& want,
                 const std::vector<int>& kind, const std::vector<std::vector<int>>& preds) {
    const auto& nodes = g.nodes();
    const std::size_t n = nodes.size();
    Costs c{std::vector<std::uint64_t>(n, 0), std::vector<std::uint64_t>(n, 0), std::vector<unsigned>(n, 0)};
    auto joins = [&](int u, int v) { // v goes on u's straight line
        const Insn& a = *nodes[std::size_t(u)].insn;
        const Insn& b = *nodes[std::size_t(v)].insn;
        return want[std::size_t(u)] && want[std::size_t(v)] && nodes[std::size_t(u)].out.size() == 1 &&
               preds[std::size_t(v)].size() == 1 && kind[std::size_t(u)] == kind[std::size_t(v)] &&
               in_straight_line(a) && (in_straight_line(b) || ends_line(b));
    };
    for (std::size_t v = 0; v < n; ++v) {
        if (!want[v]) continue;
        if (preds[v].size() == 1 && joins(preds[v][0], int(v))) continue; // not the first of its line
        std::vector<int> line{int(v)};
        while (line.size() < kLongestLine && !ends_line(*nodes[std::size_t(line.back())].insn) &&
               nodes[std::size_t(line.back())].out.size() == 1) {
            const int next = nodes[std::size_t(line.back())].out[0].to;
            if (!joins(line.back(), next) || next == int(v)) break;
            line.push_back(next);
        }
        const Insn& last = *nodes[std::size_t(line.back())].insn;
        std::vector<i8086::Piece> pieces;
        for (int x : line) {
            const Node& m = nodes[std::size_t(x)];
            pieces.push_back({m.insn->bytes, m.insn->length, m.ip});
        }
        // The line's clocks go on its last node: where a conditional transfer chooses its way.
        const std::size_t end = std::size_t(line.back());
        if (last.flow == i8086::Flow::branch) {
            const i8086::Outcomes o = clocks.branch(pieces);
            c.clocks[end] = o.taken;
            c.fall[end] = o.not_taken;
        } else if (line.size() == 1 && !in_straight_line(last) && !ends_line(last)) {
            c.clocks[end] = c.fall[end] = single_cost(g, clocks, nodes[v]); // its time depends on values
        } else {
            c.clocks[end] = c.fall[end] = clocks.sequence(pieces);
        }
        c.line[end] = unsigned(line.size());
    }
    return c;
}

std::vector<std::vector<int>> predecessors(const FlowGraph& g) {
    std::vector<std::vector<int>> p(g.nodes().size());
    for (std::size_t v = 0; v < p.size(); ++v)
        for (const auto& e : g.nodes()[v].out) p[std::size_t(e.to)].push_back(int(v));
    return p;
}

/// The states loop `l` is entered with: what each edge into its header from outside it carries.
std::vector<State> entry_states(const FlowGraph& g, const std::vector<std::vector<int>>& preds, const LoopFound& l) {
    const std::set<int> body(l.body.begin(), l.body.end());
    std::vector<State> out;
    for (int p : preds[std::size_t(l.header)])
        if (!body.count(p)) out.push_back(g.out_state(p, l.header));
    return out;
}

/// A register counted down: one DEC r on every way round the loop (no latch is reached from the
/// header without passing it), r >= 1 before it on every path (a test leaves at 0 first), nothing
/// but a POP writes r between the header and it, the value every latch carries back is that
/// DEC's (what the loop does with r after it, it undoes: a POP that restores it keeps its writer,
/// State::writer), and the stack is balanced round the loop. Then the header runs at most (r's
/// largest value at entry) + 1 times.
bool counted_down(const FlowGraph& g, const std::vector<std::vector<int>>& preds, LoopFound& l) {
    const auto& nodes = g.nodes();
    const std::set<int> body(l.body.begin(), l.body.end());
    const std::vector<State> entries = entry_states(g, preds, l);
    if (entries.empty()) return false;
    std::size_t depth = ~std::size_t(0);
    for (const State& e : entries) depth = std::min(depth, e.stack.size());
    for (int d : l.body) {
        const Insn& i = *nodes[std::size_t(d)].insn;
        int r = -1;
        unsigned width = 2;
        if (i.opcode >= 0x48 && i.opcode <= 0x4F) r = i.opcode & 7;
        else if ((i.opcode == 0xFE || i.opcode == 0xFF) && i.mod == 3 && i.reg == 1)
            r = int(i.rm), width = i.opcode == 0xFF ? 2 : 1;
        if (r < 0 || (width == 2 && r == 4)) continue;
        const int word = width == 2 ? r : (r & 3);
        std::vector<int> slots;
        if (width == 1) slots = {r};
        else if (r < 4) slots = {r, r + 4};
        else slots = {r + 4};
        auto interval = [&](const State& s) { return width == 2 ? s.reg[r] : s.b8[r]; };
        bool ok = interval(nodes[std::size_t(d)].in).lo >= 1;
        // Between the header and d (reached from the header without d, reaching d without the
        // header) only a POP may write r: it gives back a value saved since the header.
        std::set<int> from_header{l.header}, to_d{d};
        for (std::vector<int> st{l.header}; !st.empty();) {
            const int v = st.back();
            st.pop_back();
            for (const auto& e : nodes[std::size_t(v)].out)
                if (e.to != d && body.count(e.to) && from_header.insert(e.to).second) st.push_back(e.to);
        }
        for (std::vector<int> st{d}; !st.empty();) {
            const int v = st.back();
            st.pop_back();
            for (int p : preds[std::size_t(v)])
                if (p != l.header && body.count(p) && to_d.insert(p).second) st.push_back(p);
        }
        to_d.insert(l.header);
        for (int v : from_header) {
            if (!ok) break;
            const Insn& w = *nodes[std::size_t(v)].insn;
            if (!to_d.count(v) || !FlowGraph::writes(w, word)) continue;
            const bool pop = w.opcode == 0x58 + word;
            const bool other_byte = width == 1 && FlowGraph::writes_byte_only(w) >= 0 && FlowGraph::writes_byte_only(w) != r;
            ok = pop || other_byte;
        }
        for (int u : l.latches) {
            if (!ok) break;
            const State out = g.out_state(u, l.header);
            for (int k : slots) ok = ok && out.writer[k] == d;
            ok = ok && out.stack.size() == depth;
        }
        if (!ok) continue;
        // No way from the header to a latch around d.
        for (int u : l.latches) ok = ok && (u == d || !from_header.count(u));
        if (!ok) continue;
        std::uint32_t hi = 0;
        for (const State& e : entries) hi = std::max(hi, interval(e).hi);
        l.bound = std::uint64_t(hi) + 1;
        l.reason = "counted down by " + i.text + " at " + g.where(i.address) + " from at most " + std::to_string(hi) +
                   ", leaving at 0";
        return true;
    }
    return false;
}

/// A loop's bound: an annotation at its header or a latch; a LOOP whose CX only it changes; a
/// register counted down (counted_down).
LoopBounder bounder_for(const FlowGraph& g, const std::vector<std::vector<int>>& preds) {
    return [&g, &preds](LoopFound& l) {
        const auto& nodes = g.nodes();
        const std::set<int> body(l.body.begin(), l.body.end());
        std::vector<int> at{l.header};
        at.insert(at.end(), l.latches.begin(), l.latches.end());
        for (int v : at)
            if (const Annotation* a = g.annotation(nodes[std::size_t(v)].address, Annotation::Kind::iterations)) {
                l.bound = a->iterations;
                l.reason = a->reason + " (" + a->where + ")";
                return;
            }
        auto entry_interval = [&](int reg) {
            const std::vector<State> entries = entry_states(g, preds, l);
            if (entries.empty()) return Interval::top();
            Interval v{0xFFFF, 0, false};
            for (const State& e : entries) v = {std::min(v.lo, e.reg[reg].lo), std::max(v.hi, e.reg[reg].hi), false};
            return v;
        };
        auto only_writers = [&](int reg, const std::set<int>& allowed) {
            for (int v : l.body)
                if (!allowed.count(v) && FlowGraph::writes(*nodes[std::size_t(v)].insn, reg)) return false;
            return true;
        };
        const std::set<int> latches(l.latches.begin(), l.latches.end());
        const bool loop_latches = std::all_of(l.latches.begin(), l.latches.end(), [&](int v) {
            const std::uint8_t op = nodes[std::size_t(v)].insn->opcode;
            return op >= 0xE0 && op <= 0xE2;
        });
        if (loop_latches && only_writers(CX, latches)) {
            const Interval cx = entry_interval(CX);
            l.bound = cx.lo >= 1 ? cx.hi : 65536;
            l.reason = cx.lo >= 1 ? "CX <= " + std::to_string(cx.hi) + " at entry, counted down by " +
                                        nodes[std::size_t(l.latches[0])].insn->text
                                  : "CX may be 0 at entry: " + nodes[std::size_t(l.latches[0])].insn->text + " runs 65536 times";
            return;
        }
        if (counted_down(g, preds, l)) return;
        const std::uint32_t a = nodes[std::size_t(l.header)].address;
        throw ConfigError("bound: a loop at " + g.where(a) + " (" + address_hex(a) +
                          ") has no bound the code states: add `" + g.where(a) +
                          " iterations N  # why` to the annotations");
    };
}

/// The path's instructions in the order it first runs them; an instruction the path runs in
/// several call contexts is one step with their counts added.
std::vector<Step> steps_of(const FlowGraph& g, const Paths::Longest& p, const Costs& cost) {
    std::vector<Step> out;
    std::map<std::pair<std::uint32_t, bool>, std::size_t> at;
    for (const auto& ran : p.nodes) {
        if (ran.times == 0) continue; // a loop run once: its iteration's (bound - 1) x
        const Node& n = g.nodes()[std::size_t(ran.node)];
        const unsigned clocks = unsigned(ran.fell ? cost.fall[std::size_t(ran.node)] : cost.clocks[std::size_t(ran.node)]);
        const unsigned line = cost.line[std::size_t(ran.node)];
        const auto key = std::make_pair(n.address, ran.fell);
        auto it = at.find(key);
        if (it != at.end() && out[it->second].clocks == clocks && out[it->second].line == line) {
            out[it->second].times += ran.times;
            continue;
        }
        at[key] = out.size();
        out.push_back(Step{n.address, g.where(n.address), n.insn->text, clocks, ran.times, line});
    }
    return out;
}

void add_loops(const FlowGraph& g, const Paths& paths, const Paths::Longest& p, std::vector<Loop>& out) {
    for (int li : p.loops) {
        const LoopFound& l = paths.loops()[std::size_t(li)];
        const std::uint32_t a = g.nodes()[std::size_t(l.header)].address;
        if (std::any_of(out.begin(), out.end(), [&](const Loop& x) { return x.header == a && x.iterations == l.bound; }))
            continue;
        out.push_back(Loop{a, g.where(a), l.bound, l.reason});
    }
}

/// The longest IF = 0 stretch of the code outside interrupts, after start-up.
void bound_main(const Inputs& in, i8086::WorstClocks& clocks, Result& r, Term& longest_instruction) {
    State boot;
    boot.if_flag = IfState::startup;
    FlowGraph g(in, 0xFFFF, 0x0000, boot, "the code from the reset");
    const auto& nodes = g.nodes();
    const auto preds = predecessors(g);
    std::vector<bool> member(nodes.size()), running(nodes.size());
    std::vector<int> sources;
    for (std::size_t v = 0; v < nodes.size(); ++v) {
        const IfState f = nodes[v].in.if_flag;
        running[v] = f != IfState::startup;
        member[v] = f == IfState::off || f == IfState::unknown;
    }
    for (std::size_t v = 0; v < nodes.size(); ++v)
        if (member[v] && std::any_of(preds[v].begin(), preds[v].end(), [&](int p) { return !member[std::size_t(p)]; }))
            sources.push_back(int(v));
    const std::vector<std::uint64_t> single = single_costs(g, clocks, running);
    for (std::size_t v = 0; v < nodes.size(); ++v)
        if (running[v] && single[v] > longest_instruction.clocks) {
            longest_instruction.clocks = single[v];
            longest_instruction.what = nodes[v].insn->text + " at " + g.where(nodes[v].address);
        }
    if (sources.empty()) return;
    const std::vector<int> kind(member.begin(), member.end());
    const Costs cost = line_costs(g, clocks, running, kind, preds);
    const Paths paths(g, member, sources, bounder_for(g, preds));
    const Paths::Longest p = paths.longest(cost.clocks, &cost.fall);
    r.main_if0.clocks = p.clocks;
    r.main_if0.us = to_us(p.clocks, in.clock_mhz);
    r.main_if0.path = steps_of(g, p, cost);
    add_loops(g, paths, p, r.main_if0.loops);
}

SourceBound bound_source(const Inputs& in, const Source& s, i8086::WorstClocks& clocks, Term& longest_instruction) {
    State entry; // an interrupt entry clears IF; the level is in service until its EOI
    entry.if_flag = IfState::off;
    FlowGraph g(in, s.cs, s.ip, entry, s.name + " (vector " + std::to_string(s.vector) + ")");
    const auto& nodes = g.nodes();
    const auto preds = predecessors(g);
    const std::vector<bool> all(nodes.size(), true);
    const std::vector<std::uint64_t> single = single_costs(g, clocks, all);
    // A node keeps other requests waiting while IF = 0 or before the EOI (a straight line is one
    // kind throughout, so its clocks count wholly or not at all).
    std::vector<int> kind(nodes.size());
    SourceBound b;
    b.source = s;
    b.entry = g.where(nodes[0].address);
    for (std::size_t v = 0; v < nodes.size(); ++v) {
        const State& st = nodes[v].in;
        kind[v] = st.if_flag != IfState::on || st.eoi != Eoi::yes;
        if (st.if_flag == IfState::on) b.reenables = true;
        if (single[v] > longest_instruction.clocks) {
            longest_instruction.clocks = single[v];
            longest_instruction.what = nodes[v].insn->text + " at " + g.where(nodes[v].address);
        }
    }
    const Costs cost = line_costs(g, clocks, all, kind, preds);
    Costs blocking{std::vector<std::uint64_t>(nodes.size(), 0), std::vector<std::uint64_t>(nodes.size(), 0), cost.line};
    for (std::size_t v = 0; v < nodes.size(); ++v)
        if (kind[v]) blocking.clocks[v] = cost.clocks[v], blocking.fall[v] = cost.fall[v];
    const Paths paths(g, all, {0}, bounder_for(g, preds));
    const Paths::Longest service = paths.longest(cost.clocks, &cost.fall);
    const Paths::Longest block = paths.longest(blocking.clocks, &blocking.fall);
    // A service is measured from the handler's first fetch (interrupt_probe.h: first_isr), which
    // the entry's bound ends with: one code fetch more than the path from the first boundary.
    const std::uint64_t first_fetch = 4 + in.waits.code;
    b.service_clocks = service.clocks + first_fetch;
    b.blocking_clocks = block.clocks + first_fetch;
    b.service_us = to_us(service.clocks, in.clock_mhz);
    b.blocking_us = to_us(block.clocks, in.clock_mhz);
    b.path = steps_of(g, service, cost);
    b.blocking_path = steps_of(g, block, blocking);
    add_loops(g, paths, service, b.loops);
    add_loops(g, paths, block, b.loops);
    return b;
}

Term term(const std::string& name, std::uint64_t clocks, double mhz, const std::string& what) {
    return Term{name, clocks, to_us(clocks, mhz), what};
}

} // namespace

bool Result::fits() const {
    return std::all_of(sources.begin(), sources.end(), [&](const auto& s) { return s.second.blocking_us <= budget_us; });
}

Result analyse(const Inputs& in) {
    i8086::WorstClocks clocks(in.waits);
    Result r;
    r.budget_us = in.budget_us;
    r.clock_mhz = in.clock_mhz;
    r.waits = in.waits;
    r.waits_reason = in.waits_reason;
    Term longest{"longest_instruction", 0, 0, ""};
    bound_main(in, clocks, r, longest);
    for (const Source& s : in.sources) r.sources[s.name] = bound_source(in, s, clocks, longest);
    longest.us = to_us(longest.clocks, in.clock_mhz);
    longest.what = "the instruction running when the request comes: " + longest.what;
    r.longest_instruction = longest;
    r.entry = term("entry", clocks.interrupt_entry(), in.clock_mhz,
                   "INTA cycles, FLAGS CS IP pushed, the vector read, the handler's first byte fetched");
    for (auto& [name, b] : r.sources) {
        std::uint64_t others = 0;
        std::string who;
        for (const auto& [other, ob] : r.sources)
            if (other != name) {
                others += ob.blocking_clocks;
                who += (who.empty() ? "" : ", ") + other;
            }
        b.latency_terms = {
            term("outside_if0", r.main_if0.clocks, in.clock_mhz,
                 "the longest IF = 0 stretch of the code outside interrupts"),
            term("own_service", b.blocking_clocks, in.clock_mhz,
                 "its own service, when the request comes while it still keeps its level in service"),
            term("rotation", others, in.clock_mhz,
                 "each other source served once before it by the 8259A's rotating priority (" + who + ")"),
            r.longest_instruction,
            r.entry,
        };
        for (const Term& t : b.latency_terms) b.latency_clocks += t.clocks;
        b.latency_us = to_us(b.latency_clocks, in.clock_mhz);
    }
    for (const Annotation& a : in.annotations)
        if (!a.used && a.kind == Annotation::Kind::iterations)
            throw ConfigError(a.where + ": no loop or REP of the bounded code is at " + address_hex(a.address) +
                              " (the code changed? remove or move the line)");
    return r;
}

namespace {

nlohmann::json steps_json(const std::vector<Step>& steps) {
    nlohmann::json a = nlohmann::json::array();
    for (const Step& s : steps)
        a.push_back({{"address", address_hex(s.address)}, {"where", s.where}, {"instruction", s.instruction},
                     {"clocks", s.clocks}, {"line", s.line}, {"times", s.times}});
    return a;
}

nlohmann::json loops_json(const std::vector<Loop>& loops) {
    nlohmann::json a = nlohmann::json::array();
    for (const Loop& l : loops)
        a.push_back({{"address", address_hex(l.header)}, {"where", l.where}, {"iterations", l.iterations}, {"reason", l.reason}});
    return a;
}

nlohmann::json term_json(const Term& t) {
    return {{"name", t.name}, {"clocks", t.clocks}, {"us", t.us}, {"what", t.what}};
}

} // namespace

nlohmann::json to_json(const Result& r) {
    nlohmann::json j;
    j["budget_us"] = r.budget_us;
    j["clock_mhz"] = r.clock_mhz;
    j["fits"] = r.fits();
    j["waits"] = {{"code", r.waits.code}, {"data", r.waits.data}, {"io", r.waits.io}, {"inta", r.waits.inta},
                  {"reason", r.waits_reason}};
    j["sources"] = nlohmann::json::object();
    for (const auto& [name, b] : r.sources) {
        nlohmann::json s;
        s["vector"] = "0x" + hex(b.source.vector, 2);
        s["entry"] = b.entry;
        s["service_us"] = b.service_us;
        s["blocking_us"] = b.blocking_us;
        s["latency_us"] = b.latency_us;
        s["service_clocks"] = b.service_clocks;
        s["blocking_clocks"] = b.blocking_clocks;
        s["latency_clocks"] = b.latency_clocks;
        s["reenables_interrupts"] = b.reenables;
        s["path"] = steps_json(b.path);
        s["blocking_path"] = steps_json(b.blocking_path);
        s["loops"] = loops_json(b.loops);
        s["latency_terms"] = nlohmann::json::array();
        for (const Term& t : b.latency_terms) s["latency_terms"].push_back(term_json(t));
        j["sources"][name] = s;
    }
    j["main_if0"] = {{"us", r.main_if0.us}, {"clocks", r.main_if0.clocks}, {"path", steps_json(r.main_if0.path)},
                     {"loops", loops_json(r.main_if0.loops)}};
    j["longest_instruction"] = term_json(r.longest_instruction);
    j["entry"] = term_json(r.entry);
    return j;
}

std::string describe_over_budget(const Result& r) {
    std::string out;
    for (const auto& [name, b] : r.sources) {
        if (b.blocking_us <= r.budget_us) continue;
        // The routines the blocking path runs, in the order it enters them.
        std::vector<std::string> routines;
        for (const Step& s : b.blocking_path) {
            const std::string routine = s.where.substr(0, s.where.find('+'));
            if (std::find(routines.begin(), routines.end(), routine) == routines.end()) routines.push_back(routine);
        }
        std::string chain;
        for (const std::string& x : routines) chain += (chain.empty() ? "" : " > ") + x;
        char line[160];
        std::snprintf(line, sizeof line, "%s: blocking bound %.1f us over the budget %.1f us; its path: ", name.c_str(),
                      b.blocking_us, r.budget_us);
        out += (out.empty() ? "" : "\n") + std::string(line) + chain;
    }
    return out;
}

} // namespace rcsim::bound
