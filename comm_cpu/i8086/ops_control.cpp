// rcsim — Intel 8086 execution unit: control transfer.
//
// Jcc (70-7F, 60-6F alias), LOOP/LOOPE/LOOPNE/JCXZ (E0-E3), JMP (E9, EA, EB, FF /4 /5), CALL
// (E8, 9A, FF /2 /3), RET/RETF with and without an immediate (C0-C3, C8-CB), INT 3 / INT n /
// INTO / IRET (CC-CF).
//
// The shared tails are the microcode's: SUSP (susp: prefetching stops, a cycle in progress
// runs to T4), RELJMP (reljmp: SUSP, the addition, the flush), NEARCALL (call_near: the flush,
// then the IP push), FARCALL (call_far: push CS, then NEARCALL), the far return (farret: pop
// IP, SUSP, pop CS, flush). The clocks around them are the named microcode steps of
// microcode.h, as measured on the captured P80C86A-2 (SingleStepTests 8086 v1, level 3
// exact).
#include "comm_cpu/i8086/cpu.h"
#include "comm_cpu/i8086/microcode.h"

namespace rcsim::i8086 {

// FARRET: pops IP (0C2), stops prefetching, 0C3-0C4 and the jump to 0C6, pops CS and jumps
// (RETF, RETF n, IRET).
void Cpu::farret() {
    const std::uint16_t ip = pop();
    suspend_fetch();
    clks(kFarRetSusp + kJump);
    const std::uint16_t cs = pop();
    jump_far(cs, ip);
}

// Short and near relative jumps and calls, Jcc, LOOP/JCXZ, and the far forms with an
// immediate address.
void Cpu::exec_jump(std::uint8_t op) {
    if (op < 0x80) { // Jcc: 0E8 reads the displacement, 0E9 (XC RELJMP) tests the condition
        const std::int8_t d = std::int8_t(imm8());
        clk(kBranchTest);
        if (condition(op & 0x0F)) {
            clk(kJump); // into RELJMP
            reljmp(std::uint16_t(r_.ip + d));
        }
        return;
    }
    switch (op) {
    case 0xE0: case 0xE1: case 0xE2: case 0xE3: { // LOOPNE, LOOPE, LOOP, JCXZ
        clks(kLoopCount); // CX (- 1) before the displacement is read
        bool take;
        if (op == 0xE3) {
            take = r_.r[CX] == 0;
        } else {
            r_.r[CX] = std::uint16_t(r_.r[CX] - 1);
            take = r_.r[CX] != 0;
            if (op == 0xE0) take = take && !get_flag(flag::ZF);
            if (op == 0xE1) take = take && get_flag(flag::ZF);
        }
        const std::int8_t d = std::int8_t(imm8());
        clk(kBranchTest);
        if (take) {
            if (op != 0xE2) clk(kJump); // LOOPE/LOOPNE/JCXZ: 13B / 137 jump into RELJMP
            reljmp(std::uint16_t(r_.ip + d));
        }
        break;
    }
    case 0xE8: { // CALL near: RELJMP's lines at 07E-081, 082 (UNC 7) and its jump, 083 pushes IP
        const std::uint16_t d = imm16();
        const std::uint16_t ret = r_.ip;
        reljmp(std::uint16_t(r_.ip + d));
        clks(kCallRelPush);
        push(ret, true);
        break;
    }
    case 0xE9: {
        const std::uint16_t d = imm16();
        reljmp(std::uint16_t(r_.ip + d));
        break;
    }
    case 0xEB: {
        const std::int8_t d = std::int8_t(imm8());
        clk(kJump); // 0D0's L8 jump over 0D1 into RELJMP
        reljmp(std::uint16_t(r_.ip + d));
        break;
    }
    case 0xEA: { // JMP far: 0E4 (SUSP), 0E5, 0E6 (the flush)
        const std::uint16_t ip = imm16();
        const std::uint16_t cs = imm16();
        susp();
        clk(kJmpFarPc);
        jump_far(cs, ip);
        clks(kFlushLine);
        break;
    }
    default: { // 9A CALL far: 073's jump to FARCALL, 06B (SUSP), 06C (CORR); call_far from 06D
        const std::uint16_t ip = imm16();
        const std::uint16_t cs = imm16();
        clk(kJump);
        susp();
        clks(kCorr);
        call_far(cs, ip);
        break;
    }
    }
}

// Group 5 /2-/5 (FF; FE treated alike): CALL and JMP, near through r/m, far through memory.
void Cpu::exec_jump_rm(std::uint8_t op) {
    const bool word = op & 1;
    const bool mem = mod_ != 3;
    switch (reg_) {
    case 2:
    case 4: { // CALL / JMP near r/m: SUSP (074 / 0D8) after EALOAD's return (or kRegOperand)
        const std::uint16_t t = word ? rm_read16() : std::uint16_t(0xFF00 | rm_read8());
        clks(mem ? kEaLoadReturn : kRegOperand); // a prefetch may still start after the operand read
        susp();
        if (reg_ == 2) {
            clks(kCorr + kCallRetToOpr); // 075 (CORR), 076, then NEARCALL
            call_near(t);
        } else {
            jump_near(t);
            clks(kFlushLine); // 0D9 (M -> PC, FLUSH)
        }
        break;
    }
    case 3: { // CALL far m: offset, EALOAD's return, 068, segment (069); prefetching stops; 06A,
              // 06B (SUSP), 06C (CORR), FARCALL from 06D
        const std::uint16_t ip = read16(ea_seg_, ea_);
        clks(kEaLoadReturn + kFarPtrSegAddr);
        const std::uint16_t cs = read16(ea_seg_, std::uint16_t(ea_ + 2));
        suspend_fetch();
        clks(kCallFarMSeg + kSuspLine + kCorr);
        call_far(cs, ip);
        break;
    }
    default: { // 5: JMP far m: offset, EALOAD's return, 0DC, SUSP (0DD; a prefetch started after
               // the offset read runs to its T4 first), segment (0DE), the flush (0DF)
        const std::uint16_t ip = read16(ea_seg_, ea_);
        clks(kEaLoadReturn + kFarPtrSegAddr);
        susp();
        const std::uint16_t cs = read16(ea_seg_, std::uint16_t(ea_ + 2));
        jump_far(cs, ip);
        clks(kFlushLine);
        break;
    }
    }
}

// RET, RET n, RETF, RETF n (C0/C1 alias C2/C3, C8/C9 alias CA/CB), INT 3, INT n, INTO, IRET.
void Cpu::exec_return(std::uint8_t op) {
    const bool far = op & 8;
    switch (op) {
    case 0xC0: case 0xC2: case 0xC8: case 0xCA: { // RET n / RETF n: release n bytes of arguments
        const std::uint16_t n = imm16();
        clks(kJump); // 0CD's jump into FARRET
        if (far) {
            farret();
        } else {
            const std::uint16_t ip = pop();
            suspend_fetch();
            clks(kFarRetSusp);
            jump_near(ip);
        }
        r_.r[SP] = std::uint16_t(r_.r[SP] + n);
        clks(kFarRetTail);
        break;
    }
    case 0xC1: case 0xC3: case 0xC9: case 0xCB:
        if (far) { // RETF: prefetching goes on until IP has been read
            clks(kFarRetCall);
            farret();
        } else { // RET: IP read (0BC), 0BD (SUSP), the flush (0BE)
            suspend_fetch();
            const std::uint16_t ip = pop();
            clk(kSuspLine);
            jump_near(ip);
        }
        clks(far ? kFarRetTail : kRetTail);
        break;
    case 0xCC: clks(kInt3Skip + kTypeToIntr); interrupt(3); break;
    case 0xCD: { const std::uint8_t v = imm8(); clks(kIntImm); interrupt(v); break; }
    case 0xCE: // INTO: the OF test, then 1AD's jump to 1AF and the type-4 entry
        if (get_flag(flag::OF)) {
            clks(kIntoTest + kJump + kTypeToIntr);
            interrupt(4);
        } else {
            clks(kIntoTest);
        }
        break;
    default: { // CF IRET: the far return, its tail, FLAGS (0C9)
        clks(kFarRetCall);
        farret();
        clks(kFarRetTail);
        const bool was = get_flag(flag::IF);
        r_.flags = std::uint16_t((pop() & 0x0FD5) | 0xF002);
        if (was != get_flag(flag::IF)) note_if(!was, IfChange::How::instruction, op);
        break;
    }
    }
}

} // namespace rcsim::i8086
