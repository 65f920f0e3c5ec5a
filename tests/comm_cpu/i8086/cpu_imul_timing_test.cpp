// MUL/IMUL clock counts of the bare 8086 core against a count derived here, independently of
// comm_cpu/i8086/muldiv.cpp, from the 8086 microcode as published: reenigne's disassembly of
// the 8086 microcode ROM (lines 150-15F, CORX 17F-187, NEGATE 1B6-1BF, PREIMUL 1C0-1C3,
// IMULCOF 1CD-1D1, MULCOF 1D2-1D3), explained in Ken Shirriff's "Reverse-engineering the
// multiplication algorithm in the Intel 8086 processor" (righto.com, 2023-03), and traced the
// same way by MartyPC's cpu_808x/muldiv.rs (validated against the same hardware captures).
//
// Clock rules (Shirriff, "How the 8086 processor's microcode engine works"): every microcode
// line takes one clock; a taken jump, a call and a return take one more (the sequencer loads
// the new address); a conditional jump that is not taken costs nothing more.
//
// The model below runs the listing on the temporary registers (tmpa, tmpb, tmpc, the carry and
// the F1 flag), so every data-dependent branch is decided by the value the hardware would test,
// not by a formula of the operands. What it gives, per sign case (n = 8 or 16 bits):
//   150/151 (158/159)  A -> tmpc, LRCY tmpc | M -> tmpb, X0 PREIMUL            2
//   IMUL only, PREIMUL: jump 1, NEG tmpc, NCY 7 (2); a negative multiplier (AL/AX) is
//     replaced by its magnitude with CF1: SIGMA->tmpc, UNC NEGATE 7 and its jump (3), else the
//     NCY jump (1); NEGATE 7: LRCY tmpb, NEG tmpb, NCY 11 (3), then a negative tmpb (the
//     multiplicand) becomes -tmpb with CF1: SIGMA->tmpb CF1 RTN (1 + 1 return); a positive one
//     jumps to RTN (1 + 1 + 1 return).                    So: +2 for a negative multiplier,
//     -1 for a negative multiplicand; 10 in all for both positive.
//   152 UNC CORX and the call                                                   2
//   CORX: ZERO->tmpa RRCY tmpc, MAXC (2); per multiplier bit, from bit 0: NCY 8 (1), then for a
//     1 bit ADD tmpa, SIGMA->tmpa F (2) or for a 0 bit the jump (1), RRCY tmpa, SIGMA->tmpa RRCY
//     tmpc, SIGMA->tmpc NCZ 5 (3) and the jump back except after the last bit (1); RTN (1 + 1).
//     So 6n + 3 + (ones in the multiplier tmpc), tmpc being |AL| for IMUL.
//   153 F1 NEGATE (1); with F1 set (REP prefix, xor a negative multiplier, xor a negative
//     multiplicand) the jump (1) into NEGATE from line 1: NEG tmpc, NCY, COM1/NEG tmpa,
//     SIGMA->tmpa CF1 (5 either way) and line 7 again on the tmpb left by PREIMUL: +2 for a
//     tmpb still negative, +3 for a positive one. tmpb is still negative after PREIMUL only
//     when it was the most negative value (NEG 80h = 80h, NEG 8000h = 8000h): the one case
//     where IMUL's result negation is a clock shorter (issue #30).
//   154 X0 IMULCOF (1); IMUL: the jump (1), LRCY tmpc, ADC tmpa, F (3), Z 8 (1), then for a
//     zero sum (the product fits in n bits) the jump to CCOF RTN (1 + 1 + 1 return), else SCOF
//     RTN (1 + 1 return), then 155 tmpc -> A, X0 7 and its jump (2);
//     MUL: 155, 156 UNC MULCOF and its jump (3), PASS tmpa, UNC 12 F and its jump (3), Z 8 and
//     CCOF/SCOF as above.
//   157 (15F) tmpa -> X, RNI                                                     1
// Around the listing, with the instruction in a full queue (the SingleStepTests convention:
// from the clock reading the opcode to the one reading the next opcode): 2 clocks for a register
// operand before line 150, so that MUL r8 is 70-77 and MUL r16 118-133 as the iAPX 86/88
// User's Manual gives (and as the SingleStepTests F6.4 captures with a register operand and a
// full queue show: 72 clocks for AL = 0Bh, 74 for AL = E3h); with [BX] (a word at an even
// address, no wait states) 12 clocks before line 150, as the F6.4 captures of MUL [BX] with a
// full queue show (AL = 23h: 82 = 12 + 70; AL = BDh, [BX] = B8h: 85 = 12 + 73).
#include "comm_cpu/i8086/cpu.h"
#include "tests/comm_cpu/i8086/cpu_board.h"
#include "tests/support/sc_test.h"

