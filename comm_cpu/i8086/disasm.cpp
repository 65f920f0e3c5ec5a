// rcsim — the 8086 instruction decoder. See disasm.h.
#include "comm_cpu/i8086/disasm.h"

#include "models/plumbing/hex.h"

namespace rcsim::i8086 {

namespace {

// How an opcode's length is made up after the opcode byte (Intel, iAPX 86/88 User's Manual,
// "Instruction set" encoding tables; the aliases as the SingleStepTests metadata names them).
enum Form : std::uint8_t {
    none,        // the opcode alone
    imm8,        // one byte: an immediate, a short displacement, a port or a type
    imm16,       // two bytes: an immediate, a near displacement or a direct address
    far_ptr,     // four bytes: offset and segment (CALL/JMP far)
    modrm,       // a ModR/M byte and its displacement
    modrm_imm8,  // ... then a byte immediate
    modrm_imm16, // ... then a word immediate
    group3_b,    // F6: ModR/M, and a byte immediate for TEST (/0, /1)
    group3_w,    // F7: ModR/M, and a word immediate for TEST (/0, /1)
    prefix,
};

constexpr Form form_of(std::uint8_t op) {
    if (is_prefix(op)) return prefix;
    if (op < 0x40) { // the eight ALU blocks, each op r/m,r; r,r/m; AL,imm8; AX,imm16; then two others
        switch (op & 7) {
        case 0: case 1: case 2: case 3: return modrm;
        case 4: return imm8;
        case 5: return imm16;
        default: return none; // PUSH/POP segment (0F: POP CS), DAA, DAS, AAA, AAS
        }
    }
    if (op < 0x60) return none;                // INC, DEC, PUSH, POP register
    if (op < 0x80) return imm8;                // Jcc (60-6F: the 8086 decodes them as 70-7F)
    if (op == 0x81) return modrm_imm16;
    if (op < 0x84) return modrm_imm8;          // 80, 82 (alias of 80), 83
    if (op < 0x90) return modrm;               // TEST, XCHG, MOV, LEA, MOV sreg, POP r/m
    if (op == 0x9A) return far_ptr;
    if (op < 0xA0) return none;                // XCHG AX, CBW, CWD, WAIT, PUSHF, POPF, SAHF, LAHF
    if (op < 0xA4) return imm16;               // MOV AL/AX <-> direct address
    if (op == 0xA8) return imm8;
    if (op == 0xA9) return imm16;
    if (op < 0xB0) return none;                // string instructions
    if (op < 0xB8) return imm8;                // MOV r8, imm8
    if (op < 0xC0) return imm16;               // MOV r16, imm16
    switch (op) {
    case 0xC0: case 0xC2: case 0xC8: case 0xCA: return imm16; // RET/RETF imm16 (C0, C8 aliases)
    case 0xC4: case 0xC5: return modrm;                       // LES, LDS
    case 0xC6: return modrm_imm8;
    case 0xC7: return modrm_imm16;
    case 0xCD: return imm8;                                   // INT n
    case 0xD4: case 0xD5: return imm8;                        // AAM, AAD with their base
    case 0xE0: case 0xE1: case 0xE2: case 0xE3: return imm8;  // LOOPNE, LOOPE, LOOP, JCXZ
    case 0xE4: case 0xE5: case 0xE6: case 0xE7: return imm8;  // IN/OUT with a port number
    case 0xE8: case 0xE9: return imm16;                       // CALL, JMP near
    case 0xEA: return far_ptr;
    case 0xEB: return imm8;                                   // JMP short
    case 0xF6: return group3_b;
    case 0xF7: return group3_w;
    case 0xFE: case 0xFF: return modrm;
    default: break;
    }
    if (op >= 0xD0 && op < 0xD4) return modrm;  // shifts and rotates
    if (op >= 0xD8 && op < 0xE0) return modrm;  // ESC
    return none; // C1, C3, C9, CB, CC, CE, CF, D6 (SALC), D7, EC-EF, F4, F5, F8-FD
}

// The ModR/M byte's own length with its displacement: mod 00 has one only for r/m 110 (a direct
// address), mod 01 a byte, mod 10 a word, mod 11 (a register) none.
constexpr unsigned modrm_length(std::uint8_t m) {
    switch (m >> 6) {
    case 0: return (m & 7) == 6 ? 3 : 1;
    case 1: return 2;
    case 2: return 3;
    default: return 1;
    }
}

Flow flow_of(std::uint8_t op, std::uint8_t modrm) {
    if ((op >= 0x60 && op < 0x80) || (op >= 0xE0 && op < 0xE4)) return Flow::branch;
    switch (op) {
    case 0xE9: case 0xEB: return Flow::jump;
    case 0xEA: return Flow::jump_far;
    case 0xE8: return Flow::call_near;
    case 0x9A: return Flow::call_far;
    case 0xC0: case 0xC1: case 0xC2: case 0xC3: return Flow::ret_near;
    case 0xC8: case 0xC9: case 0xCA: case 0xCB: return Flow::ret_far;
    case 0xCF: return Flow::iret;
    case 0xCC: case 0xCD: case 0xCE: return Flow::int_sw;
    case 0xF4: return Flow::halt;
    case 0xFF:
        switch ((modrm >> 3) & 7) {
        case 2: return Flow::call_near;
        case 3: return Flow::call_far;
        case 4: return Flow::jump;
        case 5: return Flow::jump_far;
        default: return Flow::next;
        }
    default: return Flow::next;
    }
}

std::string hex2(unsigned v) { return hex(v & 0xFF, 2); }

// The mnemonic of an opcode without prefixes; `next` is the byte after it (0 when there is none).
std::string opcode_mnemonic(std::uint8_t op, bool has_next, std::uint8_t next) {
    static const char* const alu[] = {"ADD", "OR", "ADC", "SBB", "AND", "SUB", "XOR", "CMP"};
    static const char* const shifts[] = {"ROL", "ROR", "RCL", "RCR", "SHL", "SHR", "SETMO", "SAR"};
    static const char* const group3[] = {"TEST", "TEST", "NOT", "NEG", "MUL", "IMUL", "DIV", "IDIV"};
    static const char* const group5[] = {"INC", "DEC", "CALL", "CALL FAR", "JMP", "JMP FAR", "PUSH", "PUSH"};
    const unsigned reg = (next >> 3) & 7;
    if (op < 0x40 && (op & 7) < 6) return alu[op >> 3];
    if (op >= 0x40 && op < 0x48) return "INC";
    if (op >= 0x48 && op < 0x50) return "DEC";
    if (op >= 0x50 && op < 0x58) return "PUSH";
    if (op >= 0x58 && op < 0x60) return "POP";
    if (op >= 0x60 && op < 0x80) return "Jcc";
    if (op >= 0x80 && op < 0x84) return alu[reg];
    if ((op >= 0x88 && op < 0x8D) || (op >= 0xB0 && op < 0xC0)) return "MOV";
    if (op >= 0xD0 && op < 0xD4) return shifts[reg];
    if (op >= 0xD8 && op < 0xE0) return "ESC";
    if (op == 0xF6 || op == 0xF7) return group3[reg];
    if (op == 0xFE || op == 0xFF) return group5[reg];
    switch (op) {
    case 0x27: return "DAA";
    case 0x2F: return "DAS";
    case 0x37: return "AAA";
    case 0x3F: return "AAS";
    case 0x84: case 0x85: case 0xA8: case 0xA9: return "TEST";
    case 0x86: case 0x87: return "XCHG";
    case 0x8D: return "LEA";
    case 0x8E: return "MOV";
    case 0x8F: return "POP";
    case 0x90: return "NOP";
    case 0x98: return "CBW";
    case 0x99: return "CWD";
    case 0x9A: return "CALL FAR";
    case 0x9B: return "WAIT";
    case 0x9C: return "PUSHF";
    case 0x9D: return "POPF";
    case 0x9E: return "SAHF";
    case 0x9F: return "LAHF";
    case 0xA0: case 0xA1: case 0xA2: case 0xA3: case 0xC6: case 0xC7: return "MOV";
    case 0xC2: case 0xC3: return "RET";
    case 0xC4: return "LES";
    case 0xC5: return "LDS";
    case 0xCA: case 0xCB: return "RETF";
    case 0xCC: return "INT3";
    case 0xCD: return has_next ? "INT " + hex2(next) + "h" : "INT";
    case 0xCE: return "INTO";
    case 0xCF: return "IRET";
    case 0xD4: return "AAM";
    case 0xD5: return "AAD";
    case 0xD7: return "XLAT";
    case 0xE0: return "LOOPNE";
    case 0xE1: return "LOOPE";
    case 0xE2: return "LOOP";
    case 0xE3: return "JCXZ";
    case 0xE4: case 0xE5: case 0xEC: case 0xED: return "IN";
    case 0xE6: case 0xE7: case 0xEE: case 0xEF: return "OUT";
    case 0xE8: return "CALL";
    case 0xE9: case 0xEB: return "JMP";
    case 0xEA: return "JMP FAR";
    case 0xF4: return "HLT";
    case 0xF5: return "CMC";
    case 0xF8: return "CLC";
    case 0xF9: return "STC";
    case 0xFA: return "CLI";
    case 0xFB: return "STI";
    case 0xFC: return "CLD";
    case 0xFD: return "STD";
    default: return "opcode " + hex2(op) + "h";
    }
}

} // namespace

Decoded decode(const std::uint8_t* b, unsigned n) {
    Decoded d;
    while (d.prefixes < n && is_prefix(b[d.prefixes])) ++d.prefixes;
    if (d.prefixes >= n) return d;
    const unsigned at = d.prefixes;
    d.opcode = b[at];
    const Form f = form_of(d.opcode);
    const bool has_modrm = f >= modrm && f <= group3_w;
    if (has_modrm && at + 1 >= n) return d; // the ModR/M byte is past the bytes given
    const std::uint8_t m = has_modrm ? b[at + 1] : 0;
    unsigned rest = 0; // bytes after the opcode
    switch (f) {
    case none: case prefix: rest = 0; break;
    case imm8: rest = 1; break;
    case imm16: rest = 2; break;
    case far_ptr: rest = 4; break;
    case modrm: rest = modrm_length(m); break;
    case modrm_imm8: rest = modrm_length(m) + 1; break;
    case modrm_imm16: rest = modrm_length(m) + 2; break;
    case group3_b: rest = modrm_length(m) + ((m & 0x30) == 0 ? 1 : 0); break; // TEST: /0 and /1
    case group3_w: rest = modrm_length(m) + ((m & 0x30) == 0 ? 2 : 0); break;
    }
    d.flow = flow_of(d.opcode, m);
    if (at + 1 + rest <= n) d.length = at + 1 + rest;
    return d;
}

std::optional<Target> direct_target(const std::uint8_t* b, const Decoded& d, std::uint16_t ip) {
    if (d.length == 0) return std::nullopt;
    const std::uint8_t* operand = b + d.prefixes + 1;
    const auto word = [](const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); };
    const auto after = static_cast<std::uint16_t>(ip + d.length);
    const std::uint8_t op = d.opcode;
    if (op == 0xEA || op == 0x9A) return Target{true, word(operand + 2), word(operand)};
    if (op == 0xE9 || op == 0xE8) return Target{false, 0, static_cast<std::uint16_t>(after + word(operand))};
    const bool rel8 = op == 0xEB || (op >= 0x60 && op < 0x80) || (op >= 0xE0 && op < 0xE4);
    if (!rel8) return std::nullopt;
    const auto displacement = static_cast<std::int8_t>(operand[0]);
    return Target{false, 0, static_cast<std::uint16_t>(after + displacement)};
}

