// rcsim — the 8086 instruction decoder for people and for analyses: from an instruction's bytes
// alone, its length, its mnemonic, what it does to the flow of control and where a direct transfer
// goes. The core executes
// without it (execution decodes as the microcode does, byte by byte from the queue); the
// latency causes, the cycle profiler and the static bound read the firmware through it.
//
// Every opcode the 8086 executes is decoded, the undocumented aliases included (60-6F as 70-7F,
// C0/C1 as C2/C3, C8/C9 as CA/CB, F1 as the LOCK prefix): lengths are checked against the
// hardware-captured SingleStepTests vectors (tests/comm_cpu/i8086/disasm_test.cpp).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace rcsim::i8086 {

/// The longest 8086 instruction without prefixes: opcode, ModR/M, 16-bit displacement, 16-bit
/// immediate. Prefixes can precede it without limit (the 8086 has no 15-byte rule).
constexpr unsigned kLongestInstruction = 6;

/// Whether `b` is a prefix byte: a segment override, LOCK (F0 and its alias F1), REP/REPNE.
constexpr bool is_prefix(std::uint8_t b) {
    return (b & 0xE7) == 0x26 || b == 0xF0 || b == 0xF1 || b == 0xF2 || b == 0xF3;
}

/// What an instruction does to the flow of control.
enum class Flow : std::uint8_t {
    next,      ///< falls through to the next instruction
    jump,      ///< JMP within the segment: EB, E9, FF/4
    jump_far,  ///< JMP to another segment: EA, FF/5
    branch,    ///< taken or not: Jcc (70-7F and the aliases 60-6F), LOOP/LOOPE/LOOPNE, JCXZ
    call_near, ///< E8, FF/2
    call_far,  ///< 9A, FF/3
    ret_near,  ///< C2, C3 (and the aliases C0, C1)
    ret_far,   ///< CA, CB (and the aliases C8, C9)
    iret,      ///< CF
    int_sw,    ///< INT3, INT n, INTO
    halt,      ///< HLT
};

/// One instruction as its bytes give it.
struct Decoded {
    unsigned prefixes = 0;   ///< prefix bytes before the opcode
    unsigned length = 0;     ///< bytes in all, prefixes included; 0 when the bytes given end inside it
    std::uint8_t opcode = 0; ///< the byte after the prefixes
    Flow flow = Flow::next;
};

/// Decodes the instruction that starts at `b` (`n` bytes readable).
Decoded decode(const std::uint8_t* b, unsigned n);

/// Where a direct transfer of control goes: a near one's offset in its own segment, a far one's
/// segment and offset.
struct Target {
    bool far = false;
    std::uint16_t cs = 0; ///< far only
    std::uint16_t ip = 0;
};

/// The target written in the instruction `d` decoded at `b`, which starts at offset `ip` of its
/// segment: JMP rel8/rel16, Jcc (and its aliases), LOOP/LOOPE/LOOPNE/JCXZ and CALL rel16 go to the
/// offset after the whole instruction (prefixes included) plus the displacement, modulo 64 KB;
/// JMP/CALL ptr16:16 to the pointer. None for a transfer through a register or memory (FF /2../5),
/// returns, IRET, INT, and every instruction that falls through, or whose bytes ended early.
std::optional<Target> direct_target(const std::uint8_t* b, const Decoded& d, std::uint16_t ip);

/// The mnemonic of the instruction at `b`, prefixes included ("REP MOVSB", "CS: MOV", "INT 21h"),
/// without its operands; "opcode D6h" for an opcode it does not name. It is the text report.json
/// gives a latency cause's instruction (docs/scenarios.md), so its spelling is part of the report.
std::string mnemonic(const std::uint8_t* b, unsigned n);

} // namespace rcsim::i8086
