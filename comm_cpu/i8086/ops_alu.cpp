// rcsim — Intel 8086 execution unit: the ALU instruction group.
//
// ADD/OR/ADC/SBB/AND/SUB/XOR/CMP in every form (00-3D, 80-83), TEST (84, 85, A8, A9, F6/F7 /0
// /1), NOT/NEG (F6/F7 /2 /3), INC/DEC (40-4F, FE/FF /0 /1), the shifts and rotates (D0-D3) and
// the BCD adjustments (27, 2F, 37, 3F). ModR/M and EA are decoded before these run (step()).
//
// Timing: the operand read and the write-back are bus cycles (rm_read*/rm_write*: the EU's
// request goes to the BIU); the internal clocks between them are the named microcode steps of
// microcode.h, as measured on the captured P80C86A-2 (SingleStepTests 8086 v1, level 3
// exact). A memory r/m operand is read by EALOAD, whose return (kEaLoadReturn) comes first. A
// write-back to memory is the instruction's last bus cycle, overlapped with the next opcode
// read (RNI).
#include "comm_cpu/i8086/cpu.h"
#include "comm_cpu/i8086/microcode.h"

namespace rcsim::i8086 {

// ALU r/m,reg (d=0), reg,r/m (d=1), acc,imm (04/05 forms): op = 8 * operation + form.
void Cpu::exec_alu(std::uint8_t op) {
    const unsigned f = op >> 3; // 0 ADD, 1 OR, 2 ADC, 3 SBB, 4 AND, 5 SUB, 6 XOR, 7 CMP
    const bool compare = f == 7;
    const bool mem = mod_ != 3;
    // 008 (XI) on the operands; a memory destination then takes 009 (WB,NX) and 00A (SIGMA -> M)
    // before the write, a register one gets the result with the next opcode read.
    switch (op & 7) {
    case 0: { // op r/m8, reg8
        const std::uint8_t r = std::uint8_t(alu(f, rm_read8(), reg8(reg_), false));
        clks(mem ? kEaLoadReturn + kAluXi + (compare ? 0 : kWriteBackTest + kResultToM) : kAluXi);
        if (!compare) rm_write8(r);
        break;
    }
    case 1: { // op r/m16, reg16
        const std::uint16_t r = alu(f, rm_read16(), r_.r[reg_], true);
        clks(mem ? kEaLoadReturn + kAluXi + (compare ? 0 : kWriteBackTest + kResultToM) : kAluXi);
        if (!compare) rm_write16(r);
        break;
    }
    case 2: { // op reg8, r/m8
        const std::uint8_t b = rm_read8();
        const std::uint8_t r = std::uint8_t(alu(f, reg8(reg_), b, false));
        clks(mem ? kEaLoadReturn + kAluXi : kAluXi);
        if (!compare) set_reg8(reg_, r);
        break;
    }
    case 3: { // op reg16, r/m16
        const std::uint16_t b = rm_read16();
        const std::uint16_t r = alu(f, r_.r[reg_], b, true);
        clks(mem ? kEaLoadReturn + kAluXi : kAluXi);
        if (!compare) r_.r[reg_] = r;
        break;
    }
    case 4: { // op AL, imm8: 018's L8 jumps over the high byte's line (01A runs with RNI)
        const std::uint8_t r = std::uint8_t(alu(f, reg8(0), imm8(), false));
        clks(kJump);
        if (!compare) set_reg8(0, r);
        break;
    }
    default: { // op AX, imm16: the ALU works while the second immediate byte is read
        const std::uint16_t r = alu(f, r_.r[AX], imm16(), true);
        if (!compare) r_.r[AX] = r;
        break;
    }
    }
}

// Group 1 (80-83): op r/m, imm (82 = 80; 83 sign-extends an 8-bit immediate).
void Cpu::exec_alu_imm(std::uint8_t op) {
    const bool word = op & 1;
    const unsigned f = reg_;
    const bool compare = f == 7;
    const bool mem = mod_ != 3;
    const bool imm_word = op == 0x81;
    const std::uint16_t a = word ? rm_read16() : rm_read8();
    if (mem) clks(kEaLoadReturn);
    const std::uint16_t b = imm_word ? imm16() : word ? std::uint16_t(std::int8_t(imm8())) : imm8();
    const std::uint16_t r = alu(f, a, b, word);
    // 00C's L8 jump over the high byte's line (an 8-bit immediate, 83 too); on memory 00E (XI)
    // and, unless CMP, 00F (SIGMA -> M); on a register 00E runs with the next opcode read.
    const unsigned imm_clock = imm_word ? 0 : kJump;
    clks(mem ? imm_clock + kAluXi + (compare ? 0 : kResultToM) : imm_clock);
    if (compare) return;
    if (word) rm_write16(r);
    else rm_write8(std::uint8_t(r));
}

// TEST r/m,reg (84, 85), TEST acc,imm (A8, A9): AND without the write-back.
void Cpu::exec_test(std::uint8_t op) {
    switch (op) {
    case 0x84: alu(4, rm_read8(), reg8(reg_), false); clks(mod_ == 3 ? kAluXi : kEaLoadReturn + kAluXi); break;
    case 0x85: alu(4, rm_read16(), r_.r[reg_], true); clks(mod_ == 3 ? kAluXi : kEaLoadReturn + kAluXi); break;
    case 0xA8: alu(4, reg8(0), imm8(), false); clks(kJump); break; // 09C's L8 jump (09E with RNI)
    default: alu(4, r_.r[AX], imm16(), true); break; // A9: as op AX,imm16
    }
}

// INC/DEC r16 (40-4F): CF is kept.
void Cpu::exec_incdec_r16(std::uint8_t op) {
    const bool cf = get_flag(flag::CF);
    r_.r[op & 7] = alu(op & 8 ? 5 : 0, r_.r[op & 7], 1, true);
    set_flag(flag::CF, cf);
}

// Group 3 /0-/3 (F6/F7): TEST r/m,imm (/1 aliases /0), NOT, NEG. /4-/7 are MUL/IMUL/DIV/IDIV.
void Cpu::exec_group3(std::uint8_t op) {
    const bool word = op & 1;
    const bool mem = mod_ != 3;
    switch (reg_) {
    case 0:
    case 1: {
        // The immediate (098-099) follows EALOAD's return (kRegOperand on a register); then
        // 098's L8 jump for a byte immediate and, on memory, 09A (AND; on a register it runs
        // with the next opcode read).
        const std::uint16_t a = word ? rm_read16() : rm_read8();
        clks(mem ? kEaLoadReturn : kRegOperand);
        alu(4, a, word ? imm16() : imm8(), word);
        clks(mem ? (word ? kAluXi : kJump + kAluXi) : (word ? 0 : kJump));
        break;
    }
    case 2:
    case 3: {
        const std::uint16_t a = word ? rm_read16() : rm_read8();
        const std::uint16_t r = reg_ == 2 ? std::uint16_t(~a) : alu(5, 0, a, word);
        clks(mem ? kEaLoadReturn + kAluXi + kResultToM : kAluXi); // 04C/050, 04D/051
        if (word) rm_write16(r);
        else rm_write8(std::uint8_t(r));
        break;
    }
    case 4:
    case 5: multiply(word, reg_ == 5); break;
    default: divide(word, reg_ == 7); break;
    }
}

// INC/DEC r/m (FE/FF /0 /1): CF is kept.
void Cpu::exec_incdec_rm(std::uint8_t op) {
    const bool word = op & 1;
    const bool cf = get_flag(flag::CF);
    const std::uint16_t a = word ? rm_read16() : rm_read8();
    const std::uint16_t r = alu(reg_ ? 5 : 0, a, 1, word);
    set_flag(flag::CF, cf);
    clks(mod_ == 3 ? kAluXi : kEaLoadReturn + kAluXi + kResultToM); // 020, 021
    if (word) rm_write16(r);
    else rm_write8(std::uint8_t(r));
}

// Shifts and rotates (D0-D3): by one (D0, D1) or by CL (D2, D3); /6 is SETMO/SETMOC.
void Cpu::exec_shift(std::uint8_t op) {
    const bool word = op & 1;
    const bool by_cl = op & 2;
    const bool mem = mod_ != 3;
    const unsigned count = by_cl ? reg8(1) : 1;
    const std::uint16_t v = word ? rm_read16() : rm_read8();
    if (by_cl) clks(kShiftClSetup + kShiftClPerBit * count);
    const std::uint16_t r = shift(reg_, v, count, word);
    // The loop's exit (by one: 088, XI; on a register it runs with the next opcode read); on
    // memory EALOAD's return is spent here, after the loop, and 092 / 089 puts the result into M.
    clks(mem ? (by_cl ? kEaLoadReturn + kShiftClExit + kResultToM : kEaLoadReturn + kAluXi + kResultToM)
             : (by_cl ? kShiftClExit : 0));
    if (word) rm_write16(r);
    else rm_write8(std::uint8_t(r));
}

// DAA/DAS (27, 2F), AAA/AAS (37, 3F). AAM/AAD are in muldiv.cpp.
void Cpu::exec_bcd(std::uint8_t op) {
    const std::uint8_t al = reg8(0);
    if (op == 0x27 || op == 0x2F) {
        const bool cf = get_flag(flag::CF), af = get_flag(flag::AF);
        const bool sub = op == 0x2F;
        std::uint8_t v = al;
        bool new_af = false, new_cf = false;
        if ((al & 0x0F) > 9 || af) {
            v = std::uint8_t(sub ? v - 6 : v + 6);
            new_af = true;
        }
        // The 8086 compares with 0x9F instead of 0x99 when AF was set (captured behaviour).
        if (al > (af ? 0x9F : 0x99) || cf) {
            v = std::uint8_t(sub ? v - 0x60 : v + 0x60);
            new_cf = true;
        }
        set_reg8(0, v);
        set_szp(v, false);
        set_flag(flag::AF, new_af);
        set_flag(flag::CF, new_cf);
        clks(kDaaSetup);
        return;
    }
    const bool adj = (al & 0x0F) > 9 || get_flag(flag::AF);
    if (adj) {
        const bool add = op == 0x37;
        set_reg8(0, std::uint8_t(add ? al + 6 : al - 6));
        set_reg8(4, std::uint8_t(add ? reg8(4) + 1 : reg8(4) - 1));
    }
    set_flag(flag::AF, adj);
    set_flag(flag::CF, adj);
    set_szp(reg8(0), false);
    set_reg8(0, reg8(0) & 0x0F);
    clks(adj ? kAaaTest : kAaaTest + kJump); // no adjustment: 14D's jump over 14E
}

} // namespace rcsim::i8086