#include <cstdint>
#include <string>
#include <vector>

using namespace rcsim;
using namespace rcsim::i8086;
using rcsim::i8086::test::Board;

namespace {

// The listing above run on the temporary registers; returns the clocks from line 150 (158) to
// 157 (15F) inclusive and the product tmpa:tmpc.
struct Microcode {
    unsigned n;
    std::uint32_t mask, top;
    unsigned clocks = 0;
    std::uint32_t tmpa = 0, tmpb = 0, tmpc = 0;
    bool cf = false, f1 = false;

    explicit Microcode(unsigned bits) : n(bits), mask((1u << bits) - 1), top(1u << (bits - 1)) {}
    void line(unsigned k = 1) { clocks += k; }
    void jump() { ++clocks; } // a taken jump or a call
    void ret() { ++clocks; }
    std::uint32_t neg(std::uint32_t v) const { return (0u - v) & mask; }
    // RRCY: rotate right through the carry (n bits).
    std::uint32_t rrcy(std::uint32_t v) {
        const bool out = v & 1;
        v = (v >> 1) | (cf ? top : 0);
        cf = out;
        return v;
    }

    // NEGATE from line 7 (1BB): LRCY tmpb, NEG tmpb, NCY 11.
    void negate7() {
        cf = tmpb & top;
        line(3);
        if (cf) {
            tmpb = neg(tmpb); // 1BE SIGMA->tmpb CF1 RTN
            f1 = !f1;
            line(1);
            ret();
        } else {
            jump(); // to 11: 1BF RTN
            line(1);
            ret();
        }
    }
    // NEGATE from line 1 (1B6): the double-width tmpa:tmpc negated, then line 7.
    void negate1() {
        const bool carry = tmpc != 0; // NEG tmpc borrows unless tmpc is zero
        tmpc = neg(tmpc);
        if (carry) {
            tmpa = ~tmpa & mask; // COM1 tmpa, the jump over NEG tmpa
            line(3);
            jump();
            line(1);
        } else {
            tmpa = neg(tmpa);
            line(5);
        }
        f1 = !f1; // SIGMA->tmpa CF1
        negate7();
    }
    void corx() {
        tmpa = 0;
        tmpc = rrcy(tmpc); // ZERO->tmpa RRCY tmpc, MAXC
        line(2);
        for (unsigned i = 0; i < n; ++i) {
            line(1); // NCY 8
            if (cf) {
                const std::uint32_t s = tmpa + tmpb; // ADD tmpa, SIGMA->tmpa F
                cf = s > mask;
                tmpa = s & mask;
                line(2);
            } else {
                jump();
            }
            tmpa = rrcy(tmpa);
            tmpc = rrcy(tmpc);
            line(3);
            if (i + 1 < n) jump(); // NCZ 5
        }
        line(1); // RTN
        ret();
    }
    // Z 8 then CCOF RTN (zero) or SCOF RTN.
    void cof(std::uint32_t sigma) {
        line(1);
        if (sigma == 0) {
            jump();
            line(1);
            ret();
        } else {
            line(1);
            ret();
        }
    }

