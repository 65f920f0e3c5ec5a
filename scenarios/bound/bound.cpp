// rcsim — the static worst case of every interrupt path. See bound.h.
#include "scenarios/bound/bound.h"

#include "models/plumbing/config_error.h"
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

std::string hex(std::uint32_t v) {
    char b[16];
    std::snprintf(b, sizeof b, "0x%05X", unsigned(v));
    return b;
}

double to_us(std::uint64_t clocks, double mhz) { return std::round(double(clocks) / mhz * 10.0) / 10.0; }

/// The worst clocks of every node of `g` that `want` selects (the others 0).
std::vector<std::uint64_t> costs(const FlowGraph& g, i8086::WorstClocks& clocks, const std::vector<bool>& want) {
    std::vector<std::uint64_t> c(g.nodes().size(), 0);
    for (std::size_t v = 0; v < c.size(); ++v) {
        if (!want[v]) continue;
        const Node& n = g.nodes()[v];
        const Insn& i = *n.insn;
        std::uint32_t cx_max = 0xFFFF;
        if (uses_cx_count(i)) {
            cx_max = is_shift_by_cl(i) ? n.in.b8[CX].hi : n.in.reg[CX].hi; // a shift counts by CL alone
            if (i.rep && is_string_op(i)) {
                if (const Annotation* a = g.annotation(i.address, Annotation::Kind::iterations))
                    cx_max = std::uint32_t(std::min<std::uint64_t>(a->iterations, 0xFFFF));
                else if (n.in.reg[CX].lo == 0 && n.in.reg[CX].hi == 0xFFFF)
                    throw ConfigError("bound: a " + i.text + " at " + g.where(i.address) + " (" + hex(i.address) +
                                      ") whose count CX the code does not state: add `" + g.where(i.address) +
                                      " iterations N  # why` to the annotations");
            }
        }
        c[v] = clocks.instruction(i.bytes, i.length, n.ip, cx_max);
    }
    return c;
}

std::vector<std::vector<int>> predecessors(const FlowGraph& g) {
    std::vector<std::vector<int>> p(g.nodes().size());
    for (std::size_t v = 0; v < p.size(); ++v)
        for (const auto& e : g.nodes()[v].out) p[std::size_t(e.to)].push_back(int(v));
    return p;
}

/// A loop's bound: an annotation at its header or a latch; a LOOP whose CX only it changes; a
/// register counted down by one DEC on every way round, tested by the JNZ after it.
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
            Interval v{0xFFFF, 0, true};
            bool any = false;
            for (int p : preds[std::size_t(l.header)]) {
                if (body.count(p)) continue;
                const Interval e = g.out_state(p, l.header).reg[reg];
                v = {std::min(v.lo, e.lo), std::max(v.hi, e.hi), false};
                any = true;
            }
            return any ? v : Interval::top();
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
        if (l.latches.size() == 1) { // DEC r ; JNZ back
            const int latch = l.latches[0];
            const Insn& j = *nodes[std::size_t(latch)].insn;
            const auto& lp = preds[std::size_t(latch)];
            if ((j.opcode == 0x75 || j.opcode == 0x65) && lp.size() == 1 && body.count(lp[0])) {
                const Insn& d = *nodes[std::size_t(lp[0])].insn;
                int reg = -1;
                unsigned width = 2;
                if (d.opcode >= 0x48 && d.opcode <= 0x4F) reg = d.opcode & 7;
                if ((d.opcode == 0xFE || d.opcode == 0xFF) && d.mod == 3 && d.reg == 1)
                    reg = int(d.opcode == 0xFF ? d.rm : d.rm & 3), width = d.opcode == 0xFF ? 2 : 1;
                if (reg >= 0 && only_writers(reg, {lp[0]})) {
                    Interval v = entry_interval(reg);
                    if (width == 1) v = d.rm >= 4 ? Interval{v.lo >> 8, v.hi >> 8, false}
                                                  : ((v.hi >> 8) == (v.lo >> 8) ? Interval{v.lo & 0xFF, v.hi & 0xFF, false}
                                                                                : Interval{0, 0xFF, false});
                    if (v.lo >= 1) {
                        l.bound = v.hi;
                        l.reason = "counted down from <= " + std::to_string(v.hi) + " by " + d.text + " and " + j.text;
                        return;
                    }
                }
            }
        }
        const std::uint32_t a = nodes[std::size_t(l.header)].address;
        throw ConfigError("bound: a loop at " + g.where(a) + " (" + hex(a) +
                          ") has no bound the code states: add `" + g.where(a) +
                          " iterations N  # why` to the annotations");
    };
}

