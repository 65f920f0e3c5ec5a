// rcsim — Intel 8086 execution unit: opcode dispatch by instruction group, and the small
// miscellaneous instructions (flag operations, HLT, WAIT, SALC, ESC).
//
// Documentation: iAPX 86/88 User's Manual (Intel 210201) instruction set; undocumented forms
// as captured on a P80C86A-2 (SingleStepTests 8086 v1). The ModR/M byte and effective address
// are already decoded (step()) when execute() runs; each group spends the remaining clocks:
//   ops_alu.cpp      ALU, TEST, INC/DEC, NOT/NEG, shifts, BCD adjustments
//   ops_move.cpp     MOV/XCHG/LEA/LDS/LES/XLAT, PUSH/POP, IN/OUT, string instructions
//   ops_control.cpp  jumps, calls, returns, INT/INTO/IRET
//   muldiv.cpp       MUL/IMUL/DIV/IDIV/AAM/AAD (the CORX/CORD microcode timing)
#include "comm_cpu/i8086/cpu.h"
#include "comm_cpu/i8086/microcode.h"

#include <array>

namespace rcsim::i8086 {
namespace {

enum class Group : std::uint8_t { alu, alu_imm, test, incdec_r16, bcd, shift, group3, group5, move, stack, io,
                                  string, jump, ret, aam, aad, misc };

// (always_inline: inlined alike in the profile-generating copy of the core; pgo/README.md)
[[gnu::always_inline]] constexpr Group group_of(unsigned op) {
    if (op < 0x40) {
        if ((op & 7) == 6 || (op & 7) == 7) {
            if ((op & 0x27) == 0x26) return Group::misc; // segment prefixes (consumed by step())
            if (op >= 0x20) return Group::bcd;           // 27, 2F, 37, 3F
            return Group::stack;                         // PUSH/POP sreg
        }
        return Group::alu;
    }
    if (op < 0x50) return Group::incdec_r16;
    if (op < 0x60) return Group::stack;
    if (op < 0x80) return Group::jump; // 60-6F alias 70-7F on the 8086
    if (op < 0x84) return Group::alu_imm;
    if (op < 0x86) return Group::test;
    if (op == 0x8F || op == 0x9C || op == 0x9D) return Group::stack;
    if (op < 0xA0) return op == 0x9A ? Group::jump : op == 0x9B ? Group::misc : Group::move;
    if (op < 0xA4) return Group::move;
    if (op == 0xA8 || op == 0xA9) return Group::test;
    if (op < 0xB0) return Group::string;
    if (op < 0xC0) return Group::move;
    if (op == 0xC4 || op == 0xC5 || op == 0xC6 || op == 0xC7) return Group::move;
    if (op < 0xD0) return Group::ret;
    if (op < 0xD4) return Group::shift;
    if (op == 0xD4) return Group::aam;
    if (op == 0xD5) return Group::aad;
    if (op == 0xD7) return Group::move; // XLAT
    if (op < 0xE0) return Group::misc;  // SALC, ESC
    if (op < 0xE4 || (op >= 0xE8 && op <= 0xEB)) return Group::jump;
    if (op < 0xF0) return Group::io;
    if (op == 0xF6 || op == 0xF7) return Group::group3;
    if (op == 0xFE || op == 0xFF) return Group::group5;
    return Group::misc;
}

} // namespace

// The handler of every opcode, from its group: execute() is one indirect call.
std::array<Cpu::Handler, 256> Cpu::make_handlers() {
    std::array<Handler, 256> h{};
    for (unsigned op = 0; op < 256; ++op) {
        switch (group_of(op)) {
        case Group::alu: h[op] = &Cpu::exec_alu; break;
        case Group::alu_imm: h[op] = &Cpu::exec_alu_imm; break;
        case Group::test: h[op] = &Cpu::exec_test; break;
        case Group::incdec_r16: h[op] = &Cpu::exec_incdec_r16; break;
        case Group::bcd: h[op] = &Cpu::exec_bcd; break;
        case Group::shift: h[op] = &Cpu::exec_shift; break;
        case Group::group3: h[op] = &Cpu::exec_group3; break;
        case Group::group5: h[op] = &Cpu::exec_group5; break;
        case Group::move: h[op] = &Cpu::exec_move; break;
        case Group::stack: h[op] = &Cpu::exec_stack; break;
        case Group::io: h[op] = &Cpu::exec_io; break;
        case Group::string: h[op] = &Cpu::exec_string; break;
        case Group::jump: h[op] = &Cpu::exec_jump; break;
        case Group::ret: h[op] = &Cpu::exec_return; break;
        case Group::aam: h[op] = &Cpu::exec_aam; break;
        case Group::aad: h[op] = &Cpu::exec_aad; break;
        case Group::misc: h[op] = &Cpu::exec_misc; break;
        }
    }
    return h;
}

const std::array<Cpu::Handler, 256> Cpu::kHandlers = Cpu::make_handlers();

// FE/FF: /0 /1 INC/DEC, /2-/5 CALL/JMP, /6 /7 PUSH (FE /2-/7 as the FF forms).
void Cpu::exec_group5(std::uint8_t op) {
    if (reg_ < 2) exec_incdec_rm(op);
    else if (reg_ < 6) exec_jump_rm(op);
    else exec_stack(op);
}

void Cpu::exec_aam(std::uint8_t) { aam(imm8()); }
void Cpu::exec_aad(std::uint8_t) { aad(imm8()); }

// Flag operations, HLT, WAIT, SALC, ESC.
void Cpu::exec_misc(std::uint8_t op) {
    switch (op) {
    case 0x9B: clks(kWaitTestActive); break; // WAIT: TEST# is held active on this board, so it falls through
    case 0xD6: // SALC
        set_reg8(0, get_flag(flag::CF) ? 0xFF : 0x00);
        clks(get_flag(flag::CF) ? kSalcTest + kJump : kSalcTest);
        break;
    case 0xD8: case 0xD9: case 0xDA: case 0xDB: case 0xDC: case 0xDD: case 0xDE: case 0xDF:
        // ESC: no coprocessor; a memory operand is still read (EALOAD), then the next
        // instruction (MartyPC's 108; a register operand costs nothing more).
        if (mod_ != 3) {
            read16(ea_seg_, ea_);
            clks(kEaLoadReturn);
        }
        break;
    case 0xF4: // HLT: prefetching stops; the EU idles until NMI or an enabled INTR
        halted_ = true;
        suspend_fetch();
        clks(kHaltEnter);
        break;
    case 0xF5: set_flag(flag::CF, !get_flag(flag::CF)); break;
    case 0xF8: set_flag(flag::CF, false); break;
    case 0xF9: set_flag(flag::CF, true); break;
    case 0xFA:
        if (get_flag(flag::IF)) note_if(false, IfChange::How::instruction, op);
        set_flag(flag::IF, false);
        break;
    case 0xFB:
        // STI: the next instruction runs before an INTR is recognised.
        if (!get_flag(flag::IF)) {
            inhibit_ = true;
            note_if(true, IfChange::How::instruction, op);
        }
        set_flag(flag::IF, true);
        break;
    case 0xFC: set_flag(flag::DF, false); break;
    case 0xFD: set_flag(flag::DF, true); break;
    default: clks(kPrefix); break; // prefix bytes never reach here (step() consumes them)
    }
}

} // namespace rcsim::i8086