    void run(std::uint32_t acc, std::uint32_t operand, bool sign, bool rep) {
        tmpc = acc & mask;
        cf = tmpc & top; // LRCY tmpc
        tmpb = operand & mask;
        f1 = rep;
        line(2);
        if (sign) { // PREIMUL
            jump();
            line(2); // NEG tmpc, NCY 7
            if (cf) {
                tmpc = neg(tmpc);
                f1 = !f1;
                line(2);
                jump();
            } else {
                jump();
            }
            negate7();
        }
        line(1); // UNC CORX
        jump();
        corx();
        line(1); // F1 NEGATE
        if (f1) {
            jump();
            negate1();
        }
        line(1); // X0 IMULCOF
        if (sign) {
            jump();
            cf = tmpc & top; // LRCY tmpc, ADC tmpa, F
            line(3);
            cof((tmpa + (cf ? 1 : 0)) & mask);
            line(1); // tmpc -> A, X0 7
            jump();
        } else {
            line(2); // 155 tmpc -> A, X0 7 (not taken), 156 UNC MULCOF
            jump();
            line(2); // PASS tmpa, UNC 12 F
            jump();
            cof(tmpa);
        }
        line(1); // 157 / 15F tmpa -> X, RNI
    }
    std::uint32_t product() const { return (tmpa << n) | tmpc; }
};

// Around the listing (see the header): register operand, [BX] at an even address.
constexpr unsigned kBeforeListingReg = 2;
constexpr unsigned kBeforeListingMem = 12;

unsigned derived(std::uint32_t acc, std::uint32_t operand, bool word, bool sign, bool mem,
                 std::uint32_t* product = nullptr, bool rep = false) {
    Microcode m(word ? 16 : 8);
    m.run(acc, operand, sign, rep);
    if (product) *product = m.product();
    return m.clocks + (mem ? kBeforeListingMem : kBeforeListingReg);
}

// Runs one MUL/IMUL (F6/F7, /4 or /5) from a full queue on the bare core and returns its clocks
// (opcode read to next opcode read, as SingleStepTests counts them). Register operand: BL/BX
// (modrm EB / E3); memory operand: [BX] (modrm 2F / 27) with BX = 0x0100, DS = 0x3000.
struct Runner {
    Board b;
    unsigned run(std::uint16_t acc, std::uint16_t operand, bool word, bool sign, bool mem, bool rep = false) {
        const std::uint8_t modrm = std::uint8_t((mem ? 0x07 : 0xC3) | ((sign ? 5 : 4) << 3));
        const std::uint8_t op = std::uint8_t(word ? 0xF7 : 0xF6);
        std::uint8_t code[6] = {op, modrm, 0x90, 0x90, 0x90, 0x90};
        if (rep) { // REP (F3): the microcode's F1 set at the start, the product negated
            code[0] = 0xF3;
            code[1] = op;
            code[2] = modrm;
        }
        b.load(std::vector<std::uint8_t>(code, code + 6));
        Registers r;
        r.s[CS] = 0x1000;
        r.s[SS] = 0x2000;
        r.s[DS] = 0x3000;
        r.s[ES] = 0x4000;
        r.r[SP] = 0x0100;
        r.r[AX] = acc;
        if (mem) {
            r.r[BX] = 0x0100;
            b.ram[0x30100] = std::uint8_t(operand);
            b.ram[0x30101] = std::uint8_t(operand >> 8);
        } else {
            r.r[BX] = word ? operand : std::uint16_t(operand & 0xFF);
        }
        b.cpu.load_state(r, code, 6);
        b.cpu.start();
        const cycles_t c0 = b.cpu.cycles();
        b.cpu.step();
        b.cycles.clear();
        b.calls.clear();
        return unsigned(b.cpu.cycles() - c0);
    }
};

struct Mismatch {
    unsigned count = 0;
    std::string first;
};

void check(Runner& run, Mismatch& bad, std::uint16_t acc, std::uint16_t operand, bool word, bool sign, bool mem) {
    std::uint32_t product = 0;
    const unsigned want = derived(acc, operand, word, sign, mem, &product);
    const unsigned got = run.run(acc, operand, word, sign, mem);
    const std::uint32_t ax = run.b.cpu.regs().r[AX];
    const std::uint32_t result = word ? (std::uint32_t(run.b.cpu.regs().r[DX]) << 16) | ax : ax;
    if (got != want || result != product) {
        if (bad.count++ == 0)
            bad.first = std::string(sign ? "IMUL " : "MUL ") + (word ? "r/m16" : "r/m8") + (mem ? " [BX]" : " reg") +
                        " acc=" + std::to_string(acc) + " operand=" + std::to_string(operand) + ": core " +
                        std::to_string(got) + " clocks, microcode " + std::to_string(want) + "; result " +
                        std::to_string(result) + ", microcode " + std::to_string(product);
    }
}

// Every (accumulator, operand) byte pair of one form.
void check_byte_pairs(Runner& run, Mismatch& bad, bool sign, bool mem) {
    for (unsigned a = 0; a < 256; ++a)
        for (unsigned b = 0; b < 256; ++b) check(run, bad, std::uint16_t(a), std::uint16_t(b), false, sign, mem);
}

// A fixed 32-bit LCG (Numerical Recipes constants): the sample is the same on every run.
struct Lcg {
    std::uint32_t s;
    std::uint16_t next() {
        s = s * 1664525u + 1013904223u;
        return std::uint16_t(s >> 16);
    }
};

// Operand values where the sign cases meet: zero, one, the extremes of each sign.
const std::uint16_t kEdges16[] = {0x0000, 0x0001, 0x0002, 0x00FF, 0x0100, 0x5555, 0x7FFE, 0x7FFF,
                                  0x8000, 0x8001, 0xAAAA, 0xFF00, 0xFFFE, 0xFFFF};

} // namespace

