// rcsim — what an instruction states about the registers, the stack and IF: the abstract values
// the control flow carries (scenarios/bound/flow.h). See semantics.h.
#include "scenarios/bound/semantics.h"

#include <algorithm>
#include <cstdlib>

namespace rcsim::bound {
namespace {

constexpr int AX = 0, CX = 1, DX = 2, SP = 4, BP = 5;
constexpr std::size_t kMaxStack = 256; // abstract stack words kept (the oldest are dropped)

} // namespace

// ---- intervals ------------------------------------------------------------------------------

Interval join(const Interval& a, const Interval& b) {
    return {std::min(a.lo, b.lo), std::max(a.hi, b.hi), a.even && b.even};
}

static Interval byte_of(const Interval& w, bool high) {
    if (high) return {w.lo >> 8, w.hi >> 8, w.is_constant() && ((w.lo >> 8) & 1) == 0};
    if ((w.lo >> 8) == (w.hi >> 8)) return {w.lo & 0xFF, w.hi & 0xFF, w.even};
    return {0, 0xFF, w.even};
}

static std::uint32_t mask_of(unsigned width) { return width == 2 ? 0xFFFF : 0xFF; }

static std::uint32_t all_ones_over(std::uint32_t v) {
    std::uint32_t m = 0;
    while (m < v) m = m * 2 + 1;
    return m;
}

/// The ALU's result interval for op (the 80 /op numbering: ADD OR ADC SBB AND SUB XOR CMP).
static Interval alu(unsigned op, const Interval& d, const Interval& s, unsigned width) {
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
static void set_writer(State& s, unsigned r, unsigned width, int who) {
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

static void clobber_all(State& s) {
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

namespace {

void note_cmp(State& s, int reg, std::uint32_t value, bool zero_only) {
    s.cmp_reg = reg;
    s.cmp_value = value;
    s.cmp_zero_only = zero_only;
}

int reg_index(unsigned r, unsigned w) { return w == 2 ? int(r) : int(r) + 8; } // bytes 8..15

/// The arithmetic and logic forms: ALU, INC/DEC r16: false when `n` is not one of them.
bool alu_forms(const Insn& n, State& s) {
    const std::uint8_t op = n.opcode;
    const unsigned width = (op & 1) ? 2 : 1;
    if (op < 0x40 && (op & 7) < 4) { // ALU r/m,reg or reg,r/m
        const unsigned alu_op = op >> 3;
        const bool to_reg = op & 2;
        if (n.mod == 3) {
            const unsigned d = to_reg ? n.reg : n.rm, src = to_reg ? n.rm : n.reg;
            if ((alu_op == 6 || alu_op == 5) && n.reg == n.rm) { // XOR r,r / SUB r,r
                set_reg(s, d, width, Interval::constant(0));
                return true;
            }
            if (alu_op == 0 && n.reg == n.rm) { // ADD r,r: doubles, and the result is even
                const Interval v = get_reg(s, d, width);
                set_reg(s, d, width, v.hi * 2 <= mask_of(width) ? Interval{v.lo * 2, v.hi * 2, true}
                                                                 : Interval{0, mask_of(width) - 1, true});
                return true;
            }
            if ((alu_op == 1 || alu_op == 4) && n.reg == n.rm) { // OR r,r / AND r,r: flags only
                note_cmp(s, reg_index(d, width), 0, true);
                return true;
            }
            if (alu_op == 7) return true;
            set_reg(s, d, width, alu(alu_op, get_reg(s, d, width), get_reg(s, src, width), width));
        } else if (to_reg && alu_op != 7) {
            set_reg(s, n.reg, width, Interval{0, mask_of(width), false});
        }
        return true;
    }
    if (op < 0x40 && ((op & 7) == 4 || (op & 7) == 5)) { // ALU AL/AX,imm
        const unsigned alu_op = op >> 3;
        if (alu_op == 7) { note_cmp(s, reg_index(0, width), n.imm, false); return true; }
        set_reg(s, 0, width, alu(alu_op, get_reg(s, 0, width), Interval::constant(n.imm), width));
        return true;
    }
    if (op < 0x40 && (op & 7) == 7) { set_reg(s, AX, 2, Interval::top()); return true; }
    if (op >= 0x40 && op <= 0x4F) { // INC/DEC r16
        const unsigned r = op & 7;
        if (r == SP) { // INC SP twice pops a word, DEC SP twice pushes one (bcc drops arguments so)
            if (s.half_popped) {
                s.half_popped = false;
                op < 0x48 ? (void)pop(s) : push(s, {});
            } else {
                s.half_popped = true;
            }
            return true;
        }
        Interval v = s.reg[r];
        if (op < 0x48) v = v.hi < 0xFFFF ? Interval{v.lo + 1, v.hi + 1, false} : Interval::top();
        else v = v.lo > 0 ? Interval{v.lo - 1, v.hi - 1, false} : Interval::top();
        set_reg(s, r, 2, v);
        note_cmp(s, int(r), 0, true);
        return true;
    }
    return false;
}

/// PUSH and POP of registers and segments: false when `n` is not one of them.
bool stack_forms(const Insn& n, State& s) {
    const std::uint8_t op = n.opcode;
    if (op >= 0x50 && op <= 0x57) {
        const unsigned r = op & 7;
        StackWord w{s.reg[r], s.reg_is_flags[r], s.reg_flags[r], r == BP ? s.bp_depth : -1, {-1, -1}};
        w.writer[0] = r < 4 ? s.writer[r] : s.writer[r + 4];
        w.writer[1] = r < 4 ? s.writer[r + 4] : s.writer[r + 4];
        push(s, w);
        return true;
    }
    if (op >= 0x58 && op <= 0x5F) {
        const StackWord w = pop(s);
        const unsigned r = op & 7;
        if (r == SP) return true;
        if (r == BP) s.bp_depth = w.bp_depth;
        set_reg(s, r, 2, w.value);
        s.reg_is_flags[r] = w.flags;
        s.reg_flags[r] = w.if_saved;
        if (r < 4) s.writer[r] = w.writer[0], s.writer[r + 4] = w.writer[1];
        else s.writer[r + 4] = w.writer[0];
        return true;
    }
    if (op == 0x06 || op == 0x0E || op == 0x16 || op == 0x1E) { push(s, {}); return true; }
    if (op == 0x07 || op == 0x17 || op == 0x1F) { (void)pop(s); return true; }
    return false;
}

/// ALU r/m,imm and TEST: false when `n` is not one of them.
bool immediate_forms(const Insn& n, State& s) {
    const std::uint8_t op = n.opcode;
    const unsigned width = (op & 1) ? 2 : 1;
    if (op >= 0x80 && op <= 0x83) {
        const unsigned w = (op == 0x81 || op == 0x83) ? 2 : 1;
        if (n.mod != 3) return true;
        if (n.reg == 7) { note_cmp(s, reg_index(n.rm, w), n.imm, false); return true; }
        if (n.rm == SP && w == 2 && (n.reg == 0 || n.reg == 5)) { // ADD/SUB SP,imm: words popped/pushed
            const int delta = std::int16_t(n.imm) * (n.reg == 0 ? 1 : -1); // bcc writes ADD SP,-6
            for (int i = 0; i < std::abs(delta) / 2; ++i) delta > 0 ? (void)pop(s) : push(s, {});
            return true;
        }
        set_reg(s, n.rm, w, alu(n.reg, get_reg(s, n.rm, w), Interval::constant(n.imm), w));
        return true;
    }
    if (op == 0x84 || op == 0x85) {
        if (n.mod == 3 && n.reg == n.rm) note_cmp(s, reg_index(n.rm, width), 0, true);
        return true;
    }
    return false;
}

/// Moves, exchanges, PUSHF/POPF, string instructions, loads of constants: false when `n` is not one of them.
bool move_forms(const Insn& n, State& s) {
    const std::uint8_t op = n.opcode;
    const unsigned width = (op & 1) ? 2 : 1;
    if (op == 0x86 || op == 0x87) {
        if (n.mod != 3) { set_reg(s, n.reg, width, Interval{0, mask_of(width), false}); return true; }
        const Interval a = get_reg(s, n.reg, width), b = get_reg(s, n.rm, width);
        set_reg(s, n.reg, width, b);
        set_reg(s, n.rm, width, a);
        return true;
    }
    if (op == 0x88 || op == 0x89) {
        if (n.mod == 3) set_reg(s, n.rm, width, get_reg(s, n.reg, width));
        return true;
    }
    if (op == 0x8A || op == 0x8B) {
        if (n.mod == 3) {
            if (width == 2 && n.reg == SP) { // MOV SP,BP: back to the frame's base
                if (n.rm == BP && s.bp_depth >= 0 && std::size_t(s.bp_depth) <= s.stack.size())
                    s.stack.resize(std::size_t(s.bp_depth));
                s.half_popped = false;
                return true;
            }
            if (width == 2 && n.rm == SP && n.reg == BP) { // MOV BP,SP: a frame's base
                s.bp_depth = int(s.stack.size());
                set_reg(s, BP, 2, Interval::top());
                return true;
            }
            set_reg(s, n.reg, width, get_reg(s, n.rm, width));
            if (width == 2) {
                s.reg_is_flags[n.reg] = s.reg_is_flags[n.rm];
                s.reg_flags[n.reg] = s.reg_flags[n.rm];
            }
        } else {
            set_reg(s, n.reg, width, Interval{0, mask_of(width), false});
        }
        return true;
    }
    if (op == 0x8C) {
        if (n.mod == 3) set_reg(s, n.rm, 2, Interval::top());
        return true;
    }
    if (op == 0x8D || op == 0xC4 || op == 0xC5) { set_reg(s, n.reg, 2, Interval::top()); return true; }
    if (op == 0x8F) {
        pop(s);
        if (n.mod == 3) set_reg(s, n.rm, 2, Interval::top());
        return true;
    }
    if (op >= 0x91 && op <= 0x97) {
        const Interval a = s.reg[AX];
        set_reg(s, AX, 2, s.reg[op & 7]);
        set_reg(s, op & 7, 2, a);
        return true;
    }
    if (op == 0x98) {
        const Interval al = get_reg(s, 0, 1);
        set_reg(s, AX, 2, al.hi < 0x80 ? al : Interval::top());
        return true;
    }
    if (op == 0x99) { set_reg(s, DX, 2, s.reg[AX].hi < 0x8000 ? Interval::constant(0) : Interval::top()); return true; }
    if (op == 0x9C) { push(s, StackWord{Interval::top(), true, s.if_flag}); return true; }
    if (op == 0x9D) {
        const StackWord w = pop(s);
        if (w.flags) s.if_flag = w.if_saved;
        else if (s.if_flag != IfState::startup) s.if_flag = IfState::unknown; // a FLAGS image we did not see saved
        return true;
    }
    if (op == 0x9F) { set_reg(s, 4, 1, Interval{0, 0xFF, false}); return true; }
    if (op == 0xA0 || op == 0xA1) { set_reg(s, 0, width, Interval{0, mask_of(width), false}); return true; }
    if (op >= 0xA4 && op <= 0xAF) {
        set_reg(s, 6, 2, Interval::top());
        set_reg(s, 7, 2, Interval::top());
        if (op == 0xAC || op == 0xAD) set_reg(s, 0, width, Interval{0, mask_of(width), false});
        if (n.rep) set_reg(s, CX, 2, Interval{0, s.reg[CX].hi, false});
        return true;
    }
    if (op >= 0xB0 && op <= 0xB7) { set_reg(s, op & 7, 1, Interval::constant(n.imm & 0xFF)); return true; }
    if (op >= 0xB8 && op <= 0xBF) { set_reg(s, op & 7, 2, Interval::constant(n.imm)); return true; }
    if (op == 0xC6 || op == 0xC7) {
        if (n.mod == 3) set_reg(s, n.rm, width, Interval::constant(n.imm));
        return true;
    }
    return false;
}

/// Shifts, AAM/AAD/XLAT, IN/OUT (the EOI), group 3, CLI/STI: false when `n` is not one of them.
bool other_forms(const Insn& n, State& s, std::uint8_t pic_port) {
    const std::uint8_t op = n.opcode;
    const unsigned width = (op & 1) ? 2 : 1;
    if (op >= 0xD0 && op <= 0xD3) {
        if (n.mod != 3) return true;
        const Interval v = get_reg(s, n.rm, width);
        const std::uint32_t m = mask_of(width);
        if (op <= 0xD1 && n.reg == 4 && v.hi * 2 <= m) { set_reg(s, n.rm, width, {v.lo * 2, v.hi * 2, true}); return true; }
        if (op <= 0xD1 && n.reg == 5) { set_reg(s, n.rm, width, {v.lo / 2, v.hi / 2, false}); return true; }
        { set_reg(s, n.rm, width, Interval{0, m, false}); return true; }
    }
    if (op == 0xD4 || op == 0xD5 || op == 0xD7) { set_reg(s, AX, 2, Interval::top()); return true; }
    if (op == 0xE4 || op == 0xEC) { set_reg(s, 0, 1, Interval{0, 0xFF, false}); return true; }
    if (op == 0xE5 || op == 0xED) { set_reg(s, AX, 2, Interval::top()); return true; }
    if (op == 0xE6 || op == 0xEE) { // OUT: an OCW2 EOI (D4 D3 = 00, EOI bit set) to the 8259A
        const Interval port = op == 0xE6 ? Interval::constant(n.imm) : s.reg[DX];
        const Interval al = get_reg(s, 0, 1);
        if (port.is_constant() && port.lo == pic_port && al.is_constant() && (al.lo & 0x18) == 0 && (al.lo & 0x20))
            s.eoi = Eoi::yes;
        return true;
    }
    if (op == 0xF6 || op == 0xF7) {
        if (n.reg < 2) return true;
        if (n.reg < 4) {
            if (n.mod == 3) set_reg(s, n.rm, width, Interval{0, mask_of(width), false});
            return true;
        }
        set_reg(s, AX, 2, Interval::top());
        if (op == 0xF7) set_reg(s, DX, 2, Interval::top());
        return true;
    }
    if (op == 0xFA) {
        if (s.if_flag != IfState::startup) s.if_flag = IfState::off;
        return true;
    }
    if (op == 0xFB) {
        s.if_flag = IfState::on;
        return true;
    }
    return false;
}

/// INC/DEC r/m and PUSH r/m (groups FE, FF): false when `n` is not one of them.
bool group_fe_ff(const Insn& n, State& s) {
    const std::uint8_t op = n.opcode;
    if (op == 0xFE || op == 0xFF) {
        const unsigned w = op == 0xFF ? 2 : 1;
        if (op == 0xFF && n.reg == 6) { push(s, {}); return true; }
        if (n.reg > 1 || n.mod != 3) return true;
        Interval v = get_reg(s, n.rm, w);
        const std::uint32_t m = mask_of(w);
        if (n.reg == 0) v = v.hi < m ? Interval{v.lo + 1, v.hi + 1, false} : Interval{0, m, false};
        else v = v.lo > 0 ? Interval{v.lo - 1, v.hi - 1, false} : Interval{0, m, false};
        set_reg(s, n.rm, w, v);
        note_cmp(s, reg_index(n.rm, w), 0, true);
        return true;
    }
    return false;
}
} // namespace

/// What an instruction that is not a transfer of control does to the state.
void execute(const Insn& n, State& s, std::uint8_t pic_port) {
    s.cmp_reg = -1;
    s.cmp_zero_only = false;
    if (alu_forms(n, s) || stack_forms(n, s) || immediate_forms(n, s) || move_forms(n, s) ||
        other_forms(n, s, pic_port) || group_fe_ff(n, s))
        return;
    // Flags, HLT, WAIT, ESC, segment moves, stores: no general register changes. Anything else
    // this list does not know changes everything it might.
    static const std::uint8_t kNoRegs[] = {0x26, 0x2E, 0x36, 0x3E, 0x8E, 0x90, 0x9B, 0x9E, 0xA2, 0xA3, 0xF4, 0xF5,
                                           0xF8, 0xF9, 0xFC, 0xFD, 0xD8, 0xD9, 0xDA, 0xDB, 0xDC, 0xDD, 0xDE, 0xDF};
    if (std::find(std::begin(kNoRegs), std::end(kNoRegs), n.opcode) == std::end(kNoRegs)) clobber_all(s);
}


} // namespace rcsim::bound