std::string mnemonic(const std::uint8_t* b, unsigned n) {
    static const char* const strings[] = {"MOVSB", "MOVSW", "CMPSB", "CMPSW", "", "", "STOSB", "STOSW",
                                          "LODSB", "LODSW", "SCASB", "SCASW"};
    static const char* const segs[] = {"ES:", "CS:", "SS:", "DS:"};
    std::string pre;
    unsigned i = 0;
    bool rep = false, repne = false;
    for (; i < n && is_prefix(b[i]); ++i) {
        const std::uint8_t op = b[i];
        if (op == 0xF3) rep = true;
        else if (op == 0xF2) repne = true;
        else if (op == 0xF0 || op == 0xF1) pre += "LOCK ";
        else pre += std::string(segs[(op >> 3) & 3]) + " ";
    }
    if (i >= n) return pre.empty() ? "?" : pre + "?";
    const std::uint8_t op = b[i];
    if (op >= 0xA4 && op <= 0xAF && op != 0xA8 && op != 0xA9) {
        std::string m = strings[op - 0xA4];
        const bool compare = op == 0xA6 || op == 0xA7 || op == 0xAE || op == 0xAF;
        if (rep) m = (compare ? "REPE " : "REP ") + m;
        if (repne) m = "REPNE " + m;
        return pre + m;
    }
    const bool has_next = i + 1 < n;
    return pre + opcode_mnemonic(op, has_next, has_next ? b[i + 1] : 0);
}

} // namespace rcsim::i8086
