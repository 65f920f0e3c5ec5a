// rcsim — Intel 8086 execution unit: data moves, the stack, I/O and the string instructions.
//
// MOV in all forms (88-8C, 8E, A0-A3, B0-BF, C6, C7), XCHG (86, 87, 90-97), LEA (8D), LDS/LES
// (C4, C5), XLAT (D7), CBW/CWD (98, 99), LAHF/SAHF (9F, 9E); PUSH/POP of registers, segment
// registers, r/m and FLAGS (06/07.., 50-5F, 8F, FF /6 /7, 9C, 9D); IN/OUT (E4-E7, EC-EF); MOVS,
// CMPS, STOS, LODS, SCAS with REP (A4-AF).
//
// Timing: the internal clocks between the bus cycles are the named microcode steps of
// microcode.h, as measured on the captured P80C86A-2 (SingleStepTests 8086 v1, level 3
// exact; MOVS has no v1 file and keeps an estimate). A memory operand that is read comes through
// EALOAD (kEaLoadReturn after its read), one that is only written through EADONE (kEaDone).
#include "comm_cpu/i8086/cpu.h"
#include "comm_cpu/i8086/microcode.h"

namespace rcsim::i8086 {

// MOV, XCHG, LEA, LDS/LES, XLAT and the accumulator forms.
void Cpu::exec_move(std::uint8_t op) {
    const bool mem = mod_ != 3;
    switch (op) {
    case 0x86:
    case 0x87: { // XCHG r/m,reg: 0A4-0A5; on memory after EALOAD, then 0A6 (WB,NX), 0A7 (tmpa -> M)
        const bool word = op & 1;
        const std::uint16_t a = word ? rm_read16() : rm_read8();
        clks(mem ? kEaLoadReturn + kXchgLoad + kWriteBackTest + kResultToM : kXchgLoad);
        if (word) {
            rm_write16(r_.r[reg_]);
            r_.r[reg_] = a;
        } else {
            rm_write8(reg8(reg_));
            set_reg8(reg_, std::uint8_t(a));
        }
        break;
    }
    // MOV r/m,reg to memory: EADONE, 000 (WB,NX), 001 (tmpb -> M); from memory: EALOAD's
    // return (000-001 run with the next opcode read); MOV r/m,sreg: EADONE, 0EC (R -> M).
    case 0x88: if (mem) clks(kEaDone + kWriteBackTest + kResultToM); rm_write8(reg8(reg_)); break;
    case 0x89: if (mem) clks(kEaDone + kWriteBackTest + kResultToM); rm_write16(r_.r[reg_]); break;
    case 0x8A: set_reg8(reg_, rm_read8()); if (mem) clks(kEaLoadReturn); break;
    case 0x8B: r_.r[reg_] = rm_read16(); if (mem) clks(kEaLoadReturn); break;
    case 0x8C: if (mem) clks(kEaDone + kResultToM); rm_write16(r_.s[reg_ & 3]); break;
    case 0x8D: r_.r[reg_] = ea_; clks(kEaDone); break; // LEA: EADONE, then 004 (IND -> R) with RNI
    case 0x8E:
        // Only two bits of reg select the segment register; MOV CS works on the 8086. The next
        // instruction runs before an interrupt is recognised.
        r_.s[reg_ & 3] = rm_read16();
        if (mem) clks(kEaLoadReturn);
        inhibit_ = true;
        break;
    case 0x90: case 0x91: case 0x92: case 0x93: case 0x94: case 0x95: case 0x96: case 0x97: {
        const std::uint16_t t = r_.r[AX];
        r_.r[AX] = r_.r[op & 7];
        r_.r[op & 7] = t;
        clks(kXchgAxLoad);
        break;
    }
    case 0x98: r_.r[AX] = std::uint16_t(std::int8_t(reg8(0))); break; // CBW
    case 0x99: // CWD: a negative AX takes 05A's jump (to ONES -> DE)
        r_.r[DX] = (r_.r[AX] & 0x8000) ? 0xFFFF : 0;
        clks((r_.r[AX] & 0x8000) ? kCwdTest + kJump : kCwdTest);
        break;
    case 0x9E: r_.flags = std::uint16_t((r_.flags & 0xFF00) | (reg8(4) & 0xD5) | 0x02); clks(kSahfLoad); break; // SAHF
    case 0x9F: set_reg8(4, std::uint8_t(r_.flags)); break;                                              // LAHF
    // MOV acc,moffs / moffs,acc: the address is the immediate; a read is requested with it (062),
    // a write after 066 (tmpb -> IND).
    case 0xA0: { const std::uint16_t a = imm16(); set_reg8(0, read8(data_seg(DS), a)); break; }
    case 0xA1: { const std::uint16_t a = imm16(); r_.r[AX] = read16(data_seg(DS), a); break; }
    case 0xA2: { const std::uint16_t a = imm16(); clk(kAddrToInd); write8(data_seg(DS), a, reg8(0), true); break; }
    case 0xA3: { const std::uint16_t a = imm16(); clk(kAddrToInd); write16(data_seg(DS), a, r_.r[AX], true); break; }
    case 0xB0: case 0xB1: case 0xB2: case 0xB3: case 0xB4: case 0xB5: case 0xB6: case 0xB7:
        set_reg8(op & 7, imm8());
        clk(kJump); // 01C's L8 jump over the high byte's line
        break;
    case 0xB8: case 0xB9: case 0xBA: case 0xBB: case 0xBC: case 0xBD: case 0xBE: case 0xBF:
        r_.r[op & 7] = imm16();
        break;
    case 0xC4:
    case 0xC5: { // LES/LDS: offset, EALOAD's return, 0F0 (OPR -> R), 0F1 (INC2), segment
        const std::uint16_t off = read16(ea_seg_, ea_);
        clks(kEaLoadReturn + kLdsOffset + kFarPtrSegAddr);
        const std::uint16_t seg = read16(ea_seg_, std::uint16_t(ea_ + 2));
        r_.r[reg_] = off;
        r_.s[op == 0xC4 ? ES : DS] = seg;
        break;
    }
    case 0xC6: // MOV r/m,imm (reg is ignored by the 8086): EADONE, the immediate (014-015), then
               // 014's L8 jump for a byte (a register operand too) and 016 (tmpb -> M)
        if (!mem) {
            set_reg8(rm_, imm8());
            clk(kJump);
        } else {
            clks(kEaDone);
            const std::uint8_t v = imm8();
            clks(kJump + kResultToM);
            write8(ea_seg_, ea_, v, true);
        }
        break;
    case 0xC7:
        if (!mem) {
            r_.r[rm_] = imm16();
        } else {
            clks(kEaDone);
            const std::uint16_t v = imm16();
            clks(kResultToM);
            write16(ea_seg_, ea_, v, true);
        }
        break;
    default: // D7 XLAT: 10C-10E form BX + AL
        clks(kXlatAddr);
        set_reg8(0, read8(data_seg(DS), std::uint16_t(r_.r[BX] + reg8(0))));
        break;
    }
}

// PUSH/POP: registers, segment registers, r/m (8F, FF /6 /7), FLAGS.
void Cpu::exec_stack(std::uint8_t op) {
    switch (op) {
    case 0x06: case 0x0E: case 0x16: case 0x1E:
        clks(kPushSetup);
        push(r_.s[(op >> 3) & 3], true);
        break;
    case 0x07: case 0x0F: case 0x17: case 0x1F:
        // POP CS (0F) loads CS without flushing the queue, as the 8086 does. Any segment
        // register load delays interrupt recognition by one instruction.
        r_.s[(op >> 3) & 3] = pop();
        inhibit_ = true;
        break;
    case 0x50: case 0x51: case 0x52: case 0x53: case 0x54: case 0x55: case 0x56: case 0x57:
        clks(kPushSetup);
        // PUSH SP stores the decremented value on the 8086.
        r_.r[SP] = std::uint16_t(r_.r[SP] - 2);
        write16(SS, r_.r[SP], r_.r[op & 7], true);
        break;
    case 0x58: case 0x59: case 0x5A: case 0x5B: case 0x5C: case 0x5D: case 0x5E: case 0x5F:
        r_.r[op & 7] = pop();
        break;
    case 0x8F: { // POP r/m: a memory operand's EADONE, 040, the stack read, 042, 043-044 (memory)
        const bool mem = mod_ != 3;
        if (mem) clks(kEaDone);
        clk(kPopRmStart);
        const std::uint16_t v = pop();
        clk(kPopRmSp);
        if (mem) clks(kPopRmToMem);
        rm_write16(v);
        break;
    }
    case 0x9C: clks(kPushSetup); push(r_.flags, true); break;
    case 0x9D: { // POPF
        const bool was = get_flag(flag::IF);
        r_.flags = std::uint16_t((pop() & 0x0FD5) | 0xF002);
        if (was != get_flag(flag::IF)) note_if(!was, IfChange::How::instruction, op);
        break;
    }
    default: { // FE/FF /6 /7: PUSH r/m (8-bit forms push 0xFF in the high byte)
        const bool word = op & 1;
        const std::uint16_t v = word ? rm_read16() : std::uint16_t(0xFF00 | rm_read8());
        clks(mod_ == 3 ? kRegOperand + kPushSetup : kEaLoadReturn + kPushSetup); // 024-026
        r_.r[SP] = std::uint16_t(r_.r[SP] - 2);
        // PUSH SP through r/m pushes the decremented value as well.
        write16(SS, r_.r[SP], (mod_ == 3 && rm_ == SP) ? r_.r[SP] : v, true);
        break;
    }
    }
}

// IN/OUT with an immediate port (E4-E7: the port byte, widened (0AD / 0B1); OUT moves it into
// IND on a line of its own (0B2)) or DX (EC-EF: IN requests with 0B4, OUT after 0B8).
void Cpu::exec_io(std::uint8_t op) {
    const bool word = op & 1;
    const bool output = op & 2;
    std::uint16_t port = r_.r[DX];
    if (op < 0xE8) {
        port = imm8();
        clks(output ? kPortWiden + kAddrToInd : kPortWiden);
    } else if (output) {
        clks(kAddrToInd);
    }
    if (output) out(port, word ? r_.r[AX] : reg8(0), word, true);
    else if (word) r_.r[AX] = in(port, true);
    else set_reg8(0, std::uint8_t(in(port, false)));
}

// One element of a string instruction, `last` when no REP run follows it. Element timings
// measured on the P80C86A-2 (clocks from the end of the previous step; a read returns in its T4
// clock, a write that is not the last one too).
void Cpu::string_element(std::uint8_t op, bool last) {
    const bool word = op & 1;
    const std::uint16_t step = get_flag(flag::DF) ? std::uint16_t(word ? -2 : -1) : std::uint16_t(word ? 2 : 1);
    const int src_seg = data_seg(DS);
    // (always_inline: inlined alike in the profile-generating copy of the core; pgo/README.md)
    auto load = [&](int seg, std::uint16_t off) __attribute__((always_inline)) -> std::uint16_t {
        return word ? read16(seg, off) : read8(seg, off);
    };
    switch (op) {
    case 0xA4:
    case 0xA5: { // MOVS (no v1 captures: an estimate; no clock for 12C before the read)
        const std::uint16_t v = load(src_seg, r_.r[SI]);
        clks(kMovsStep);
        if (word) write16(ES, r_.r[DI], v, last);
        else write8(ES, r_.r[DI], std::uint8_t(v), last);
        r_.r[SI] += step;
        r_.r[DI] += step;
        break;
    }
    case 0xA6:
    case 0xA7: { // CMPS: 120-121, read DS:SI, 123-124, read ES:DI, 126-128
        clks(kRptsTest + kCmpsScasSelect);
        const std::uint16_t a = load(src_seg, r_.r[SI]);
        clks(kCmpsKeepFirst);
        const std::uint16_t b = load(ES, r_.r[DI]);
        clks(kStrCompare);
        alu(7, a, b, word);
        r_.r[SI] += step;
        r_.r[DI] += step;
        break;
    }
    case 0xAA:
    case 0xAB: // STOS: 11C, the write (11D), 11E
        clks(kRptsTest);
        if (word) write16(ES, r_.r[DI], r_.r[AX], false);
        else write8(ES, r_.r[DI], reg8(0), false);
        clks(kStosStep);
        r_.r[DI] += step;
        break;
    case 0xAC:
    case 0xAD: { // LODS: 12C, the read (12D), 12E and its jump to 1F8
        clks(kRptsTest);
        const std::uint16_t v = load(src_seg, r_.r[SI]);
        if (word) r_.r[AX] = v;
        else set_reg8(0, std::uint8_t(v));
        r_.r[SI] += step;
        clks(kLodsStep);
        break;
    }
    default: { // SCAS: 120-121 and 121's jump to 125, read ES:DI, 126-128
        clks(kRptsTest + kCmpsScasSelect + kJump);
        const std::uint16_t b = load(ES, r_.r[DI]);
        clks(kStrCompare);
        alu(7, word ? r_.r[AX] : reg8(0), b, word);
        r_.r[DI] += step;
        break;
    }
    }
}

// A string instruction, with its REP run. REP timings measured on the P80C86A-2, named after
// RPTS and the routines' loop lines: the entry into RPTS (CX tested in the fifth clock), its
// return to the first element, an overhead between elements when the run goes on, and the
// end of the run (the same overhead, or a compare's F1ZZ jump).
void Cpu::exec_string(std::uint8_t op) {
    if (!rep_) {
        string_element(op, true);
        return;
    }
    const bool compare = op == 0xA6 || op == 0xA7 || op == 0xAE || op == 0xAF;
    const bool lods = op == 0xAC || op == 0xAD;
    const bool stos = op == 0xAA || op == 0xAB;
    // per element when the run goes on (LODS: 1F8's F1 jump to 131 first)
    const unsigned overhead = lods ? kJump + kRepNext : stos ? kRepNextStos : kRepNext;
    bool first = !rep_suspended_;
    clks(first ? kRepStart : overhead); // resuming a parked run: the overhead of the element boundary
    rep_suspended_ = false;
    for (;;) {
        if (r_.r[CX] == 0) {
            clks(kRptsCxTest);
            return;
        }
        if (first) clks(kRptsToElement);
        first = false;
        string_element(op, false);
        r_.r[CX] = std::uint16_t(r_.r[CX] - 1);
        if (compare && (get_flag(flag::ZF) != (rep_ == 0xF3))) {
            clk(kJump); // REPE/REPNE: the compare ended the run (129's F1ZZ jump to 1F4)
            return;
        }
        if (r_.r[CX] == 0) {
            clks(overhead);
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

} // namespace rcsim::i8086