// The listing's own arithmetic is the product the instruction defines (a check of the model).
TEST(Cpu8086MulTiming, MicrocodeModelComputesTheProduct) {
    for (unsigned a = 0; a < 256; ++a)
        for (unsigned b = 0; b < 256; ++b) {
            std::uint32_t p = 0;
            derived(a, b, false, true, false, &p);
            ASSERT_EQ(p, std::uint32_t(std::uint16_t(int(std::int8_t(a)) * int(std::int8_t(b))))) << a << " " << b;
            derived(a, b, false, false, false, &p);
            ASSERT_EQ(p, a * b) << a << " " << b;
        }
    // The User's Manual bands (register operand): MUL r8 70-77, MUL r16 118-133.
    EXPECT_EQ(derived(0, 0, false, false, false), 70u);
    EXPECT_EQ(derived(0xFF, 0xFF, false, false, false), 77u);
    EXPECT_EQ(derived(0, 0, true, false, false), 118u);
    EXPECT_EQ(derived(0xFFFF, 0xFFFF, true, false, false), 133u);
    EXPECT_EQ(derived(0, 0, false, true, false), 80u) << "IMUL r8 80-98";
    EXPECT_EQ(derived(0, 0, true, true, false), 128u) << "IMUL r16 128-154";
}

// IMUL r/m8 with a register operand: all 65 536 (AL, BL) pairs.
TEST(Cpu8086MulTiming, ImulReg8AllPairs) {
    Runner run;
    Mismatch bad;
    check_byte_pairs(run, bad, true, false);
    EXPECT_EQ(bad.count, 0u) << "first: " << bad.first;
}

// IMUL r/m8 with a memory operand ([BX]): all 65 536 (AL, [BX]) pairs.
TEST(Cpu8086MulTiming, ImulMem8AllPairs) {
    Runner run;
    Mismatch bad;
    check_byte_pairs(run, bad, true, true);
    EXPECT_EQ(bad.count, 0u) << "first: " << bad.first;
}

// MUL r/m8, both operand forms: all pairs.
TEST(Cpu8086MulTiming, MulByteAllPairs) {
    Runner run;
    Mismatch bad;
    for (bool mem : {false, true}) check_byte_pairs(run, bad, false, mem);
    EXPECT_EQ(bad.count, 0u) << "first: " << bad.first;
}

// IMUL and MUL r/m16, register and [BX]: every pair of the edge values and 40 000 pseudo-random
// pairs per form, a quarter of them with the operand forced to 8000h or the sign bits varied.
TEST(Cpu8086MulTiming, Word16EdgesAndSample) {
    Runner run;
    Mismatch bad;
    for (bool sign : {true, false})
        for (bool mem : {false, true}) {
            for (std::uint16_t a : kEdges16)
                for (std::uint16_t b : kEdges16) check(run, bad, a, b, true, sign, mem);
            Lcg rng{0x8086u + (sign ? 1u : 0u) + (mem ? 2u : 0u)};
            for (unsigned i = 0; i < 40000; ++i) {
                std::uint16_t a = rng.next(), b = rng.next();
                if (i % 4 == 1) b = 0x8000;
                if (i % 4 == 2) a = std::uint16_t(a ^ 0x8000);
                check(run, bad, a, b, true, sign, mem);
            }
        }
    EXPECT_EQ(bad.count, 0u) << "first: " << bad.first;
}

// REP IMUL r/m8 (F3 F6 /5, register operand): F1 starts set, so NEGATE runs when the signs
// agree and the most negative multiplicand meets it when AL is negative. The prefix's clocks
// come before line 150 and are not derived here: the core's count minus the listing's must be
// one constant over all 65 536 pairs, and the product the listing's (negated) one.
TEST(Cpu8086MulTiming, RepImulReg8AllPairsDifferByAConstant) {
    Runner run;
    unsigned bad = 0;
    std::string first;
    int offset = 0;
    for (unsigned a = 0; a < 256; ++a)
        for (unsigned b = 0; b < 256; ++b) {
            std::uint32_t product = 0;
            const int want = int(derived(a, b, false, true, false, &product, true));
            const int got = int(run.run(std::uint16_t(a), std::uint16_t(b), false, true, false, true));
            if (a == 0 && b == 0) offset = got - want;
            if (got - want != offset || run.b.cpu.regs().r[AX] != product) {
                if (bad++ == 0)
                    first = "AL=" + std::to_string(a) + " BL=" + std::to_string(b) + ": core " + std::to_string(got) +
                            ", listing " + std::to_string(want) + " + " + std::to_string(offset);
            }
        }
    EXPECT_EQ(bad, 0u) << "first: " << first;
}
