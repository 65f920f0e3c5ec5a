// rcsim — Intel 8086 execution unit: MUL/IMUL, DIV/IDIV, AAM/AAD (group F6/F7 /4-/7, D4, D5).
//
// Timing follows the structure of the published 8086 microcode disassembly (facts only): MUL
// and IMUL run the CORX shift-and-add co-routine (PREIMUL, NEGATE and IMULCOF around it for
// IMUL, MULCOF for MUL), DIV and IDIV the CORD restoring-division co-routine (PREIDIV, NEGATE,
// POSTIDIV for IDIV), AAD runs CORX. Each micro-instruction takes one clock; a taken jump, a
// call and a return cost one more clock (the sequencer loads the new address). The counts
// below are written per routine so they read against the listing; the whole sequence runs on
// internal clocks (the operand is read before it starts), so only the total is spent.
// Checked against the SingleStepTests 8086 v1 captures (F6/F7 /4-/7, D4, D5: level 3 exact).
#include "comm_cpu/i8086/cpu.h"
#include "comm_cpu/i8086/microcode.h"

namespace rcsim::i8086 {
namespace {

// Clock count of a microcode sequence: run(n) = n micro-instructions in a row, jump() = the
// extra clock of a taken jump or call, rtn() = the extra clock of a return.
struct Micro {
    unsigned clocks = 0;
    void run(unsigned n) { clocks += n; }
    void jump() { ++clocks; }
    void rtn() { ++clocks; }
};

unsigned popcount16(std::uint16_t v) {
    unsigned n = 0;
    for (; v; v &= std::uint16_t(v - 1)) ++n;
    return n;
}

// CORX: multiplies tmpb by tmpc (`multiplier`, n bits), one bit per loop iteration from bit 0.
// RRCY tmpc / MAXC, then per bit: NCY (1), ADD tmpa + F when the bit is set (2) or the jump
// over it (1), RRCY tmpa, RRCY tmpc, NCZ (3) and the jump back (1) except after the last bit;
// RTN (2). So a one bit of the multiplier costs a clock more than a zero bit.
void corx(Micro& m, std::uint16_t multiplier, unsigned n) {
    m.run(2);
    const unsigned ones = popcount16(std::uint16_t(multiplier & ((1u << n) - 1)));
    m.clocks += n * (1 + 1 + 3 + 1) - 1 + ones;
    m.run(1);
    m.rtn();
}

// NEGATE from its line 7 (the multiplicand/divisor sign): LRCY tmpb, NEG tmpb, NCY (3), then
// for a negative tmpb SIGMA->tmpb + CF1 RTN (2), for a positive one the jump to RTN (3).
void negate_tail(Micro& m, bool tmpb_negative) {
    m.run(3);
    if (tmpb_negative) {
        m.run(1);
        m.rtn();
    } else {
        m.jump();
        m.run(1);
        m.rtn();
    }
}

// The whole NEGATE co-routine: NEG tmpc, NCY, COM1 or NEG tmpa, SIGMA->tmpa + CF1 (5 either
// way: the carry branch skips one line and pays the jump), then the line-7 tail.
void negate_full(Micro& m, bool tmpb_negative) {
    m.run(5);
    negate_tail(m, tmpb_negative);
}

// The common tail of IMULCOF/MULCOF: Z tests the high half; a zero one (the product fits: CF
// and OF cleared) jumps to CCOF RTN (4), otherwise SCOF RTN (3).
void carry_overflow(Micro& m, bool fits) {
    m.run(1);
    if (fits) {
        m.jump();
        m.run(1);
        m.rtn();
    } else {
        m.run(1);
        m.rtn();
    }
}

// MUL/IMUL: 150-157 (byte) / 158-15F (word). `multiplier` is AL/AX, `multiplicand` the r/m
// operand, `rep` the F1 flag a REP prefix sets (it makes the microcode negate the product).
// (always_inline here and below: inlined alike in the profile-generating copy of the core,
// so the profile-guided build finds counts for every call; comm_cpu/tools/pgo/README.md.)
[[gnu::always_inline]] inline unsigned mul_clocks(std::uint16_t multiplier, std::uint16_t multiplicand, unsigned n,
                                                  bool sign, bool rep, bool fits) {
    const std::uint16_t top = std::uint16_t(1u << (n - 1));
    Micro m;
    bool f1 = rep;
    m.run(2); // A->tmpc | LRCY tmpc, M->tmpb | X0 PREIMUL
    if (sign) {
        // PREIMUL: NEG tmpc, NCY; a negative multiplier is replaced by its magnitude (CF1).
        m.jump();
        m.run(2);
        if (multiplier & top) {
            multiplier = std::uint16_t(-multiplier);
            f1 = !f1;
            m.run(2);
            m.jump();
        } else {
            m.jump();
        }
        negate_tail(m, multiplicand & top);
        if (multiplicand & top) f1 = !f1;
    }
    m.run(1); // UNC CORX
    m.jump();
    corx(m, multiplier, n);
    m.run(1); // F1 NEGATE
    if (f1) {
        // NEGATE's line 7 tests tmpb as PREIMUL left it: IMUL replaced a negative multiplicand
        // by NEG tmpb, which is still negative for the most negative value (80h, 8000h): that
        // one takes the shorter CF1 RTN path (issue #30).
        const std::uint16_t tmpb =
            sign && (multiplicand & top) ? std::uint16_t((0u - multiplicand) & ((1u << n) - 1)) : multiplicand;
        m.jump();
        negate_full(m, tmpb & top);
    }
    m.run(1); // X0 IMULCOF
    if (sign) {
        m.jump(); // IMULCOF: LRCY tmpc, ADC tmpa (high half + sign of the low half), F
        m.run(3);
        carry_overflow(m, fits);
        m.run(1); // tmpc -> A | X0 7
        m.jump();
    } else {
        m.run(2); // tmpc -> A | X0 7, UNC MULCOF
        m.jump();
        m.run(2); // MULCOF: PASS tmpa, F
        m.jump();
        carry_overflow(m, fits);
    }
    return m.clocks;
}

// DIV/IDIV: 160-166 (byte) / 168-16F (word), CORD, and for IDIV PREIDIV/NEGATE/POSTIDIV.
// Runs the restoring division on the magnitudes |hi:lo| / |divisor| (n bits each half) as CORD
// does, because both the clock count and the flags a divide error pushes depend on each step.
struct DivResult {
    unsigned clocks = 0;
    bool fault = false;
    bool flagged = false;                // a subtraction with F set the flags ...
    std::uint32_t flag_a = 0, flag_b = 0; // ... with these operands (the last one)
    bool cord_done = false;              // CORD ran to its RTN (its last RCLY set CF) ...
    bool cf = false;                     // ... to this
};

[[gnu::always_inline]] inline DivResult div_clocks(std::uint32_t hi, std::uint32_t lo, std::uint32_t divisor,
                                                   unsigned n, bool sign, bool neg_dividend, bool neg_divisor) {
    const std::uint32_t mask = (1u << n) - 1, top = 1u << (n - 1);
    Micro m;
    DivResult r;
    m.run(3); // dividend halves and divisor into tmpa, tmpc, tmpb
    if (sign) {
        m.jump(); // PREIDIV: the dividend's sign; a negative one goes through the whole NEGATE
        m.run(2);
        if (neg_dividend) {
            m.run(5);
        } else {
            m.jump();
        }
        negate_tail(m, neg_divisor);
    }
    m.run(1); // UNC CORD
    m.jump();
    // CORD: SUBT tmpa (F), MAXC, NCY INT0: the quotient does not fit when hi >= divisor.
    m.run(3);
    r.flagged = true;
    r.flag_a = hi;
    r.flag_b = divisor;
    if (hi >= divisor) {
        m.jump();
        r.fault = true;
        r.clocks = m.clocks;
        return r;
    }
    std::uint32_t a = hi & mask, q = lo & mask;
    bool carry = true; // the borrow of the first trial
    for (unsigned i = n; i-- > 0;) {
        const bool last = i == 0;
        // RCLY tmpc, RCLY tmpa: the quotient bit in, the next dividend bit into tmpa (4).
        const bool qout = q & top;
        q = ((q << 1) | (carry ? 1 : 0)) & mask;
        const bool aout = a & top;
        a = ((a << 1) | (qout ? 1 : 0)) & mask;
        m.run(4);
        if (aout) {
            // A bit fell out of tmpa: the subtraction cannot borrow. Jump, RCY, SUBT.
            a = (a - divisor) & mask;
            carry = false;
            m.jump();
            m.run(2);
        } else {
            r.flag_a = a; // the trial subtraction with F: its flags stand until the next one
            r.flag_b = divisor;
            m.run(2);
            if (a >= divisor) {
                a -= divisor;
                carry = false;
                m.jump(); // NCY to the SUBT line
                m.run(1);
            } else {
                carry = true;
                m.run(1);
                if (last) continue; // NCZ falls through to the end of the loop
            }
        }
        if (last) {
            m.run(1);
            m.jump();
        } else {
            m.jump(); // NCZ back to the loop head
        }
    }
    q = ((q << 1) | (carry ? 1 : 0)) & mask; // the quotient, complemented
    r.cord_done = true;
    r.cf = q & top;                          // the last RCLY: set when |quotient| < 2^(n-1)
    m.run(3);                                // RCLY tmpc, SIGMA->tmpc, RCLY (CF) | RTN
    m.rtn();
    m.run(2); // COM1 tmpc, X0 POSTIDIV
    if (sign) {
        m.jump(); // POSTIDIV: NCY INT0 (the quotient magnitude must stay below 2^(n-1))
        m.run(1);
        if (!r.cf) {
            m.jump();
            r.fault = true;
            r.clocks = m.clocks;
            return r;
        }
        m.run(3); // LRCY tmpb, NEG tmpa, NCY: the remainder's sign ...
        m.run(1); // ... (negate it, or the jump over)
        m.run(2); // INC tmpc, F1
        m.run(1); // COM tmpc, or the jump over it
        m.run(1); // CCOF RTN
        m.rtn();
    }
    r.clocks = m.clocks;
    return r;
}

} // namespace

// MUL/IMUL r/m (F6/F7 /4 /5). Flags: CF = OF = the high half is significant.
void Cpu::multiply(bool word, bool sign) {
    const bool rep = rep_ != 0; // a REP prefix negates the product (the microcode's F1 flag)
    const bool mem = mod_ != 3;
    bool fits;
    std::uint16_t acc, src;
    if (!word) {
        src = rm_read8();
        acc = reg8(0);
        int p = sign ? int(std::int8_t(acc)) * int(std::int8_t(src)) : int(acc) * int(src);
        if (rep) p = -p;
        const std::uint16_t prod = std::uint16_t(p);
        fits = sign ? std::int16_t(prod) == std::int8_t(prod & 0xFF) : (prod >> 8) == 0;
        r_.r[AX] = prod;
        set_szp(prod >> 8, false);
        set_flag(flag::ZF, prod == 0);
    } else {
        src = rm_read16();
        acc = r_.r[AX];
        std::int64_t p = sign ? std::int64_t(std::int16_t(acc)) * std::int16_t(src) : std::int64_t(acc) * src;
        if (rep) p = -p;
        const std::uint32_t prod = std::uint32_t(p);
        fits = sign ? std::int32_t(prod) == std::int16_t(prod & 0xFFFF) : (prod >> 16) == 0;
        r_.r[AX] = std::uint16_t(prod);
        r_.r[DX] = std::uint16_t(prod >> 16);
        set_szp(std::uint16_t(prod >> 16), true);
        set_flag(flag::ZF, prod == 0);
    }
    set_flag(flag::CF, !fits);
    set_flag(flag::OF, !fits);
    // A memory operand takes a clock more; the last result move (157 / 15F) before RNI.
    clks(mul_clocks(acc, src, word ? 16 : 8, sign, rep, fits) + (mem ? kMulDivMemOperand : 0) + kMulDivResult);
}

// DIV/IDIV r/m (F6/F7 /6 /7); returns false when the divide error (type 0) was taken. The
// 8086 pushes the address of the next instruction and, for IDIV, refuses the most negative
// quotient (POSTIDIV keeps the magnitude below 2^(n-1)).
bool Cpu::divide(bool word, bool sign) {
    const bool negate = rep_ != 0;
    const unsigned n = word ? 16 : 8;
    const std::uint32_t top = 1u << (n - 1), mask = (1u << n) - 1;
    const std::uint32_t src = word ? rm_read16() : rm_read8();
    const std::uint32_t dividend = word ? (std::uint32_t(r_.r[DX]) << 16) | r_.r[AX] : r_.r[AX];
    const std::uint32_t dsign = top << n; // sign bit of the double-width dividend
    const bool neg_dividend = sign && (dividend & dsign);
    const bool neg_divisor = sign && (src & top);
    const std::uint32_t mag = neg_dividend ? (0u - dividend) & ((dsign << 1) - 1) : dividend;
    const std::uint32_t dmag = neg_divisor ? (0u - src) & mask : src;
    const DivResult t = div_clocks(mag >> n, mag & mask, dmag, n, sign, neg_dividend, neg_divisor);
    if (!t.fault) {
        std::uint32_t q = (mag / dmag) & mask, rem = (mag % dmag) & mask;
        if (sign) {
            if (neg_dividend != neg_divisor) q = (0u - q) & mask;
            if (negate) q = (0u - q) & mask;
            if (neg_dividend) rem = (0u - rem) & mask;
        }
        if (word) {
            r_.r[AX] = std::uint16_t(q);
            r_.r[DX] = std::uint16_t(rem);
        } else {
            r_.r[AX] = std::uint16_t((rem << 8) | q);
        }
    }
    // Around the microcode: a memory operand takes a clock more; then the last result move (166
    // / 16E) before RNI, or the way to the type-0 entry on an error.
    clks(t.clocks + (mod_ != 3 ? kMulDivMemOperand : 0) + (t.fault ? kDivToInt0 : kMulDivResult));
    if (t.fault) {
        // The FLAGS image the error pushes holds what the microcode left: the flags of the last
        // subtraction with F (the first trial for an error found by CORD), and CF from CORD's
        // final RCLY when the error comes from POSTIDIV.
        if (t.flagged) alu(5, std::uint16_t(t.flag_a), std::uint16_t(t.flag_b), word);
        if (t.cord_done) set_flag(flag::CF, t.cf);
        interrupt(0);
    }
    return !t.fault;
}

// AAM (D4): AH = AL / imm, AL = AL % imm through CORD; a zero base takes the divide error.
void Cpu::aam(std::uint8_t base) {
    if (base == 0) {
        clks(kAamZeroBase);
        interrupt(0);
        return;
    }
    const std::uint8_t al = reg8(0);
    const std::uint8_t q = std::uint8_t(al / base);
    set_reg8(4, q);
    set_reg8(0, std::uint8_t(al % base));
    set_szp(reg8(0), false);
    // The division loop (measured): one clock per one bit of the quotient, two more when the
    // quotient is odd.
    clks(kAamLoop + kAamPerQuotientOne * popcount16(q) + ((q & 1) ? kAamOddQuotient : 0));
}

// AAD (D5): AL = AL + AH * imm, flags as the addition. 170-171 and the call (3), CORX with the
// immediate as multiplier, 172-173 (2).
void Cpu::aad(std::uint8_t base) {
    const std::uint8_t prod = std::uint8_t(reg8(4) * base);
    const std::uint8_t r = std::uint8_t(alu(0, reg8(0), prod, false));
    r_.r[AX] = r;
    Micro m;
    m.run(2);
    m.jump();
    corx(m, base, 8);
    m.run(2);
    clks(m.clocks);
}

} // namespace rcsim::i8086
