// rcsim — Intel 8086 execution unit: the opcode table.
//
// Documentation: iAPX 86/88 User's Manual (Intel 210201) instruction set; undocumented forms
// as captured on a P80C86A-2 (SingleStepTests 8086 v1). The ModR/M byte and effective address
// are already decoded (step()) when execute() runs; each case spends the remaining clocks.
#include "comm_cpu/i8086.h"

namespace rcsim::i8086 {
// One string element; returns false when a REPE/REPNE compare ends the run.
void Cpu::string_op(std::uint8_t op) {
    const bool word = op & 1;
    const std::uint16_t step = get_flag(flag::DF) ? std::uint16_t(word ? -2 : -1) : std::uint16_t(word ? 2 : 1);
    const int src_seg = data_seg(DS);
    // Element timings measured on the P80C86A-2 (clocks counted from the end of the
    // previous step; a read returns in its T4 clock, a write that is not the last one too).
    auto one = [&](bool last) -> bool {
        switch (op) {
        case 0xA4:
        case 0xA5: { // MOVS
            // Not covered by the v1 suite (no A4/A5 files): the earlier estimate is kept.
            const std::uint16_t v = word ? read16(src_seg, r_.r[SI]) : read8(src_seg, r_.r[SI]);
            clks(1);
            if (word) write16(ES, r_.r[DI], v, last);
            else write8(ES, r_.r[DI], std::uint8_t(v), last);
            r_.r[SI] += step;
            r_.r[DI] += step;
            return true;
        }
        case 0xA6:
        case 0xA7: { // CMPS
            clks(2);
            const std::uint16_t a = word ? read16(src_seg, r_.r[SI]) : read8(src_seg, r_.r[SI]);
            clks(2);
            const std::uint16_t b = word ? read16(ES, r_.r[DI]) : read8(ES, r_.r[DI]);
            clks(last ? 4 : 4);
            alu(7, a, b, word);
            r_.r[SI] += step;
            r_.r[DI] += step;
            return true;
        }
        case 0xAA:
        case 0xAB: // STOS
            clks(1);
            if (word) write16(ES, r_.r[DI], r_.r[AX], false);
            else write8(ES, r_.r[DI], reg8(0), false);
            clks(last ? 2 : 2);
            r_.r[DI] += step;
            return true;
        case 0xAC:
        case 0xAD: { // LODS
            clks(1);
            const std::uint16_t v = word ? read16(src_seg, r_.r[SI]) : read8(src_seg, r_.r[SI]);
            if (word) r_.r[AX] = v;
            else set_reg8(0, std::uint8_t(v));
            r_.r[SI] += step;
            clks(last ? 3 : 3);
            return true;
        }
        default: { // SCAS
            clks(3);
            const std::uint16_t b = word ? read16(ES, r_.r[DI]) : read8(ES, r_.r[DI]);
            clks(last ? 4 : 4);
            alu(7, word ? r_.r[AX] : reg8(0), b, word);
            r_.r[DI] += step;
            return true;
        }
        }
    };
    const bool compare = op == 0xA6 || op == 0xA7 || op == 0xAE || op == 0xAF;
    if (!rep_) {
        one(true);
        return;
    }
    // REP timings measured on the P80C86A-2: a 4-clock prologue (CX tested in the fifth), a
    // first-element set-up, a per-element loop overhead when the run continues and one clock
    // when it ends.
    const bool lods = op == 0xAC || op == 0xAD;
    const bool stos = op == 0xAA || op == 0xAB;
    const unsigned overhead = lods ? 3 : stos ? 1 : 2; // per element when the run goes on
    const unsigned setup = 3;                           // before the first element
    bool first = !rep_suspended_;
    if (first) clks(4);
    else clks(overhead); // resuming a parked run: the overhead of the element boundary
    rep_suspended_ = false;
    for (;;) {
        if (r_.r[CX] == 0) {
            clks(1);
            return;
        }
        if (first) clks(setup);
        first = false;
        one(false);
        r_.r[CX] = std::uint16_t(r_.r[CX] - 1);
        if (compare && (get_flag(flag::ZF) != (rep_ == 0xF3))) {
            clk();
            return;
        }
        if (r_.r[CX] == 0) {
            clks(stos ? 1 : lods ? 3 : 2);
            return;
        }
        // Interruptible between elements: IP goes back to the last prefix, so only that
        // prefix is seen again when the handler returns (the 8086 multiple-prefix bug).
        if (nmi_pending_ || (intr_ && get_flag(flag::IF))) {
            r_.ip = std::uint16_t(r_.ip - 2);
            rep_interrupted_ = true;
            return;
        }
        if (cycle_ >= limit_) {
            // End of a run slice: park between elements; step() resumes here.
            rep_suspended_ = true;
            return;
        }
        clks(overhead);
    }
}

void Cpu::execute(std::uint8_t op) {
    switch (op) {
    // ---- ALU r/m, reg / reg, r/m / acc, imm ----
    case 0x00: case 0x08: case 0x10: case 0x18: case 0x20: case 0x28: case 0x30: case 0x38: {
        const unsigned f = op >> 3;
        const std::uint8_t a = rm_read8();
        const std::uint8_t r = std::uint8_t(alu(f, a, reg8(reg_), false));
        if (mod_ == 3) {
            clks(1);
            if (f != 7) rm_write8(r);
        } else {
            clks(f == 7 ? 3 : 5);
            if (f != 7) rm_write8(r);
        }
        break;
    }
    case 0x01: case 0x09: case 0x11: case 0x19: case 0x21: case 0x29: case 0x31: case 0x39: {
        const unsigned f = op >> 3;
        const std::uint16_t a = rm_read16();
        const std::uint16_t r = alu(f, a, r_.r[reg_], true);
        if (mod_ == 3) {
            clks(1);
            if (f != 7) rm_write16(r);
        } else {
            clks(f == 7 ? 3 : 5);
            if (f != 7) rm_write16(r);
        }
        break;
    }
    case 0x02: case 0x0A: case 0x12: case 0x1A: case 0x22: case 0x2A: case 0x32: case 0x3A: {
        const unsigned f = op >> 3;
        const std::uint8_t b = rm_read8();
        const std::uint8_t r = std::uint8_t(alu(f, reg8(reg_), b, false));
        clks(mod_ == 3 ? 1 : 3);
        if (f != 7) set_reg8(reg_, r);
        break;
    }
    case 0x03: case 0x0B: case 0x13: case 0x1B: case 0x23: case 0x2B: case 0x33: case 0x3B: {
        const unsigned f = op >> 3;
        const std::uint16_t b = rm_read16();
        const std::uint16_t r = alu(f, r_.r[reg_], b, true);
        clks(mod_ == 3 ? 1 : 3);
        if (f != 7) r_.r[reg_] = r;
        break;
    }
    case 0x04: case 0x0C: case 0x14: case 0x1C: case 0x24: case 0x2C: case 0x34: case 0x3C: {
        const unsigned f = op >> 3;
        const std::uint8_t r = std::uint8_t(alu(f, reg8(0), imm8(), false));
        clk();
        if (f != 7) set_reg8(0, r);
        break;
    }
    case 0x05: case 0x0D: case 0x15: case 0x1D: case 0x25: case 0x2D: case 0x35: case 0x3D: {
        const unsigned f = op >> 3;
        const std::uint16_t r = alu(f, r_.r[AX], imm16(), true);
        if (f != 7) r_.r[AX] = r;
        break;
    }

    // ---- segment push/pop ----
    case 0x06: case 0x0E: case 0x16: case 0x1E:
        clks(3);
        push(r_.s[(op >> 3) & 3], true);
        break;
    case 0x07: case 0x0F: case 0x17: case 0x1F:
        // POP CS (0F) loads CS without flushing the queue, as the 8086 does.
        r_.s[(op >> 3) & 3] = pop();
        inhibit_ = true;
        break;

    // ---- BCD ----
    case 0x27: case 0x2F: { // DAA / DAS
        const std::uint8_t al = reg8(0);
        const bool cf = get_flag(flag::CF), af = get_flag(flag::AF);
        std::uint8_t v = al;
        const bool sub = op == 0x2F;
        bool new_af = false, new_cf = false;
        if ((al & 0x0F) > 9 || af) {
            v = std::uint8_t(sub ? v - 6 : v + 6);
            new_af = true;
        }
        if (al > (af ? 0x9F : 0x99) || cf) {
            v = std::uint8_t(sub ? v - 0x60 : v + 0x60);
            new_cf = true;
        }
        set_reg8(0, v);
        set_szp(v, false);
        set_flag(flag::AF, new_af);
        set_flag(flag::CF, new_cf);
        clks(2);
        break;
    }
    case 0x37: case 0x3F: { // AAA / AAS
        const std::uint8_t al = reg8(0);
        const bool adj = (al & 0x0F) > 9 || get_flag(flag::AF);
        if (adj) {
            if (op == 0x37) {
                set_reg8(0, std::uint8_t(al + 6));
                set_reg8(4, std::uint8_t(reg8(4) + 1));
            } else {
                set_reg8(0, std::uint8_t(al - 6));
                set_reg8(4, std::uint8_t(reg8(4) - 1));
            }
        }
        set_flag(flag::AF, adj);
        set_flag(flag::CF, adj);
        set_szp(reg8(0), false);
        set_reg8(0, reg8(0) & 0x0F);
        clks(adj ? 6 : 7);
        break;
    }

    // ---- INC/DEC/PUSH/POP r16 ----
    case 0x40: case 0x41: case 0x42: case 0x43: case 0x44: case 0x45: case 0x46: case 0x47:
    case 0x48: case 0x49: case 0x4A: case 0x4B: case 0x4C: case 0x4D: case 0x4E: case 0x4F: {
        const bool cf = get_flag(flag::CF);
        r_.r[op & 7] = alu(op & 8 ? 5 : 0, r_.r[op & 7], 1, true);
        set_flag(flag::CF, cf);
        break;
    }
    case 0x50: case 0x51: case 0x52: case 0x53: case 0x54: case 0x55: case 0x56: case 0x57:
        clks(3);
        // PUSH SP stores the decremented value on the 8086.
        r_.r[SP] = std::uint16_t(r_.r[SP] - 2);
        write16(SS, r_.r[SP], r_.r[op & 7], true);
        break;
    case 0x58: case 0x59: case 0x5A: case 0x5B: case 0x5C: case 0x5D: case 0x5E: case 0x5F:
        r_.r[op & 7] = pop();
        break;

    // ---- conditional jumps (60-6F alias 70-7F on the 8086) ----
    case 0x60: case 0x61: case 0x62: case 0x63: case 0x64: case 0x65: case 0x66: case 0x67:
    case 0x68: case 0x69: case 0x6A: case 0x6B: case 0x6C: case 0x6D: case 0x6E: case 0x6F:
    case 0x70: case 0x71: case 0x72: case 0x73: case 0x74: case 0x75: case 0x76: case 0x77:
    case 0x78: case 0x79: case 0x7A: case 0x7B: case 0x7C: case 0x7D: case 0x7E: case 0x7F: {
        const std::int8_t d = std::int8_t(imm8());
        clk();
        if (condition(op & 0x0F)) {
            clk();
            reljmp(std::uint16_t(r_.ip + d));
        }
        break;
    }

    // ---- group 1: ALU r/m, imm ----
    case 0x80: case 0x81: case 0x82: case 0x83: {
        const bool word = op & 1;
        const unsigned f = reg_;
        const bool mem = mod_ != 3;
        if (!word) {
            const std::uint8_t a = rm_read8();
            if (mem) clks(2); // the immediate is read two clocks after the operand's T4
            const std::uint8_t b = imm8();
            const std::uint8_t r = std::uint8_t(alu(f, a, b, false));
            clks(!mem ? 1 : (f == 7 ? 2 : 3));
            if (f != 7) rm_write8(r);
        } else {
            const std::uint16_t a = rm_read16();
            if (mem) clks(2);
            const bool imm_word = op == 0x81;
            const std::uint16_t b = imm_word ? imm16() : std::uint16_t(std::int8_t(imm8()));
            const std::uint16_t r = alu(f, a, b, true);
            clks(!mem ? (imm_word ? 0 : 1) : (f == 7 ? (imm_word ? 1 : 2) : (imm_word ? 2 : 3)));
            if (f != 7) rm_write16(r);
        }
        break;
    }
    case 0x84: {
        alu(4, rm_read8(), reg8(reg_), false);
        clks(mod_ == 3 ? 1 : 3);
        break;
    }
    case 0x85: {
        alu(4, rm_read16(), r_.r[reg_], true);
        clks(mod_ == 3 ? 1 : 3);
        break;
    }
    case 0x86: {
        const std::uint8_t a = rm_read8();
        clks(mod_ == 3 ? 2 : 6);
        rm_write8(reg8(reg_));
        set_reg8(reg_, a);
        break;
    }
    case 0x87: {
        const std::uint16_t a = rm_read16();
        clks(mod_ == 3 ? 2 : 6);
        rm_write16(r_.r[reg_]);
        r_.r[reg_] = a;
        break;
    }
    case 0x88:
        if (mod_ != 3) clks(4);
        rm_write8(reg8(reg_));
        break;
    case 0x89:
        if (mod_ != 3) clks(4);
        rm_write16(r_.r[reg_]);
        break;
    case 0x8A:
        set_reg8(reg_, rm_read8());
        if (mod_ != 3) clks(2);
        break;
    case 0x8B:
        r_.r[reg_] = rm_read16();
        if (mod_ != 3) clks(2);
        break;
    case 0x8C:
        if (mod_ != 3) clks(3);
        rm_write16(r_.s[reg_ & 3]);
        break;
    case 0x8D:
        r_.r[reg_] = ea_;
        clks(2);
        break;
    case 0x8E:
        // Only two bits of reg select the segment register; MOV CS works on the 8086.
        r_.s[reg_ & 3] = rm_read16();
        if (mod_ != 3) clks(2);
        inhibit_ = true;
        break;
    case 0x8F: {
        const std::uint16_t v = pop();
        clks(1);
        rm_write16(v);
        break;
    }

    // ---- XCHG AX, r16 / CBW / CWD / flags ----
    case 0x90: case 0x91: case 0x92: case 0x93: case 0x94: case 0x95: case 0x96: case 0x97: {
        const std::uint16_t t = r_.r[AX];
        r_.r[AX] = r_.r[op & 7];
        r_.r[op & 7] = t;
        clks(1);
        break;
    }
    case 0x98:
        r_.r[AX] = std::uint16_t(std::int8_t(reg8(0)));
        break;
    case 0x99:
        r_.r[DX] = (r_.r[AX] & 0x8000) ? 0xFFFF : 0;
        clks((r_.r[AX] & 0x8000) ? 4 : 3);
        break;
    case 0x9A: {
        const std::uint16_t ip = imm16();
        const std::uint16_t cs = imm16();
        clk();
        susp();
        clks(2);
        call_far(cs, ip);
        break;
    }
    case 0x9B: // WAIT: TEST# is held active on this board, so it falls through
        clks(3);
        break;
    case 0x9C:
        clks(3);
        push(r_.flags, true);
        break;
    case 0x9D:
        r_.flags = std::uint16_t((pop() & 0x0FD5) | 0xF002);
        break;
    case 0x9E:
        r_.flags = std::uint16_t((r_.flags & 0xFF00) | (reg8(4) & 0xD5) | 0x02);
        clks(2);
        break;
    case 0x9F:
        set_reg8(4, std::uint8_t(r_.flags));
        break;

    // ---- MOV acc, moffs ----
    case 0xA0: { const std::uint16_t a = imm16(); set_reg8(0, read8(data_seg(DS), a)); break; }
    case 0xA1: { const std::uint16_t a = imm16(); r_.r[AX] = read16(data_seg(DS), a); break; }
    case 0xA2: { const std::uint16_t a = imm16(); clk(); write8(data_seg(DS), a, reg8(0), true); break; }
    case 0xA3: { const std::uint16_t a = imm16(); clk(); write16(data_seg(DS), a, r_.r[AX], true); break; }

    case 0xA4: case 0xA5: case 0xA6: case 0xA7: case 0xAA: case 0xAB: case 0xAC: case 0xAD: case 0xAE:
    case 0xAF:
        string_op(op);
        break;
    case 0xA8:
        alu(4, reg8(0), imm8(), false);
        clk();
        break;
    case 0xA9:
        alu(4, r_.r[AX], imm16(), true);
        break;

    case 0xB0: case 0xB1: case 0xB2: case 0xB3: case 0xB4: case 0xB5: case 0xB6: case 0xB7:
        set_reg8(op & 7, imm8());
        clk();
        break;
    case 0xB8: case 0xB9: case 0xBA: case 0xBB: case 0xBC: case 0xBD: case 0xBE: case 0xBF:
        r_.r[op & 7] = imm16();
        break;

    // ---- returns (C0/C1 alias C2/C3, C8/C9 alias CA/CB) ----
    case 0xC0: case 0xC2: case 0xC8: case 0xCA: {
        const std::uint16_t n = imm16();
        clks(1);
        const std::uint16_t ip = pop();
        suspend_fetch();
        std::uint16_t cs = r_.s[CS];
        if (op & 8) {
            clks(3);
            cs = pop();
        }
        r_.r[SP] = std::uint16_t(r_.r[SP] + n);
        clks((op & 8) ? 0 : 2);
        jump_far(cs, ip);
        clks(2);
        break;
    }
    case 0xC1: case 0xC3: case 0xC9: case 0xCB: {
        if (op & 8) { // RETF: prefetching goes on until IP has been read
            clks(2);
            const std::uint16_t ip = pop();
            suspend_fetch();
            clks(3);
            const std::uint16_t cs = pop();
            jump_far(cs, ip);
        } else {
            suspend_fetch();
            const std::uint16_t ip = pop();
            clk();
            jump_near(ip);
        }
        clks(2);
        break;
    }
    case 0xC4: case 0xC5: {
        const std::uint16_t off = read16(ea_seg_, ea_);
        clks(4);
        const std::uint16_t seg = read16(ea_seg_, std::uint16_t(ea_ + 2));
        r_.r[reg_] = off;
        r_.s[op == 0xC4 ? ES : DS] = seg;
        break;
    }
    case 0xC6:
        // reg is ignored by the 8086.
        if (mod_ == 3) set_reg8(rm_, imm8());
        else {
            clks(2);
            const std::uint8_t v = imm8();
            clks(2);
            write8(ea_seg_, ea_, v, true);
        }
        break;
    case 0xC7:
        if (mod_ == 3) r_.r[rm_] = imm16();
        else {
            clks(2);
            const std::uint16_t v = imm16();
            clks(1);
            write16(ea_seg_, ea_, v, true);
        }
        break;

    // ---- interrupts ----
    case 0xCC:
        clks(4);
        interrupt(3);
        break;
    case 0xCD: {
        const std::uint8_t v = imm8();
        clks(2);
        interrupt(v);
        break;
    }
    case 0xCE:
        if (get_flag(flag::OF)) {
            clks(5);
            interrupt(4);
        } else {
            clks(2);
        }
        break;
    case 0xCF: {
        clks(2);
        const std::uint16_t ip = pop();
        suspend_fetch();
        clks(3);
        const std::uint16_t cs = pop();
        jump_far(cs, ip);
        clks(2);
        r_.flags = std::uint16_t((pop() & 0x0FD5) | 0xF002);
        break;
    }

    // ---- shifts ----
    case 0xD0: case 0xD1: case 0xD2: case 0xD3: {
        const bool word = op & 1;
        const unsigned count = (op & 2) ? reg8(1) : 1;
        if (!word) {
            const std::uint8_t v = rm_read8();
            if (op & 2) clks(4 + 4 * count);
            const std::uint8_t r = std::uint8_t(shift(reg_, v, count, false));
            clks(mod_ != 3 ? ((op & 2) ? 5 : 4) : ((op & 2) ? 2 : 0));
            rm_write8(r);
        } else {
            const std::uint16_t v = rm_read16();
            if (op & 2) clks(4 + 4 * count);
            const std::uint16_t r = shift(reg_, v, count, true);
            clks(mod_ != 3 ? ((op & 2) ? 5 : 4) : ((op & 2) ? 2 : 0));
            rm_write16(r);
        }
        break;
    }
    case 0xD4: aam(imm8()); break;
    case 0xD5: aad(imm8()); break;
    case 0xD6: // SALC
        set_reg8(0, get_flag(flag::CF) ? 0xFF : 0x00);
        clks(1);
        break;
    case 0xD7: { // XLAT
        clks(3);
        set_reg8(0, read8(data_seg(DS), std::uint16_t(r_.r[BX] + reg8(0))));
        break;
    }
    case 0xD8: case 0xD9: case 0xDA: case 0xDB: case 0xDC: case 0xDD: case 0xDE: case 0xDF:
        // ESC: no coprocessor; a memory operand is still read.
        if (mod_ != 3) read16(ea_seg_, ea_);
        clks(1);
        break;

    // ---- loops ----
    case 0xE0: case 0xE1: case 0xE2: case 0xE3: {
        bool take;
        clks(2); // CX (- 1) before the displacement is read
        if (op == 0xE3) {
            take = r_.r[CX] == 0;
        } else {
            r_.r[CX] = std::uint16_t(r_.r[CX] - 1);
            take = r_.r[CX] != 0;
            if (op == 0xE0) take = take && !get_flag(flag::ZF);
            if (op == 0xE1) take = take && get_flag(flag::ZF);
        }
        const std::int8_t d = std::int8_t(imm8());
        clk();
        if (take) {
            if (op != 0xE2) clk(); // the extra condition test of LOOPE/LOOPNE/JCXZ
            reljmp(std::uint16_t(r_.ip + d));
        }
        break;
    }
    case 0xE4: { const std::uint8_t p = imm8(); clks(1); set_reg8(0, std::uint8_t(in(p, false))); break; }
    case 0xE5: { const std::uint8_t p = imm8(); clks(1); r_.r[AX] = in(p, true); break; }
    case 0xE6: { const std::uint8_t p = imm8(); clks(2); out(p, reg8(0), false, true); break; }
    case 0xE7: { const std::uint8_t p = imm8(); clks(2); out(p, r_.r[AX], true, true); break; }
    case 0xEC: set_reg8(0, std::uint8_t(in(r_.r[DX], false))); break;
    case 0xED: r_.r[AX] = in(r_.r[DX], true); break;
    case 0xEE: clks(1); out(r_.r[DX], reg8(0), false, true); break;
    case 0xEF: clks(1); out(r_.r[DX], r_.r[AX], true, true); break;

    case 0xE8: {
        const std::uint16_t d = imm16();
        const std::uint16_t ret = r_.ip;
        reljmp(std::uint16_t(r_.ip + d));
        clks(2);
        push(ret, true);
        break;
    }
    case 0xE9: {
        const std::uint16_t d = imm16();
        reljmp(std::uint16_t(r_.ip + d));
        break;
    }
    case 0xEA: {
        const std::uint16_t ip = imm16();
        const std::uint16_t cs = imm16();
        susp();
        clk();
        jump_far(cs, ip);
        clks(1);
        break;
    }
    case 0xEB: {
        const std::int8_t d = std::int8_t(imm8());
        clk();
        reljmp(std::uint16_t(r_.ip + d));
        break;
    }

    // ---- misc ----
    case 0xF4: // HLT
        halted_ = true;
        suspend_fetch();
        clks(1);
        break;
    case 0xF5: set_flag(flag::CF, !get_flag(flag::CF)); break;
    case 0xF8: set_flag(flag::CF, false); break;
    case 0xF9: set_flag(flag::CF, true); break;
    case 0xFA: set_flag(flag::IF, false); break;
    case 0xFB:
        // STI: the next instruction runs before an INTR is recognised.
        if (!get_flag(flag::IF)) inhibit_ = true;
        set_flag(flag::IF, true);
        break;
    case 0xFC: set_flag(flag::DF, false); break;
    case 0xFD: set_flag(flag::DF, true); break;

    case 0xF6: case 0xF7: {
        const bool word = op & 1;
        switch (reg_) {
        case 0:
        case 1:
            if (!word) {
                const std::uint8_t a = rm_read8();
                clks(mod_ != 3 ? 2 : 1);
                alu(4, a, imm8(), false);
            } else {
                const std::uint16_t a = rm_read16();
                clks(mod_ != 3 ? 2 : 1);
                alu(4, a, imm16(), true);
            }
            clks(mod_ != 3 ? (word ? 1 : 2) : (word ? 0 : 1));
            break;
        case 2:
            if (!word) { const std::uint8_t a = rm_read8(); clks(mod_ == 3 ? 1 : 4); rm_write8(std::uint8_t(~a)); }
            else { const std::uint16_t a = rm_read16(); clks(mod_ == 3 ? 1 : 4); rm_write16(std::uint16_t(~a)); }
            break;
        case 3:
            if (!word) { const std::uint8_t a = rm_read8(); clks(mod_ == 3 ? 1 : 4); rm_write8(std::uint8_t(alu(5, 0, a, false))); }
            else { const std::uint16_t a = rm_read16(); clks(mod_ == 3 ? 1 : 4); rm_write16(alu(5, 0, a, true)); }
            break;
        default:
            if (reg_ >= 6) divide(word, reg_ == 7);
            else multiply(word, reg_ == 5);
            break;
        }
        break;
    }
    case 0xFE: case 0xFF: {
        const bool word = op & 1;
        switch (reg_) {
        case 0:
        case 1: {
            const bool cf = get_flag(flag::CF);
            if (!word) {
                const std::uint8_t a = rm_read8();
                const std::uint8_t r = std::uint8_t(alu(reg_ ? 5 : 0, a, 1, false));
                set_flag(flag::CF, cf);
                clks(mod_ == 3 ? 1 : 4);
                rm_write8(r);
            } else {
                const std::uint16_t a = rm_read16();
                const std::uint16_t r = alu(reg_ ? 5 : 0, a, 1, true);
                set_flag(flag::CF, cf);
                clks(mod_ == 3 ? 1 : 4);
                rm_write16(r);
            }
            break;
        }
        case 2: { // CALL near r/m
            const std::uint16_t t = word ? rm_read16() : std::uint16_t(0xFF00 | rm_read8());
            if (mod_ == 3) {
                clk();
                susp();
            } else {
                clks(2);
                susp();
            }
            clks(3);
            call_near(t);
            break;
        }
        case 3: { // CALL far m
            const std::uint16_t ip = read16(ea_seg_, ea_);
            clks(3);
            const std::uint16_t cs = read16(ea_seg_, std::uint16_t(ea_ + 2));
            suspend_fetch();
            clks(4);
            call_far(cs, ip);
            break;
        }
        case 4: { // JMP near r/m
            const std::uint16_t t = word ? rm_read16() : std::uint16_t(0xFF00 | rm_read8());
            if (mod_ == 3) {
                clk();
                susp();
            } else {
                clks(2); // a prefetch may still start after the operand read
                susp();
            }
            jump_near(t);
            clks(1);
            break;
        }
        case 5: { // JMP far m
            const std::uint16_t ip = read16(ea_seg_, ea_);
            clks(3);
            susp();
            const std::uint16_t cs = read16(ea_seg_, std::uint16_t(ea_ + 2));
            jump_far(cs, ip);
            clks(1);
            break;
        }
        default: { // PUSH r/m (7 is an alias)
            const std::uint16_t v = word ? rm_read16() : std::uint16_t(0xFF00 | rm_read8());
            clks(mod_ == 3 ? 4 : 5);
            r_.r[SP] = std::uint16_t(r_.r[SP] - 2);
            // PUSH SP through r/m pushes the decremented value as well.
            write16(SS, r_.r[SP], (mod_ == 3 && rm_ == SP) ? r_.r[SP] : v, true);
            break;
        }
        }
        break;
    }
    default:
        // Prefix bytes never reach here (step() consumes them).
        clks(1);
        break;
    }
}

} // namespace rcsim::i8086
