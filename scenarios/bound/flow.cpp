// rcsim — the control flow of a ROM from one entry. See flow.h.
#include "scenarios/bound/flow.h"

#include "comm_cpu/i8086/disasm.h"
#include "models/plumbing/config_error.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <deque>

namespace rcsim::bound {
namespace {

using i8086::Flow;

constexpr int AX = 0, CX = 1, DX = 2, SP = 4, BP = 5;
constexpr std::size_t kMaxNodes = 400000;   // a graph this large is a ROM the analysis cannot bound
constexpr unsigned kMaxDepth = 32;          // calls nested deeper than this: recursion in effect
constexpr std::size_t kMaxStack = 256;      // abstract stack words kept (the oldest are dropped)
constexpr unsigned kWidenAfter = 6;         // updates of a node's state before its intervals widen

std::string hex(std::uint32_t v, int digits = 5) {
    char b[16];
    std::snprintf(b, sizeof b, "0x%0*X", digits, unsigned(v));
    return b;
}

bool has_modrm(std::uint8_t op) {
    if (op < 0x40) return (op & 7) < 4;
    if (op >= 0x80 && op <= 0x8F) return true;
    return op == 0xC4 || op == 0xC5 || op == 0xC6 || op == 0xC7 || (op >= 0xD0 && op <= 0xD3) ||
           (op >= 0xD8 && op <= 0xDF) || op == 0xF6 || op == 0xF7 || op == 0xFE || op == 0xFF;
}

// ---- intervals ------------------------------------------------------------------------------

Interval join(const Interval& a, const Interval& b) {
    return {std::min(a.lo, b.lo), std::max(a.hi, b.hi), a.even && b.even};
}

Interval byte_of(const Interval& w, bool high) {
    if (high) return {w.lo >> 8, w.hi >> 8, w.is_constant() && ((w.lo >> 8) & 1) == 0};
    if ((w.lo >> 8) == (w.hi >> 8)) return {w.lo & 0xFF, w.hi & 0xFF, w.even};
    return {0, 0xFF, w.even};
}

std::uint32_t mask_of(unsigned width) { return width == 2 ? 0xFFFF : 0xFF; }

std::uint32_t all_ones_over(std::uint32_t v) {
    std::uint32_t m = 0;
    while (m < v) m = m * 2 + 1;
    return m;
}

/// The ALU's result interval for op (the 80 /op numbering: ADD OR ADC SBB AND SUB XOR CMP).
Interval alu(unsigned op, const Interval& d, const Interval& s, unsigned width) {
    const std::uint32_t m = mask_of(width);
    const Interval top{0, m, false};
    if (d.is_constant() && s.is_constant()) {
        switch (op) {
        case 0: return Interval::constant((d.lo + s.lo) & m);
        case 1: return Interval::constant(d.lo | s.lo);
        case 4: return Interval::constant(d.lo & s.lo);
        case 5: return Interval::constant((d.lo - s.lo) & m);
        case 6: return Interval::constant(d.lo ^ s.lo);
        default: break;
        }
    }
    switch (op) {
    case 0:
        if (d.hi + s.hi <= m) return {d.lo + s.lo, d.hi + s.hi, d.even && s.even};
        return top;
    case 5:
        if (d.lo >= s.hi) return {d.lo - s.hi, d.hi - s.lo, d.even && s.even};
        return top;
    case 4: return {0, std::min(d.hi, s.hi), d.even || s.even};
    case 1:
    case 6: return {0, all_ones_over(std::max(d.hi, s.hi)), false};
    default: return top;
    }
}

IfState join_if(IfState a, IfState b) { return a == b ? a : IfState::unknown; }

State join(const State& a, const State& b) {
    State s = a;
    for (int r = 0; r < 8; ++r) {
        s.reg[r] = join(a.reg[r], b.reg[r]);
        s.reg_is_flags[r] = a.reg_is_flags[r] && b.reg_is_flags[r];
        s.reg_flags[r] = join_if(a.reg_flags[r], b.reg_flags[r]);
        s.b8[r] = join(a.b8[r], b.b8[r]);
    }
    for (int k = 0; k < 12; ++k)
        if (a.writer[k] != b.writer[k]) s.writer[k] = State::kMixed;
    s.if_flag = join_if(a.if_flag, b.if_flag);
    s.eoi = a.eoi == b.eoi ? a.eoi : Eoi::maybe;
    // Stacks of different depths meet only on unbalanced paths: keep the common bottom words.
    const std::size_t n = std::min(a.stack.size(), b.stack.size());
    s.stack.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (a.stack[i] == b.stack[i]) continue;
        s.stack[i].value = join(a.stack[i].value, b.stack[i].value);
        s.stack[i].flags = a.stack[i].flags && b.stack[i].flags;
        s.stack[i].if_saved = join_if(a.stack[i].if_saved, b.stack[i].if_saved);
    }
    const std::size_t k = std::min(a.saved_if.size(), b.saved_if.size());
    s.saved_if.resize(k);
    for (std::size_t i = 0; i < k; ++i) s.saved_if[i] = join_if(a.saved_if[i], b.saved_if[i]);
    s.half_popped = a.half_popped || b.half_popped;
    if (a.bp_depth != b.bp_depth) s.bp_depth = -1;
    if (a.cmp_reg != b.cmp_reg || a.cmp_value != b.cmp_value || a.cmp_zero_only != b.cmp_zero_only) s.cmp_reg = -1;
    return s;
}

/// After repeated updates: every interval that still moves goes to the top.
void widen(State& s, const State& before) {
    for (int r = 0; r < 8; ++r) {
        if (!(s.reg[r] == before.reg[r])) s.reg[r] = Interval::top();
        if (!(s.b8[r] == before.b8[r])) s.b8[r] = Interval{0, 0xFF, false};
    }
    for (std::size_t i = 0; i < s.stack.size() && i < before.stack.size(); ++i)
        if (!(s.stack[i].value == before.stack[i].value)) s.stack[i].value = Interval::top();
    for (int k = 0; k < 12; ++k)
        if (s.writer[k] != before.writer[k]) s.writer[k] = State::kMixed;
}

// ---- register access ------------------------------------------------------------------------

Interval get_reg(const State& s, unsigned r, unsigned width) { return width == 2 ? s.reg[r] : s.b8[r]; }

/// The writer slots of register r of `width` (State::writer).
void set_writer(State& s, unsigned r, unsigned width, int who) {
    if (width == 1) s.writer[r] = who;
    else if (r < 4) s.writer[r] = s.writer[r + 4] = who;
    else s.writer[r + 4] = who;
}

void set_reg(State& s, unsigned r, unsigned width, const Interval& v) {
    set_writer(s, r, width, s.now);
    if (width == 2) {
        s.reg[r] = v;
        if (r < 4) s.b8[r] = byte_of(v, false), s.b8[r + 4] = byte_of(v, true);
        s.reg_is_flags[r] = false;
        return;
    }
    s.b8[r] = v;
    const unsigned w = r & 3;
    const Interval lo = s.b8[w], hi = s.b8[w + 4];
    s.reg[w] = {hi.lo * 256 + lo.lo, hi.hi * 256 + lo.hi, lo.even};
    s.reg_is_flags[w] = false;
}

void push(State& s, const StackWord& w) {
    s.stack.push_back(w);
    if (s.stack.size() > kMaxStack) s.stack.erase(s.stack.begin());
}

StackWord pop(State& s) {
    if (s.stack.empty()) return {};
    StackWord w = s.stack.back();
    s.stack.pop_back();
    return w;
}

void clobber_all(State& s) {
    for (int r = 0; r < 8; ++r)
        if (r != SP) set_reg(s, unsigned(r), 2, Interval::top());
}

/// The interval a jump's condition leaves the compared register on one edge (false: the edge
/// cannot be taken). `cc` is the condition's low nibble (70-7F numbering).
bool refine(State& s, unsigned cc, bool taken) {
    if (s.cmp_reg < 0) return true;
    const bool byte = s.cmp_reg >= 8;
    const unsigned r = unsigned(s.cmp_reg & 7);
    Interval v = get_reg(s, r, byte ? 1 : 2);
    const std::uint32_t k = s.cmp_value;
    // The condition as "value < k" (b), "value <= k" (be), "value == k" (e), each possibly negated.
    bool negate = !taken;
    switch (cc) {
    case 0x2: case 0x3: // JB / JAE
    case 0x6: case 0x7: // JBE / JA
        if (s.cmp_zero_only) return true;
        if (cc & 1) negate = !negate;
        if ((cc & ~1u) == 0x2) { // value < k
            if (!negate) v.hi = std::min(v.hi, k == 0 ? 0 : k - 1), v.lo = k == 0 ? 1 : v.lo;
            else v.lo = std::max(v.lo, k);
        } else { // value <= k
            if (!negate) v.hi = std::min(v.hi, k);
            else v.lo = std::max(v.lo, k + 1);
        }
        break;
    case 0x4: case 0x5: // JE / JNE
        if (cc & 1) negate = !negate;
        if (!negate) {
            if (k < v.lo || k > v.hi) return false;
            v = Interval::constant(k);
        } else {
            if (v.is_constant() && v.lo == k) return false;
            if (v.lo == k) ++v.lo;
            if (v.hi == k && v.hi > v.lo) --v.hi;
        }
        break;
    default: return true;
    }
    if (v.lo > v.hi) return false;
    int kept[12];
    std::copy(std::begin(s.writer), std::end(s.writer), kept);
    set_reg(s, r, byte ? 1 : 2, v); // a narrower range of the same value: no new writer
    std::copy(std::begin(kept), std::end(kept), s.writer);
    return true;
}

/// What an instruction that is not a transfer of control does to the state.
void execute(const Insn& n, State& s, std::uint8_t pic_port) {
    const std::uint8_t op = n.opcode;
    const unsigned width = (op & 1) ? 2 : 1;
    s.cmp_reg = -1;
    s.cmp_zero_only = false;
    auto note_cmp = [&](int reg, std::uint32_t value, bool zero_only) {
        s.cmp_reg = reg;
        s.cmp_value = value;
        s.cmp_zero_only = zero_only;
    };
    auto reg_index = [](unsigned r, unsigned w) { return w == 2 ? int(r) : int(r) + 8; };
    if (op < 0x40 && (op & 7) < 4) { // ALU r/m,reg or reg,r/m
        const unsigned alu_op = op >> 3;
        const bool to_reg = op & 2;
        if (n.mod == 3) {
            const unsigned d = to_reg ? n.reg : n.rm, src = to_reg ? n.rm : n.reg;
            if ((alu_op == 6 || alu_op == 5) && n.reg == n.rm) { // XOR r,r / SUB r,r
                set_reg(s, d, width, Interval::constant(0));
                return;
            }
            if (alu_op == 0 && n.reg == n.rm) { // ADD r,r: doubles, and the result is even
                const Interval v = get_reg(s, d, width);
                set_reg(s, d, width, v.hi * 2 <= mask_of(width) ? Interval{v.lo * 2, v.hi * 2, true}
                                                                 : Interval{0, mask_of(width) - 1, true});
                return;
            }
            if ((alu_op == 1 || alu_op == 4) && n.reg == n.rm) { // OR r,r / AND r,r: flags only
                note_cmp(reg_index(d, width), 0, true);
                return;
            }
            if (alu_op == 7) return;
            set_reg(s, d, width, alu(alu_op, get_reg(s, d, width), get_reg(s, src, width), width));
        } else if (to_reg && alu_op != 7) {
            set_reg(s, n.reg, width, Interval{0, mask_of(width), false});
        }
        return;
    }
    if (op < 0x40 && ((op & 7) == 4 || (op & 7) == 5)) { // ALU AL/AX,imm
        const unsigned alu_op = op >> 3;
        if (alu_op == 7) return note_cmp(reg_index(0, width), n.imm, false);
        set_reg(s, 0, width, alu(alu_op, get_reg(s, 0, width), Interval::constant(n.imm), width));
        return;
    }
    if (op < 0x40 && (op & 7) == 7) return set_reg(s, AX, 2, Interval::top());
    if (op >= 0x40 && op <= 0x4F) { // INC/DEC r16
        const unsigned r = op & 7;
        if (r == SP) { // INC SP twice pops a word, DEC SP twice pushes one (bcc drops arguments so)
            if (s.half_popped) {
                s.half_popped = false;
                op < 0x48 ? (void)pop(s) : push(s, {});
            } else {
                s.half_popped = true;
            }
            return;
        }
        Interval v = s.reg[r];
        if (op < 0x48) v = v.hi < 0xFFFF ? Interval{v.lo + 1, v.hi + 1, false} : Interval::top();
        else v = v.lo > 0 ? Interval{v.lo - 1, v.hi - 1, false} : Interval::top();
        set_reg(s, r, 2, v);
        return note_cmp(int(r), 0, true);
    }
    if (op >= 0x50 && op <= 0x57) {
        const unsigned r = op & 7;
        StackWord w{s.reg[r], s.reg_is_flags[r], s.reg_flags[r], r == BP ? s.bp_depth : -1, {-1, -1}};
        w.writer[0] = r < 4 ? s.writer[r] : s.writer[r + 4];
        w.writer[1] = r < 4 ? s.writer[r + 4] : s.writer[r + 4];
        return push(s, w);
    }
    if (op >= 0x58 && op <= 0x5F) {
        const StackWord w = pop(s);
        const unsigned r = op & 7;
        if (r == SP) return;
        if (r == BP) s.bp_depth = w.bp_depth;
        set_reg(s, r, 2, w.value);
        s.reg_is_flags[r] = w.flags;
        s.reg_flags[r] = w.if_saved;
        if (r < 4) s.writer[r] = w.writer[0], s.writer[r + 4] = w.writer[1];
        else s.writer[r + 4] = w.writer[0];
        return;
    }
    if (op == 0x06 || op == 0x0E || op == 0x16 || op == 0x1E) return push(s, {});
    if (op == 0x07 || op == 0x17 || op == 0x1F) return (void)pop(s);
    if (op >= 0x80 && op <= 0x83) {
        const unsigned w = (op == 0x81 || op == 0x83) ? 2 : 1;
        if (n.mod != 3) return;
        if (n.reg == 7) return note_cmp(reg_index(n.rm, w), n.imm, false);
        if (n.rm == SP && w == 2 && (n.reg == 0 || n.reg == 5)) { // ADD/SUB SP,imm: words popped/pushed
            const int delta = std::int16_t(n.imm) * (n.reg == 0 ? 1 : -1); // bcc writes ADD SP,-6
            for (int i = 0; i < std::abs(delta) / 2; ++i) delta > 0 ? (void)pop(s) : push(s, {});
            return;
        }
        set_reg(s, n.rm, w, alu(n.reg, get_reg(s, n.rm, w), Interval::constant(n.imm), w));
        return;
    }
    if (op == 0x84 || op == 0x85) {
        if (n.mod == 3 && n.reg == n.rm) note_cmp(reg_index(n.rm, width), 0, true);
        return;
    }
    if (op == 0x86 || op == 0x87) {
        if (n.mod != 3) return set_reg(s, n.reg, width, Interval{0, mask_of(width), false});
        const Interval a = get_reg(s, n.reg, width), b = get_reg(s, n.rm, width);
        set_reg(s, n.reg, width, b);
        return set_reg(s, n.rm, width, a);
    }
    if (op == 0x88 || op == 0x89) {
        if (n.mod == 3) set_reg(s, n.rm, width, get_reg(s, n.reg, width));
        return;
    }
    if (op == 0x8A || op == 0x8B) {
        if (n.mod == 3) {
            if (width == 2 && n.reg == SP) { // MOV SP,BP: back to the frame's base
                if (n.rm == BP && s.bp_depth >= 0 && std::size_t(s.bp_depth) <= s.stack.size())
                    s.stack.resize(std::size_t(s.bp_depth));
                s.half_popped = false;
                return;
            }
            if (width == 2 && n.rm == SP && n.reg == BP) { // MOV BP,SP: a frame's base
                s.bp_depth = int(s.stack.size());
                return set_reg(s, BP, 2, Interval::top());
            }
            set_reg(s, n.reg, width, get_reg(s, n.rm, width));
            if (width == 2) {
                s.reg_is_flags[n.reg] = s.reg_is_flags[n.rm];
                s.reg_flags[n.reg] = s.reg_flags[n.rm];
            }
        } else {
            set_reg(s, n.reg, width, Interval{0, mask_of(width), false});
        }
        return;
    }
    if (op == 0x8C) {
        if (n.mod == 3) set_reg(s, n.rm, 2, Interval::top());
        return;
    }
    if (op == 0x8D || op == 0xC4 || op == 0xC5) return set_reg(s, n.reg, 2, Interval::top());
    if (op == 0x8F) {
        pop(s);
        if (n.mod == 3) set_reg(s, n.rm, 2, Interval::top());
        return;
    }
    if (op >= 0x91 && op <= 0x97) {
        const Interval a = s.reg[AX];
        set_reg(s, AX, 2, s.reg[op & 7]);
        return set_reg(s, op & 7, 2, a);
    }
    if (op == 0x98) {
        const Interval al = get_reg(s, 0, 1);
        return set_reg(s, AX, 2, al.hi < 0x80 ? al : Interval::top());
    }
    if (op == 0x99) return set_reg(s, DX, 2, s.reg[AX].hi < 0x8000 ? Interval::constant(0) : Interval::top());
    if (op == 0x9C) return push(s, StackWord{Interval::top(), true, s.if_flag});
    if (op == 0x9D) {
        const StackWord w = pop(s);
        if (w.flags) s.if_flag = w.if_saved;
        else if (s.if_flag != IfState::startup) s.if_flag = IfState::unknown; // a FLAGS image we did not see saved
        return;
    }
    if (op == 0x9F) return set_reg(s, 4, 1, Interval{0, 0xFF, false});
    if (op == 0xA0 || op == 0xA1) return set_reg(s, 0, width, Interval{0, mask_of(width), false});
    if (op >= 0xA4 && op <= 0xAF) {
        set_reg(s, 6, 2, Interval::top());
        set_reg(s, 7, 2, Interval::top());
        if (op == 0xAC || op == 0xAD) set_reg(s, 0, width, Interval{0, mask_of(width), false});
        if (n.rep) set_reg(s, CX, 2, Interval{0, s.reg[CX].hi, false});
        return;
    }
    if (op >= 0xB0 && op <= 0xB7) return set_reg(s, op & 7, 1, Interval::constant(n.imm & 0xFF));
    if (op >= 0xB8 && op <= 0xBF) return set_reg(s, op & 7, 2, Interval::constant(n.imm));
    if (op == 0xC6 || op == 0xC7) {
        if (n.mod == 3) set_reg(s, n.rm, width, Interval::constant(n.imm));
        return;
    }
    if (op >= 0xD0 && op <= 0xD3) {
        if (n.mod != 3) return;
        const Interval v = get_reg(s, n.rm, width);
        const std::uint32_t m = mask_of(width);
        if (op <= 0xD1 && n.reg == 4 && v.hi * 2 <= m) return set_reg(s, n.rm, width, {v.lo * 2, v.hi * 2, true});
        if (op <= 0xD1 && n.reg == 5) return set_reg(s, n.rm, width, {v.lo / 2, v.hi / 2, false});
        return set_reg(s, n.rm, width, Interval{0, m, false});
    }
    if (op == 0xD4 || op == 0xD5 || op == 0xD7) return set_reg(s, AX, 2, Interval::top());
    if (op == 0xE4 || op == 0xEC) return set_reg(s, 0, 1, Interval{0, 0xFF, false});
    if (op == 0xE5 || op == 0xED) return set_reg(s, AX, 2, Interval::top());
    if (op == 0xE6 || op == 0xEE) { // OUT: an OCW2 EOI (D4 D3 = 00, EOI bit set) to the 8259A
        const Interval port = op == 0xE6 ? Interval::constant(n.imm) : s.reg[DX];
        const Interval al = get_reg(s, 0, 1);
        if (port.is_constant() && port.lo == pic_port && al.is_constant() && (al.lo & 0x18) == 0 && (al.lo & 0x20))
            s.eoi = Eoi::yes;
        return;
    }
    if (op == 0xF6 || op == 0xF7) {
        if (n.reg < 2) return;
        if (n.reg < 4) {
            if (n.mod == 3) set_reg(s, n.rm, width, Interval{0, mask_of(width), false});
            return;
        }
        set_reg(s, AX, 2, Interval::top());
        if (op == 0xF7) set_reg(s, DX, 2, Interval::top());
        return;
    }
    if (op == 0xFA) {
        if (s.if_flag != IfState::startup) s.if_flag = IfState::off;
        return;
    }
    if (op == 0xFB) {
        s.if_flag = IfState::on;
        return;
    }
    if (op == 0xFE || op == 0xFF) {
        const unsigned w = op == 0xFF ? 2 : 1;
        if (op == 0xFF && n.reg == 6) return push(s, {});
        if (n.reg > 1 || n.mod != 3) return;
        Interval v = get_reg(s, n.rm, w);
        const std::uint32_t m = mask_of(w);
        if (n.reg == 0) v = v.hi < m ? Interval{v.lo + 1, v.hi + 1, false} : Interval{0, m, false};
        else v = v.lo > 0 ? Interval{v.lo - 1, v.hi - 1, false} : Interval{0, m, false};
        set_reg(s, n.rm, w, v);
        return note_cmp(reg_index(n.rm, w), 0, true);
    }
    // Flags, HLT, WAIT, ESC, segment moves, stores: no general register changes. Anything else
    // this list does not know changes everything it might.
    static const std::uint8_t kNoRegs[] = {0x26, 0x2E, 0x36, 0x3E, 0x8E, 0x90, 0x9B, 0x9E, 0xA2, 0xA3, 0xF4, 0xF5,
                                           0xF8, 0xF9, 0xFC, 0xFD, 0xD8, 0xD9, 0xDA, 0xDB, 0xDC, 0xDD, 0xDE, 0xDF};
    if (std::find(std::begin(kNoRegs), std::end(kNoRegs), op) == std::end(kNoRegs)) clobber_all(s);
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
    return hex(address);
}

void FlowGraph::fail(std::uint32_t address, const std::string& why) const {
    throw ConfigError("bound: " + entry_name_ + ": " + why + " at " + where(address) + " (" + hex(address) + ")");
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
                edges.push_back({to, EdgeKind::next});
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
            if (l - cs_base > 0xFFFF) fail(i.address, "annotated target " + hex(l) + " is outside this code segment");
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
                    fail(i.address, "a jump table entry at " + hex(at) + " outside the ROM");
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