/// The path's instructions in the order it first runs them; an instruction the path runs in
/// several call contexts is one step with their counts added.
std::vector<Step> steps_of(const FlowGraph& g, const Paths::Longest& p, const std::vector<std::uint64_t>& cost) {
    std::vector<Step> out;
    std::map<std::uint32_t, std::size_t> at;
    for (auto [v, times] : p.nodes) {
        const Node& n = g.nodes()[std::size_t(v)];
        const unsigned clocks = unsigned(cost[std::size_t(v)]);
        auto it = at.find(n.address);
        if (it != at.end() && out[it->second].clocks == clocks) {
            out[it->second].times += times;
            continue;
        }
        at[n.address] = out.size();
        out.push_back(Step{n.address, g.where(n.address), n.insn->text, clocks, times});
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
    const std::vector<std::uint64_t> cost = costs(g, clocks, running);
    for (std::size_t v = 0; v < nodes.size(); ++v)
        if (running[v] && cost[v] > longest_instruction.clocks) {
            longest_instruction.clocks = cost[v];
            longest_instruction.what = nodes[v].insn->text + " at " + g.where(nodes[v].address);
        }
    if (sources.empty()) return;
    const Paths paths(g, member, sources, bounder_for(g, preds));
    const Paths::Longest p = paths.longest(cost);
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
    const std::vector<std::uint64_t> cost = costs(g, clocks, all);
    std::vector<std::uint64_t> blocking(nodes.size(), 0);
    SourceBound b;
    b.source = s;
    b.entry = g.where(nodes[0].address);
    for (std::size_t v = 0; v < nodes.size(); ++v) {
        const State& st = nodes[v].in;
        if (st.if_flag != IfState::on || st.eoi != Eoi::yes) blocking[v] = cost[v];
        if (st.if_flag == IfState::on) b.reenables = true;
        if (cost[v] > longest_instruction.clocks) {
            longest_instruction.clocks = cost[v];
            longest_instruction.what = nodes[v].insn->text + " at " + g.where(nodes[v].address);
        }
    }
    const Paths paths(g, all, {0}, bounder_for(g, preds));
    const Paths::Longest service = paths.longest(cost), block = paths.longest(blocking);
    b.service_clocks = service.clocks;
    b.blocking_clocks = block.clocks;
    b.service_us = to_us(service.clocks, in.clock_mhz);
    b.blocking_us = to_us(block.clocks, in.clock_mhz);
    b.path = steps_of(g, service, cost);
    b.blocking_path = steps_of(g, block, cost);
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
            throw ConfigError(a.where + ": no loop or REP of the bounded code is at " + hex(a.address) +
                              " (the code changed? remove or move the line)");
    return r;
}

namespace {

nlohmann::json steps_json(const std::vector<Step>& steps) {
    nlohmann::json a = nlohmann::json::array();
    for (const Step& s : steps)
        a.push_back({{"address", hex(s.address)}, {"where", s.where}, {"instruction", s.instruction},
                     {"clocks", s.clocks}, {"times", s.times}});
    return a;
}

nlohmann::json loops_json(const std::vector<Loop>& loops) {
    nlohmann::json a = nlohmann::json::array();
    for (const Loop& l : loops)
        a.push_back({{"address", hex(l.header)}, {"where", l.where}, {"iterations", l.iterations}, {"reason", l.reason}});
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
        char vec[8];
        std::snprintf(vec, sizeof vec, "0x%02X", unsigned(b.source.vector));
        s["vector"] = vec;
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
