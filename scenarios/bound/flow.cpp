// rcsim — the control flow of a ROM from one entry. See flow.h.
#include "scenarios/bound/flow.h"

#include "scenarios/bound/semantics.h"

#include "comm_cpu/i8086/disasm.h"
#include "models/plumbing/config_error.h"
#include "models/plumbing/hex.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <deque>

namespace rcsim::bound {
namespace {

using i8086::Flow;

constexpr int AX = 0, CX = 1, DX = 2;
constexpr std::size_t kMaxNodes = 400000;   // a graph this large is a ROM the analysis cannot bound
constexpr unsigned kMaxDepth = 32;          // calls nested deeper than this: recursion in effect
constexpr unsigned kWidenAfter = 6;         // updates of a node's state before its intervals widen

std::string address_hex(std::uint32_t v) { return "0x" + hex(v, 5); }

bool has_modrm(std::uint8_t op) {
    if (op < 0x40) return (op & 7) < 4;
    if (op >= 0x80 && op <= 0x8F) return true;
    return op == 0xC4 || op == 0xC5 || op == 0xC6 || op == 0xC7 || (op >= 0xD0 && op <= 0xD3) ||
           (op >= 0xD8 && op <= 0xDF) || op == 0xF6 || op == 0xF7 || op == 0xFE || op == 0xFF;
}

} // namespace

bool State::operator==(const State& o) const {
    for (int r = 0; r < 8; ++r)
        if (!(reg[r] == o.reg[r]) || !(b8[r] == o.b8[r]) || reg_is_flags[r] != o.reg_is_flags[r] ||
            reg_flags[r] != o.reg_flags[r])
            return false;
    for (int k = 0; k < 12; ++k)
        if (writer[k] != o.writer[k]) return false;
    return if_flag == o.if_flag && eoi == o.eoi && stack == o.stack && half_popped == o.half_popped &&
           saved_if == o.saved_if && bp_depth == o.bp_depth && cmp_reg == o.cmp_reg && cmp_value == o.cmp_value &&
           cmp_zero_only == o.cmp_zero_only;
}

// ---- decoding -------------------------------------------------------------------------------

const Insn& FlowGraph::insn_at(std::uint32_t address, std::uint16_t ip) const {
    auto it = insns_.find(address);
    if (it != insns_.end()) return it->second;
    const std::uint32_t off = address - in_.rom_base;
    if (address < in_.rom_base || off >= in_.rom.size()) fail(address, "the code leaves the ROM");
    Insn n;
    n.address = address;
    n.ip = ip;
    const unsigned avail = unsigned(std::min<std::size_t>(sizeof n.bytes, in_.rom.size() - off));
    std::copy_n(in_.rom.begin() + off, avail, n.bytes);
    const i8086::Decoded d = i8086::decode(n.bytes, avail);
    if (d.length == 0) fail(address, "an instruction runs past the end of the ROM");
    n.length = d.length;
    n.prefixes = d.prefixes;
    n.opcode = d.opcode;
    n.flow = d.flow;
    n.text = i8086::mnemonic(n.bytes, avail);
    for (unsigned i = 0; i < d.prefixes; ++i) {
        const std::uint8_t p = n.bytes[i];
        if (p == 0xF2 || p == 0xF3) n.rep = true;
        if ((p & 0xE7) == 0x26) n.segment = (p >> 3) & 3;
    }
    unsigned at = d.prefixes + 1;
    if (has_modrm(n.opcode)) {
        n.has_modrm = true;
        const std::uint8_t m = n.bytes[at++];
        n.mod = m >> 6;
        n.reg = (m >> 3) & 7;
        n.rm = m & 7;
        if (n.mod == 1) n.disp = std::int8_t(n.bytes[at++]);
        else if (n.mod == 2 || (n.mod == 0 && n.rm == 6)) {
            n.disp = std::int16_t(n.bytes[at] | (n.bytes[at + 1] << 8));
            at += 2;
        }
    }
    // The immediate is whatever the decoder's length leaves after the ModR/M bytes.
    const unsigned rest = n.length - at;
    if (rest == 1) n.imm = n.bytes[at];
    else if (rest >= 2) n.imm = std::uint32_t(n.bytes[at] | (n.bytes[at + 1] << 8));
    if (n.opcode == 0x83 && rest == 1) n.imm = std::uint32_t(std::int16_t(std::int8_t(n.bytes[at]))) & 0xFFFF;
    return insns_.emplace(address, n).first->second;
}

std::string FlowGraph::where(std::uint32_t address) const {
    if (const debug::Symbol* s = in_.symbols.containing(address)) {
        if (s->address == address) return s->name;
        char b[16];
        std::snprintf(b, sizeof b, "+0x%X", unsigned(address - s->address));
        return s->name + b;
    }
    return address_hex(address);
}

void FlowGraph::fail(std::uint32_t address, const std::string& why) const {
    throw ConfigError("bound: " + entry_name_ + ": " + why + " at " + where(address) + " (" + address_hex(address) + ")");
}

const Annotation* FlowGraph::annotation(std::uint32_t address, Annotation::Kind kind) const {
    for (const Annotation& a : in_.annotations)
        if (a.address == address && a.kind == kind) {
            a.used = true;
            return &a;
        }
    return nullptr;
}

int FlowGraph::writes_byte_only(const Insn& n) {
    const std::uint8_t op = n.opcode;
    if (op >= 0xB0 && op <= 0xB7) return op & 7;
    const bool byte_form = (op < 0x40 && (op & 7) < 4 && !(op & 1)) || op == 0x80 || op == 0x82 || op == 0x88 ||
                           op == 0x8A || op == 0xC6 || op == 0xD0 || op == 0xD2 || op == 0xFE ||
                           (op == 0xF6 && (n.reg == 2 || n.reg == 3));
    if (!byte_form || !n.has_modrm) return -1;
    if (op == 0x8A || (op < 0x40 && (op & 2))) return int(n.reg);
    return n.mod == 3 ? int(n.rm) : -1;
}

bool FlowGraph::writes(const Insn& n, int r) {
    const std::uint8_t op = n.opcode;
    const unsigned width = (op & 1) ? 2 : 1;
    auto rm_is = [&](unsigned w) { return n.mod == 3 && (w == 2 ? int(n.rm) == r : int(n.rm & 3) == r); };
    auto reg_is = [&](unsigned w) { return w == 2 ? int(n.reg) == r : int(n.reg & 3) == r; };
    if (op < 0x40 && (op & 7) < 4) {
        if ((op & 0x38) == 0x38) return false; // CMP
        if (((op & 0x38) == 0x08 || (op & 0x38) == 0x20) && n.mod == 3 && n.reg == n.rm) return false; // OR/AND r,r: flags only
        return (op & 2) ? reg_is(width) : rm_is(width);
    }
    if (op < 0x40 && ((op & 7) == 4 || (op & 7) == 5)) return (op & 0x38) != 0x38 && r == AX;
    if (op < 0x40 && (op & 7) == 7) return r == AX; // DAA DAS AAA AAS
    if (op >= 0x40 && op <= 0x5F) return int(op & 7) == r && op >= 0x40 && (op < 0x50 || op >= 0x58);
    if (op >= 0x80 && op <= 0x83) return n.reg != 7 && rm_is(op == 0x81 || op == 0x83 ? 2 : 1);
    if (op == 0x86 || op == 0x87) return reg_is(width) || rm_is(width);
    if (op == 0x88 || op == 0x89 || op == 0x8C) return rm_is(op == 0x88 ? 1 : 2);
    if (op == 0x8A || op == 0x8B || op == 0x8D || op == 0xC4 || op == 0xC5) return reg_is(op == 0x8A ? 1 : 2);
    if (op == 0x8F) return rm_is(2);
    if (op >= 0x90 && op <= 0x97) return op != 0x90 && (r == AX || int(op & 7) == r);
    if (op == 0x98 || op == 0x9F || op == 0xA0 || op == 0xA1 || op == 0xD4 || op == 0xD5 || op == 0xD7) return r == AX;
    if (op == 0x99) return r == DX;
    if (op >= 0xA4 && op <= 0xAF) return r == 6 || r == 7 || (n.rep && r == CX) || ((op == 0xAC || op == 0xAD) && r == AX);
    if (op >= 0xB0 && op <= 0xBF) return op < 0xB8 ? int(op & 3) == r : int(op & 7) == r;
    if (op == 0xC6 || op == 0xC7 || (op >= 0xD0 && op <= 0xD3)) return rm_is(width);
    if (op >= 0xE0 && op <= 0xE2) return r == CX;
    if (op == 0xE4 || op == 0xE5 || op == 0xEC || op == 0xED) return r == AX;
    if (op == 0xF6 || op == 0xF7) {
        if (n.reg < 2) return false;
        if (n.reg < 4) return rm_is(width);
        return r == AX || (op == 0xF7 && r == DX);
    }
    if (op == 0xFE || op == 0xFF) return n.reg < 2 && rm_is(op == 0xFE ? 1 : 2);
    return false;
}

// ---- the graph ------------------------------------------------------------------------------

FlowGraph::FlowGraph(const Inputs& inputs, std::uint16_t cs, std::uint16_t ip, State entry_state, std::string entry_name)
    : in_(inputs), entry_name_(std::move(entry_name)) {
    Context root;
    root.routine = (std::uint32_t(cs) << 4) + ip;
    contexts_.push_back(root);
    node_for(0, cs, ip);
    build(std::move(entry_state));
}

int FlowGraph::node_for(int context, std::uint16_t cs, std::uint16_t ip) {
    const std::uint32_t linear = ((std::uint32_t(cs) << 4) + ip) & 0xFFFFF;
    const auto key = std::make_pair(context, linear);
    if (auto it = index_.find(key); it != index_.end()) return it->second;
    if (nodes_.size() >= kMaxNodes)
        fail(linear, "more than " + std::to_string(kMaxNodes) + " instructions with calls inlined (a loop of calls?)");
    Node n;
    n.address = linear;
    n.context = context;
    n.cs = cs;
    n.ip = ip;
    n.insn = &insn_at(linear, ip);
    nodes_.push_back(std::move(n));
    index_.emplace(key, int(nodes_.size() - 1));
    return int(nodes_.size() - 1);
}

int FlowGraph::call_context(int from, std::uint32_t routine, std::uint16_t ret_cs, std::uint16_t ret_ip, unsigned depth) {
    const std::uint32_t site = nodes_[std::size_t(from)].address;
    const int parent = nodes_[std::size_t(from)].context;
    const auto key = std::make_pair(parent, site);
    if (auto it = context_of_.find(key); it != context_of_.end()) return it->second;
    unsigned nesting = 0;
    for (int c = parent; c >= 0; c = contexts_[std::size_t(c)].parent, ++nesting)
        if (contexts_[std::size_t(c)].routine == routine && c != 0)
            fail(site, "recursion: " + where(routine) + " calls itself through this call; a bound needs no recursion");
    if (nesting >= kMaxDepth) fail(site, "calls nested more than " + std::to_string(kMaxDepth) + " deep");
    Context c;
    c.parent = parent;
    c.call_site = site;
    c.return_cs = ret_cs;
    c.return_ip = ret_ip;
    c.routine = routine;
    c.saves_if = annotation(routine, Annotation::Kind::irq_save) != nullptr;
    c.restores_if = annotation(routine, Annotation::Kind::irq_restore) != nullptr;
    c.stack_at_call = depth;
    contexts_.push_back(c);
    context_of_.emplace(key, int(contexts_.size() - 1));
    return int(contexts_.size() - 1);
}

void FlowGraph::build(State entry_state) {
    nodes_[0].in = std::move(entry_state);
    std::deque<int> work{0};
    std::vector<bool> queued(1, true);
    std::vector<int> preds_seen(1, 0);
    std::vector<std::pair<int, State>> next;
    while (!work.empty()) {
        const int n = work.front();
        work.pop_front();
        queued[std::size_t(n)] = false;
        next.clear();
        successors(n, next);
        auto& edges = nodes_[std::size_t(n)].out;
        for (auto& [to, st] : next) {
            if (std::none_of(edges.begin(), edges.end(), [&](const Node::Edge& e) { return e.to == to; })) {
                edges.push_back({to});
                preds_seen.resize(nodes_.size(), 0);
                ++preds_seen[std::size_t(to)];
            }
            queued.resize(nodes_.size(), false);
            Node& t = nodes_[std::size_t(to)];
            State joined = t.updates == 0 ? st : join(t.in, st);
            if (t.updates > 0 && joined == t.in) continue;
            // Widen where paths meet (every loop has such a node): a node with one predecessor
            // keeps what the edge into it states (a test's narrowing of a counter).
            if (++t.updates > kWidenAfter && preds_seen[std::size_t(to)] > 1) widen(joined, t.in);
            t.in = std::move(joined);
            if (!queued[std::size_t(to)]) {
                queued[std::size_t(to)] = true;
                work.push_back(to);
            }
        }
    }
}

State FlowGraph::out_state(int n, int to) const {
    std::vector<std::pair<int, State>> next;
    const_cast<FlowGraph*>(this)->successors(n, next);
    for (auto& [t, st] : next)
        if (t == to) return st;
    return nodes_[std::size_t(n)].in;
}

void FlowGraph::successors(int n, std::vector<std::pair<int, State>>& out) {
    const Insn& i = *nodes_[std::size_t(n)].insn;
    const int ctx = nodes_[std::size_t(n)].context;
    const State& in = nodes_[std::size_t(n)].in;
    const std::uint16_t cs = nodes_[std::size_t(n)].cs, ip = nodes_[std::size_t(n)].ip;
    const std::uint16_t next_ip = std::uint16_t(ip + i.length);
    auto go = [&](int c, std::uint16_t to_cs, std::uint16_t to_ip, State st) {
        const int t = node_for(c, to_cs, to_ip);
        out.emplace_back(t, std::move(st));
    };
    auto go_call = [&](std::uint16_t to_cs, std::uint16_t to_ip, State st, unsigned pushed) {
        const unsigned depth = unsigned(in.stack.size());
        for (unsigned k = 0; k < pushed; ++k) push(st, {});
        const int c = call_context(n, (std::uint32_t(to_cs) << 4) + to_ip, cs, next_ip, depth);
        go(c, to_cs, to_ip, std::move(st));
    };
    auto go_return = [&](State st) {
        if (ctx == 0) fail(i.address, "a return from the entry itself (RET where IRET was expected)");
        const Context& c = contexts_[std::size_t(ctx)];
        st.stack.resize(std::min<std::size_t>(st.stack.size(), c.stack_at_call));
        // irq_save: what IF was at the call, for the irq_restore that pairs with it.
        if (c.saves_if) st.saved_if.push_back(nodes_[std::size_t(index_.at({c.parent, c.call_site}))].in.if_flag);
        if (c.restores_if) {
            st.if_flag = st.saved_if.empty() ? IfState::unknown : st.saved_if.back();
            if (!st.saved_if.empty()) st.saved_if.pop_back();
        }
        go(c.parent, c.return_cs, c.return_ip, std::move(st));
    };
    State st = in;
    st.now = n;
    if (i.flow == Flow::next) {
        execute(i, st, in_.pic_port);
        return go(ctx, cs, next_ip, std::move(st));
    }
    switch (i.flow) {
    case Flow::jump:
    case Flow::call_near: {
        std::vector<std::uint16_t> targets;
        if (auto t = i8086::direct_target(i.bytes, i8086::decode(i.bytes, i.length), ip)) targets.push_back(t->ip);
        else targets = indirect_targets(n);
        for (std::uint16_t t : targets) {
            if (i.flow == Flow::jump) go(ctx, cs, t, st);
            else go_call(cs, t, st, 1);
        }
        return;
    }
    case Flow::jump_far:
    case Flow::call_far: {
        auto t = i8086::direct_target(i.bytes, i8086::decode(i.bytes, i.length), ip);
        if (!t) {
            const Annotation* a = annotation(i.address, Annotation::Kind::targets);
            if (!a) fail(i.address, "a far transfer through memory: add `" + where(i.address) + " targets ADDRESS ...  # why`");
            for (std::uint32_t l : a->targets) {
                if (i.flow == Flow::jump_far) go(ctx, std::uint16_t(l >> 4), std::uint16_t(l & 0xF), st);
                else go_call(std::uint16_t(l >> 4), std::uint16_t(l & 0xF), st, 2);
            }
            return;
        }
        if (i.flow == Flow::jump_far) go(ctx, t->cs, t->ip, st);
        else go_call(t->cs, t->ip, st, 2);
        return;
    }
    case Flow::branch: {
        const auto t = i8086::direct_target(i.bytes, i8086::decode(i.bytes, i.length), ip);
        const std::uint8_t op = i.opcode;
        State taken = st, fall = st;
        taken.cmp_reg = fall.cmp_reg = -1;
        bool can_take = true, can_fall = true;
        if (op >= 0x60 && op <= 0x7F) {
            can_take = refine(taken = st, op & 0xF, true);
            can_fall = refine(fall = st, op & 0xF, false);
            taken.cmp_reg = fall.cmp_reg = -1;
        } else if (op == 0xE3) { // JCXZ: narrows CX on each way, writes nothing
            taken.now = fall.now = in.writer[CX]; // (both halves: CX's word writer, if one)
            set_reg(taken, CX, 2, Interval::constant(0));
            if (fall.reg[CX].is_constant() && fall.reg[CX].lo == 0) can_fall = false;
            Interval cx = fall.reg[CX];
            cx.lo = std::max<std::uint32_t>(cx.lo, 1);
            set_reg(fall, CX, 2, cx);
            for (int k : {CX, CX + 4}) taken.writer[k] = fall.writer[k] = in.writer[k];
            if (in.reg[CX].lo != 0) can_take = false;
        } else { // LOOP, LOOPE, LOOPNE: CX - 1, then taken while it is not 0
            Interval cx = in.reg[CX];
            cx = cx.lo > 0 ? Interval{cx.lo - 1, cx.hi - 1, false} : Interval::top();
            if (cx.is_constant() && cx.lo == 0) can_take = false;
            set_reg(fall, CX, 2, op == 0xE2 ? Interval::constant(0) : cx);
            cx.lo = std::max<std::uint32_t>(cx.lo, 1);
            set_reg(taken, CX, 2, cx);
        }
        if (can_take) go(ctx, cs, t->ip, std::move(taken));
        if (can_fall) go(ctx, cs, next_ip, std::move(fall));
        return;
    }
    case Flow::ret_near:
    case Flow::ret_far:
        return go_return(std::move(st));
    case Flow::iret:
        if (ctx != 0) fail(i.address, "IRET inside a called routine");
        nodes_[std::size_t(n)].exit = true;
        return;
    case Flow::halt:
        nodes_[std::size_t(n)].exit = true;
        return;
    case Flow::int_sw:
        fail(i.address, "a software interrupt (" + i.text + "): the bound does not follow INT n");
    default: return;
    }
}

std::vector<std::uint16_t> FlowGraph::indirect_targets(int n) {
    const Insn& i = *nodes_[std::size_t(n)].insn;
    const State& in = nodes_[std::size_t(n)].in;
    const std::uint32_t cs_base = std::uint32_t(nodes_[std::size_t(n)].cs) << 4;
    std::vector<std::uint16_t> out;
    if (const Annotation* a = annotation(i.address, Annotation::Kind::targets)) {
        for (std::uint32_t l : a->targets) {
            if (l - cs_base > 0xFFFF) fail(i.address, "annotated target " + address_hex(l) + " is outside this code segment");
            out.push_back(std::uint16_t(l - cs_base));
        }
        return out;
    }
    // A jump table in the ROM: CS:[table + index] with the index's range and evenness known (a
    // compare and a conditional jump before it, and the index doubled).
    static const int kIndex[8] = {-1, -1, -1, -1, 6, 7, -1, 3}; // [SI+d], [DI+d], [BX+d]
    if (i.mod != 3 && i.mod != 0 && i.segment == 1 && kIndex[i.rm] >= 0) {
        const Interval v = in.reg[kIndex[i.rm]];
        if (v.even && v.hi - v.lo <= 512) {
            for (std::uint32_t k = v.lo; k <= v.hi; k += 2) {
                const std::uint32_t at = cs_base + ((std::uint32_t(i.disp) + k) & 0xFFFF);
                if (at < in_.rom_base || at + 1 - in_.rom_base >= in_.rom.size())
                    fail(i.address, "a jump table entry at " + address_hex(at) + " outside the ROM");
                const std::size_t o = at - in_.rom_base;
                out.push_back(std::uint16_t(in_.rom[o] | (in_.rom[o + 1] << 8)));
            }
            return out;
        }
    }
    fail(i.address, std::string("an indirect ") + (i.flow == i8086::Flow::jump ? "jump" : "call") +
                        " whose targets the code does not state: add `" + where(i.address) +
                        " targets ADDRESS ...  # why` to the annotations");
}

} // namespace rcsim::bound
