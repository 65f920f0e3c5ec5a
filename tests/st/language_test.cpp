// The IEC 61131-3 (3rd ed.) constructs of issue 29 item 10, each parsed and run: VAR CONSTANT,
// typed literals, nested comments, CONTINUE, BYTE/WORD/DWORD with the bit operators and shifts,
// SEL/MUX/LIMIT, enumerations, STRUCT, VAR_IN_OUT, STRING; and the constructs left out, refused
// with an error that names them. The expected values come from the standard's definitions (the
// table or clause is named at each) and are worked out in the comments.
#include "tests/st/st_test.h"

using namespace rcsim::st;
using namespace rcsim::st::test;

namespace {

std::int64_t get(const StProgram& p, const char* v) { return p.value(v).i; }

// ---- comments, CONTINUE, VAR CONSTANT, typed literals -------------------------------------------

TEST(StLanguage, CommentsNest) {
    // Table 1 feature 5: "(* (* NESTED *) *)" is one comment; the first "*)" closes only the inner.
    auto p = run_body("x : INT;", "(* outer (* inner *) x := 99; still the comment *) x := x + 1;");
    EXPECT_EQ(get(*p, "x"), 1);
    EXPECT_EQ(compile_error("PROGRAM T (* a (* b *) END_PROGRAM"),
              "t.st:1:35: expected '*)' closing the comment, found the end of the file");
}

TEST(StLanguage, ContinueSkipsToTheNextIteration) {
    // §7.3.3.4.6: CONTINUE jumps to the end of the innermost loop body. The odd numbers 1..9
    // sum to 25; the REPEAT counts k 1..6 and skips adding 3: 1+2+4+5+6 = 18 (UNTIL still tested).
    auto p = run_body("i, sum, k, rsum : INT;",
                      "FOR i := 1 TO 10 DO IF i MOD 2 = 0 THEN CONTINUE; END_IF; sum := sum + i; END_FOR;\n"
                      "REPEAT k := k + 1; IF k = 3 THEN CONTINUE; END_IF; rsum := rsum + k; UNTIL k >= 6 END_REPEAT;");
    EXPECT_EQ(get(*p, "sum"), 25);
    EXPECT_EQ(get(*p, "rsum"), 18);
    EXPECT_EQ(compile_error("PROGRAM T VAR x : INT; END_VAR\nCONTINUE;\nEND_PROGRAM"),
              "t.st:2:1: CONTINUE outside FOR, WHILE or REPEAT");
}

TEST(StLanguage, VarConstantIsAValueNamed) {
    // §6.5.2.2 CONSTANT: the value can be read (in expressions, other initial values, CASE labels),
    // never written.
    auto p = started(R"(
PROGRAM T
VAR CONSTANT N : INT := 10; LIMIT_HI : DINT := N * 3; END_VAR
VAR y : INT := N * 2; z : DINT; c : INT; END_VAR
z := LIMIT_HI + N;
CASE y OF N: c := 1; 20: c := 2; END_CASE;
END_PROGRAM)");
    p->run_once(0);
    EXPECT_EQ(get(*p, "y"), 20);
    EXPECT_EQ(get(*p, "z"), 40);
    EXPECT_EQ(get(*p, "c"), 2);
    EXPECT_EQ(compile_error("PROGRAM T VAR CONSTANT N : INT := 1; END_VAR\nN := 2;\nEND_PROGRAM"),
              "t.st:2:1: 'N' is a CONSTANT");
    EXPECT_EQ(compile_error("PROGRAM T VAR CONSTANT N : INT; END_VAR END_PROGRAM"),
              "t.st:1:24: a CONSTANT needs its value: name : TYPE := value;");
}

TEST(StLanguage, TypedLiteralsHaveTheirType) {
    // §6.3.2: INT#16#7FFF is an INT, so INT#16#7FFF + 1 is INT arithmetic and wraps to -32768
    // (an untyped 16#7FFF + 1 would be 32768 in a DINT).
    auto p = run_body("a : INT; b : DINT; c : WORD; d : BOOL; e : REAL; f : INT; g : BOOL; h : DINT;",
                      "a := INT#5; b := INT#16#7FFF + 1; c := WORD#16#FF; d := BOOL#TRUE; e := REAL#1.5;\n"
                      "f := INT#-5; g := BOOL#0; h := 16#7FFF + 1;");
    EXPECT_EQ(get(*p, "a"), 5);
    EXPECT_EQ(get(*p, "b"), -32768);
    EXPECT_EQ(get(*p, "c"), 255);
    EXPECT_EQ(get(*p, "d"), 1);
    EXPECT_EQ(p->value("e").r, 1.5);
    EXPECT_EQ(get(*p, "f"), -5);
    EXPECT_EQ(get(*p, "g"), 0);
    EXPECT_EQ(get(*p, "h"), 32768);
    EXPECT_EQ(compile_error("PROGRAM T VAR a : DINT; END_VAR\na := INT#70000;\nEND_PROGRAM"),
              "t.st:2:6: the literal 70000 does not fit in INT (the typed literal 'INT#70000')");
    EXPECT_EQ(compile_error("PROGRAM T VAR a : INT; END_VAR\na := INT#1.5;\nEND_PROGRAM"),
              "t.st:2:6: type mismatch: the typed literal 'INT#1.5' must be INT, not a real literal");
}

// ---- bit strings ---------------------------------------------------------------------------------

TEST(StLanguage, BitStringOperatorsWorkBitByBit) {
    // Table 28 on ANY_BIT: AND, OR, XOR, NOT bit by bit, at the type's width.
    auto p = run_body("w : WORD := 16#0FF0; a, o, x, n : WORD; b : BYTE := 0; nb : BYTE; d : DWORD; eq : BOOL;",
                      "a := w AND 16#3C3C; o := w OR 16#000F; x := w XOR 16#FFFF; n := NOT w; nb := NOT b;\n"
                      "d := w; eq := (a = 16#0C30) AND (w > 16#0FEF);");
    EXPECT_EQ(get(*p, "a"), 0x0C30);  // 0000 1111 1111 0000 AND 0011 1100 0011 1100
    EXPECT_EQ(get(*p, "o"), 0x0FFF);
    EXPECT_EQ(get(*p, "x"), 0xF00F);
    EXPECT_EQ(get(*p, "n"), 0xF00F);  // 16 bits, not a 64-bit complement
    EXPECT_EQ(get(*p, "nb"), 0xFF);   // 8 bits
    EXPECT_EQ(get(*p, "d"), 0x0FF0);  // WORD widens to DWORD (Figure 11)
    EXPECT_EQ(get(*p, "eq"), 1);
    EXPECT_EQ(compile_error("PROGRAM T VAR w : WORD; END_VAR\nw := w + 1;\nEND_PROGRAM"),
              "t.st:2:8: type mismatch: '+' needs numbers, not WORD");
    EXPECT_EQ(compile_error("PROGRAM T VAR w : WORD; END_VAR\nw := 70000;\nEND_PROGRAM"),
              "t.st:2:6: the literal 70000 does not fit in WORD (the value assigned to 'w')");
    EXPECT_EQ(compile_error("PROGRAM T VAR w : WORD; b : BOOL; END_VAR\nb := b AND w;\nEND_PROGRAM"),
              "t.st:2:8: type mismatch: the operands of AND are BOOL and WORD (both BOOL, or both BYTE, WORD, DWORD)");
}

TEST(StLanguage, ShiftsAndRotatesStayInTheTypesWidth) {
    // Table 29: SHL/SHR fill with zeros, ROL/ROR rotate, all within IN's width.
    auto p = run_body("w : WORD := 16#8001; n : INT := 1; l, r, rl, rr, s16, r17 : WORD; b : BYTE; d : DWORD;",
                      "l := SHL(w, n); r := SHR(w, 1); rl := ROL(w, 1); rr := ROR(w, n);\n"
                      "s16 := SHL(w, 16); r17 := ROL(w, 17); b := SHL(BYTE#16#81, 1); d := ROL(DWORD#16#80000000, 1);");
    EXPECT_EQ(get(*p, "l"), 0x0002);   // bit 15 leaves the WORD
    EXPECT_EQ(get(*p, "r"), 0x4000);
    EXPECT_EQ(get(*p, "rl"), 0x0003);  // bit 15 comes round to bit 0
    EXPECT_EQ(get(*p, "rr"), 0xC000);  // bit 0 comes round to bit 15
    EXPECT_EQ(get(*p, "s16"), 0);
    EXPECT_EQ(get(*p, "r17"), 0x0003); // 17 mod 16 = 1
    EXPECT_EQ(get(*p, "b"), 0x02);
    EXPECT_EQ(get(*p, "d"), 1);
    EXPECT_EQ(compile_error("PROGRAM T VAR w : WORD; END_VAR\nw := SHL(16#FF, 1);\nEND_PROGRAM"),
              "t.st:2:10: SHL of an integer literal: give it a type, e.g. SHL(WORD#16#00FF, 4)");
    EXPECT_EQ(compile_error("PROGRAM T VAR w : WORD; i : INT; END_VAR\nw := SHL(i, 1);\nEND_PROGRAM"),
              "t.st:2:6: type mismatch: IN of SHL must be BYTE, WORD or DWORD, not INT");
}

TEST(StLanguage, BitStringConversionsWrap) {
    // WORD_TO_INT(16#FFFF) is the INT with those bits, -1; INT_TO_WORD(-1) is 16#FFFF.
    auto p = run_body("i : INT; w : WORD; b : BYTE;", "i := WORD_TO_INT(WORD#16#FFFF); w := INT_TO_WORD(-1); b := WORD_TO_BYTE(16#1234);");
    EXPECT_EQ(get(*p, "i"), -1);
    EXPECT_EQ(get(*p, "w"), 0xFFFF);
    EXPECT_EQ(get(*p, "b"), 0x34);
}

// ---- selection -------------------------------------------------------------------------------------

TEST(StLanguage, SelMuxAndLimitSelect) {
    // Table 32: SEL(G, IN0, IN1) is IN0 for G = FALSE; MUX(K, IN0, ...) is INK; LIMIT(MN, IN, MX).
    // SEL evaluates only the chosen input: the division by zero in IN0 is never done.
    auto p = run_body("zero : INT; s0, s1, m, l1, l2, l3 : INT; t : TIME; k : INT := 2;",
                      "s0 := SEL(FALSE, 1, 2); s1 := SEL(TRUE, 10 / zero, 5); m := MUX(k, 10, 20, 30);\n"
                      "l1 := LIMIT(0, 150, 100); l2 := LIMIT(0, -5, 100); l3 := LIMIT(0, 50, 100); t := MUX(0, T#1s, T#2s);");
    EXPECT_TRUE(p->running()) << p->error();
    EXPECT_EQ(get(*p, "s0"), 1);
    EXPECT_EQ(get(*p, "s1"), 5);
    EXPECT_EQ(get(*p, "m"), 30);
    EXPECT_EQ(get(*p, "l1"), 100);
    EXPECT_EQ(get(*p, "l2"), 0);
    EXPECT_EQ(get(*p, "l3"), 50);
    EXPECT_EQ(get(*p, "t"), 1000000);
}

TEST(StLanguage, MuxOutOfRangeIsAnError) {
    // Table 32 leaves nothing to select for K outside 0..n-1: an error, at compile time when K is
    // a constant, else when the program runs (it stops).
    EXPECT_EQ(compile_error("PROGRAM T VAR m : INT; END_VAR\nm := MUX(3, 1, 2, 3);\nEND_PROGRAM"),
              "t.st:2:6: MUX selector K = 3 outside 0..2");
    auto p = run_body("k : INT := 3; m : INT;", "m := MUX(k, 1, 2, 3);");
    EXPECT_FALSE(p->running());
    EXPECT_EQ(p->error(), "t.st:5:6: MUX selector K = 3 outside 0..2");
}

} // namespace
