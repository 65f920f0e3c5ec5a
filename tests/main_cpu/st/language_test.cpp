// The IEC 61131-3 (3rd ed.) constructs of issue 29 item 10, each parsed and run: VAR CONSTANT,
// typed literals, nested comments, CONTINUE, BYTE/WORD/DWORD with the bit operators and shifts,
// SEL/MUX/LIMIT, enumerations, STRUCT, VAR_IN_OUT, STRING; and the constructs left out, refused
// with an error that names them. The expected values come from the standard's definitions (the
// table or clause is named at each) and are worked out in the comments.
#include "tests/main_cpu/st/st_test.h"
#include "tests/support/files.h"

#include <filesystem>

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
    auto p = run_body("zero : INT; s0, s1, m, l1, l2, l3, mn : INT; t : TIME; k : INT := 2; i7 : INT := 7;",
                      "s0 := SEL(FALSE, 1, 2); s1 := SEL(TRUE, 10 / zero, 5); m := MUX(k, 10, 20, 30);\n"
                      "l1 := LIMIT(0, 150, 100); l2 := LIMIT(0, -5, 100); l3 := LIMIT(0, 50, 100); t := MUX(0, T#1s, T#2s);\n"
                      "mn := MIN(100, i7); (* the literal takes i7's type: an INT result *)");
    EXPECT_TRUE(p->running()) << p->error();
    EXPECT_EQ(get(*p, "s0"), 1);
    EXPECT_EQ(get(*p, "s1"), 5);
    EXPECT_EQ(get(*p, "m"), 30);
    EXPECT_EQ(get(*p, "l1"), 100);
    EXPECT_EQ(get(*p, "l2"), 0);
    EXPECT_EQ(get(*p, "l3"), 50);
    EXPECT_EQ(get(*p, "t"), 1000000);
    EXPECT_EQ(get(*p, "mn"), 7);
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

// ---- enumerations, STRUCT, VAR_IN_OUT, STRING ------------------------------------------------------

const char* types_text = R"(
TYPE
    Color : (Red, Green := 5, Blue);
    Mode : (Idle, Run, Fault) := Run;
    Point : STRUCT x : DINT; y : DINT := 7; END_STRUCT;
    Segment : STRUCT a, b : Point; tag : Color := Blue; END_STRUCT;
END_TYPE
)";

TEST(StLanguage, EnumerationsHaveTheirValuesAndDefaults) {
    // §6.4.4.2: a value without one given is one more than the one before (Blue = 6); a variable
    // starts as the type's initial value, else its first value (Red; Mode says Run).
    auto p = started(std::string(types_text) + R"(
PROGRAM T
VAR c : Color; m : Mode; d : Color := Color#Blue; same, differ : BOOL; n : DINT; k : INT; END_VAR
same := d = Blue;
differ := c <> d;
CASE d OF
    Red: k := 1;
    Green, Blue: k := 2;
END_CASE;
CASE m OF Idle: n := 10; Run: n := 20; ELSE n := 30; END_CASE;
END_PROGRAM)");
    p->run_once(0);
    EXPECT_EQ(get(*p, "c"), 0);
    EXPECT_EQ(get(*p, "d"), 6);
    EXPECT_EQ(get(*p, "m"), 1);
    EXPECT_EQ(get(*p, "same"), 1);
    EXPECT_EQ(get(*p, "differ"), 1);
    EXPECT_EQ(get(*p, "k"), 2);
    EXPECT_EQ(get(*p, "n"), 20);
    EXPECT_EQ(p->variables()["d"], "Blue"); // the report names the value
    auto f = started(std::string(types_text) + R"(
FUNCTION Next : Color
VAR_INPUT c : Color; END_VAR
Next := SEL(c = Red, Red, Green);
END_FUNCTION
PROGRAM T VAR a : Color; END_VAR
a := Next(Red);
END_PROGRAM)");
    f->run_once(0);
    EXPECT_EQ(get(*f, "a"), 5); // a FUNCTION of an enumeration: Red gives Green = 5
    const std::string prog = std::string(types_text) + "PROGRAM T VAR c : Color; i : INT; END_VAR\n";
    EXPECT_EQ(compile_error(prog + "c := 1;\nEND_PROGRAM"),
              "t.st:9:6: type mismatch: the value assigned to 'c' must be Color, not an integer literal");
    EXPECT_EQ(compile_error(prog + "c := Run;\nEND_PROGRAM"),
              "t.st:9:6: type mismatch: the value assigned to 'c' must be Color, not Mode");
    EXPECT_EQ(compile_error(prog + "i := c + 1;\nEND_PROGRAM"), "t.st:9:8: type mismatch: '+' needs numbers, not Color");
    EXPECT_EQ(compile_error(prog + "CASE c OF Run: i := 1; END_CASE;\nEND_PROGRAM"),
              "t.st:9:11: type mismatch: a CASE label must be Color, not Mode");
}

TEST(StLanguage, StructMembersAreReadWrittenCopiedAndInitialised) {
    // §6.4.4.4: members by name, defaults from the type (y = 7, tag = Blue), (x := 1) initial
    // values, whole-structure assignment copies every member, ARRAY OF a STRUCT.
    auto p = started(std::string(types_text) + R"(
PROGRAM T
VAR p : Point := (x := 1); q : Point; s : Segment := (b := (x := 3, y := 4)); pts : ARRAY[1..3] OF Point;
    i : INT := 2; r1, r2, r3, r4 : DINT; t : Color; END_VAR
p.x := p.x + 10;
q := p;
s.a := q;
pts[i].y := 5;
pts[3] := s.b;
r1 := q.x; r2 := q.y; r3 := s.a.x + s.b.y; r4 := pts[2].y + pts[3].x + pts[1].y;
t := s.tag;
END_PROGRAM)");
    p->run_once(0);
    EXPECT_EQ(get(*p, "r1"), 11);          // 1 + 10
    EXPECT_EQ(get(*p, "r2"), 7);           // the member's default
    EXPECT_EQ(get(*p, "r3"), 11 + 4);
    EXPECT_EQ(get(*p, "r4"), 5 + 3 + 7);   // pts[1] keeps the default y = 7
    EXPECT_EQ(get(*p, "t"), 6);            // Blue
    const auto v = p->variables();
    EXPECT_EQ(v["q"], (nlohmann::json{{"x", 11}, {"y", 7}}));
    EXPECT_EQ(v["pts"][2], (nlohmann::json{{"x", 3}, {"y", 4}}));
    EXPECT_EQ(get(*p, "q.x"), 11);
    EXPECT_THROW(p->value("q"), std::out_of_range); // several slots: not one value to force
    const std::string prog = std::string(types_text) + "PROGRAM T VAR p : Point; i : DINT; c : Segment; END_VAR\n";
    EXPECT_EQ(compile_error(prog + "p.z := 1;\nEND_PROGRAM"), "t.st:9:3: 'z' is not a member of Point");
    EXPECT_EQ(compile_error(prog + "i := p;\nEND_PROGRAM"),
              "t.st:9:6: type mismatch: the value assigned to 'i' must be DINT, not Point");
    EXPECT_EQ(compile_error(prog + "p := c;\nEND_PROGRAM"),
              "t.st:9:6: type mismatch: the value assigned to 'p' must be Point, not Segment");
    EXPECT_EQ(compile_error(prog + "i := p + 1;\nEND_PROGRAM"),
              "t.st:9:6: 'p' is a STRUCT Point; use its members, e.g. p.x");
    EXPECT_EQ(compile_error("TYPE A : STRUCT b : B; END_STRUCT; B : STRUCT a : A; END_STRUCT; END_TYPE\n"
                            "PROGRAM T VAR x : A; END_VAR END_PROGRAM"),
              "t.st:1:6: type 'A' contains itself");
}

TEST(StLanguage, VarInOutWritesTheCallersVariable) {
    // §6.5.2.2 VAR_IN_OUT: the block or function works on the caller's variable itself, whatever
    // its type (an INT, an ARRAY, a STRUCT).
    auto p = started(std::string(types_text) + R"(
FUNCTION_BLOCK Bump
VAR_IN_OUT v : INT; pt : Point; END_VAR
v := v + 1;
pt.x := pt.x + v;
END_FUNCTION_BLOCK

FUNCTION Sum : DINT
VAR_IN_OUT a : ARRAY[1..4] OF DINT; END_VAR
VAR i : INT; END_VAR
FOR i := 1 TO 4 DO Sum := Sum + a[i]; a[i] := 0; END_FOR;
END_FUNCTION

PROGRAM T
VAR x : INT; p : Point; b : Bump; arr : ARRAY[1..4] OF DINT := [1, 2, 3, 4]; total : DINT; END_VAR
b(v := x, pt := p);
b(v := x, pt := p);
total := Sum(arr);
END_PROGRAM)");
    p->run_once(0);
    EXPECT_EQ(get(*p, "x"), 2);
    EXPECT_EQ(p->variables()["p"]["x"], 3); // 1, then 1 + 2
    EXPECT_EQ(get(*p, "total"), 10);
    EXPECT_EQ(get(*p, "arr[3]"), 0);        // the function cleared the caller's array
    const std::string fb = "FUNCTION_BLOCK B VAR_IN_OUT v : INT; END_VAR v := 1; END_FUNCTION_BLOCK\n"
                           "PROGRAM T VAR b : B; x : INT; d : DINT; END_VAR\n";
    EXPECT_EQ(compile_error(fb + "b(v := x + 1);\nEND_PROGRAM"), "t.st:3:8: VAR_IN_OUT 'v' of B needs a variable, not an expression");
    EXPECT_EQ(compile_error(fb + "b();\nEND_PROGRAM"), "t.st:3:1: VAR_IN_OUT 'v' of B is not given (every call names its variable)");
    EXPECT_EQ(compile_error(fb + "b(v := d);\nEND_PROGRAM"), "t.st:3:8: type mismatch: VAR_IN_OUT 'v' of B is INT, 'd' is DINT");
    EXPECT_EQ(compile_error(fb + "x := b.v;\nEND_PROGRAM"), "t.st:3:8: 'v' is not an input or output of B");
    EXPECT_EQ(compile_error("PROGRAM T VAR_IN_OUT v : INT; END_VAR END_PROGRAM"),
              "t.st:1:11: VAR_IN_OUT in a PROGRAM (nothing calls a PROGRAM to give it a variable)");
}

TEST(StLanguage, StringsHoldTextUpToTheirLength) {
    // §6.4.2 STRING[n]: at most n characters, a longer value cut; §6.3.3 '$' escapes; Table 43's
    // LEN, LEFT, RIGHT, MID, CONCAT, FIND (positions from 1); comparisons by character code.
    auto p = started(R"(
PROGRAM T
VAR s : STRING[5] := 'abcdefg'; t : STRING; u : STRING[20]; n, f, g : INT; lt, eq : BOOL;
    q : STRING[4] := '$'$41$$'; END_VAR
t := CONCAT(s, '-', 'xyz');
u := MID(t, 3, 2);
n := LEN(t);
f := FIND(t, 'xy');
g := FIND(t, 'q');
lt := 'abc' < 'abd';
eq := LEFT(t, 2) = 'ab' AND RIGHT(t, 3) = 'xyz';
END_PROGRAM)");
    p->run_once(0);
    const auto v = p->variables();
    EXPECT_EQ(v["s"], "abcde");       // cut to 5
    EXPECT_EQ(v["t"], "abcde-xyz");
    EXPECT_EQ(v["u"], "bcd");         // 3 characters from the 2nd
    EXPECT_EQ(v["q"], "'A$");         // $' $41 $$
    EXPECT_EQ(get(*p, "n"), 9);
    EXPECT_EQ(get(*p, "f"), 7);
    EXPECT_EQ(get(*p, "g"), 0);
    EXPECT_EQ(get(*p, "lt"), 1);
    EXPECT_EQ(get(*p, "eq"), 1);
    EXPECT_EQ(compile_error("PROGRAM T VAR s : STRING; i : INT; END_VAR\ni := s;\nEND_PROGRAM"),
              "t.st:2:6: type mismatch: the value assigned to 'i' must be INT, not STRING[80]");
    EXPECT_EQ(compile_error("PROGRAM T VAR s : STRING; END_VAR\ns := s + 'a';\nEND_PROGRAM"),
              "t.st:2:8: type mismatch: '+' is not defined for STRING[80] and STRING[1] (CONCAT joins strings)");
    auto q = run_body("s : STRING := 'abcdef'; i, d, r : STRING;",
                      "i := INSERT(s, 'XY', 2); d := DELETE(s, 2, 3); r := REPLACE(s, 'Z', 3, 2);");
    EXPECT_EQ(q->variables()["i"], "abXYcdef"); // after the 2nd character
    EXPECT_EQ(q->variables()["d"], "abef");     // 2 characters from the 3rd
    EXPECT_EQ(q->variables()["r"], "aZef");     // 3 characters from the 2nd become 'Z'
    auto bad = run_body("s : STRING := 'abc'; t : STRING; p : INT := 5;", "t := MID(s, 1, p);");
    EXPECT_EQ(bad->error(), "t.st:5:6: MID position P = 5 outside 1..4");
}

// ---- what the subset leaves out: an error that names it ----------------------------------------------

TEST(StLanguage, ConstructsOutsideTheSubsetAreNamed) {
    const std::pair<const char*, const char*> cases[] = {
        {"PROGRAM T VAR p : POINTER TO INT; END_VAR END_PROGRAM", "t.st:1:19: POINTER TO is not supported (docs/st.md)"},
        {"PROGRAM T VAR p : REF_TO INT; END_VAR END_PROGRAM", "t.st:1:19: REF_TO is not supported (docs/st.md)"},
        {"PROGRAM T VAR p : REFERENCE TO INT; END_VAR END_PROGRAM", "t.st:1:19: REFERENCE TO is not supported (docs/st.md)"},
        {"PROGRAM T VAR_TEMP x : INT; END_VAR END_PROGRAM",
         "t.st:1:11: this variable section (VAR_TEMP, VAR_EXTERNAL, VAR_ACCESS, VAR_CONFIG) is not supported (docs/st.md)"},
        {"PROGRAM T VAR RETAIN x : INT; END_VAR END_PROGRAM",
         "t.st:1:15: RETAIN, NON_RETAIN, PERSISTENT is not supported (docs/st.md)"},
        {"PROGRAM T VAR x AT %IX0.0 : BOOL; END_VAR END_PROGRAM", "t.st:1:17: AT (a located variable) is not supported (docs/st.md)"},
        {"PROGRAM T VAR a : ARRAY[1..2, 1..2] OF INT; END_VAR END_PROGRAM",
         "t.st:1:29: an ARRAY of more than one dimension is not supported (docs/st.md)"},
        {"PROGRAM T VAR x : SINT; END_VAR END_PROGRAM", "t.st:1:19: SINT is not supported (docs/st.md)"},
        {"PROGRAM T VAR x : WSTRING; END_VAR END_PROGRAM", "t.st:1:19: WSTRING is not supported (docs/st.md)"},
        {"PROGRAM T VAR x : (A, B); END_VAR END_PROGRAM",
         "t.st:1:19: an enumeration declared in a variable's type (declare it in TYPE ... END_TYPE) is not supported (docs/st.md)"},
        {"PROGRAM T VAR x : DINT; END_VAR x := ADR(x); END_PROGRAM", "t.st:1:38: ADR is not supported (docs/st.md)"},
        {"PROGRAM T VAR x : DINT; END_VAR x := x^; END_PROGRAM", "t.st:1:39: the dereference '^' is not supported (docs/st.md)"},
        {"PROGRAM T VAR x : DINT; END_VAR {attribute 'hide'} END_PROGRAM", "t.st:1:33: a pragma { } is not supported (docs/st.md)"},
        {"PROGRAM T VAR x : BOOL; END_VAR x := D#2020-01-01 = D#2020-01-01; END_PROGRAM",
         "t.st:1:38: a DATE, TIME_OF_DAY, DATE_AND_TIME or LTIME literal is not supported (docs/st.md)"},
        {"PROGRAM T JMP later; END_PROGRAM", "t.st:1:11: JMP (jumps and labels) is not supported (docs/st.md)"},
        {"CLASS C END_CLASS", "t.st:1:1: CONFIGURATION, RESOURCE, CLASS, INTERFACE, NAMESPACE (one task, no OOP) is not supported (docs/st.md)"},
        {"FUNCTION_BLOCK B EXTENDS A END_FUNCTION_BLOCK",
         "t.st:1:18: EXTENDS, IMPLEMENTS (the OOP extensions) is not supported (docs/st.md)"},
        {"FUNCTION_BLOCK B METHOD M END_METHOD END_FUNCTION_BLOCK",
         "t.st:1:18: METHOD, PROPERTY, ACTION (the OOP extensions) is not supported (docs/st.md)"},
        {"PROGRAM T VAR x : INT(0..100); END_VAR END_PROGRAM",
         "t.st:1:22: a subrange type such as INT(0..100) is not supported (docs/st.md)"},
        {"PROGRAM T VAR x, y : BOOL; END_VAR x S= y; END_PROGRAM",
         "t.st:1:38: S=, R=, REF= (set, reset and reference assignments) is not supported (docs/st.md)"},
        {"PROGRAM T VAR s : STRING; i : INT; END_VAR s := INT_TO_STRING(i); END_PROGRAM",
         "t.st:1:49: INT_TO_STRING: a conversion to or from STRING is not supported (docs/st.md)"},
        {"PROGRAM T VAR g : AXES_GROUP_REF; END_VAR END_PROGRAM",
         "t.st:1:19: AXES_GROUP_REF is not supported: rcsim has no axes group object; the interpolating blocks take "
         "their group's axes as AxisX, AxisY (AxisZ, AxisU) inputs (docs/st.md \"Motion blocks\")"},
        {"PROGRAM T VAR s : STRING; END_VAR s := \"wide\"; END_PROGRAM",
         "t.st:1:40: a WSTRING literal \"...\" is not supported (docs/st.md)"},
    };
    for (const auto& [text, want] : cases) EXPECT_EQ(compile_error(text), want) << text;
}

// ---- the examples of docs/st.md ---------------------------------------------------------------------

TEST(StLanguage, TheDocsExamplesRun) {
    // Every ```st block of docs/st.md followed by <!-- st-expect: {json} --> compiles, its first
    // PROGRAM runs once, and each variable named holds what the page says.
    const std::string doc = rcsim::test::slurp(std::filesystem::path(RCSIM_SOURCE_DIR) / "docs/st.md");
    const std::string open = "```st\n", expect = "<!-- st-expect: ";
    int examples = 0;
    for (std::size_t at = doc.find(open); at != std::string::npos; at = doc.find(open, at + 1)) {
        const std::size_t body = at + open.size(), end = doc.find("```\n", body);
        ASSERT_NE(end, std::string::npos);
        const std::size_t e = end + 4;
        ASSERT_EQ(doc.compare(e, expect.size(), expect), 0) << "an ```st block of docs/st.md without st-expect";
        const std::size_t close = doc.find(" -->", e);
        const auto want = nlohmann::json::parse(doc.substr(e + expect.size(), close - e - expect.size()));
        const std::string text = doc.substr(body, end - body);
        std::unique_ptr<Unit> unit = compile(text, "st.md", 0);
        ASSERT_FALSE(unit->program_names.empty());
        auto p = started(text, unit->program_names.front());
        p->run_once(0);
        ASSERT_TRUE(p->running()) << p->error();
        const auto vars = p->variables();
        for (const auto& [name, value] : want.items()) EXPECT_EQ(vars.at(name), value) << name << " in\n" << text;
        ++examples;
    }
    EXPECT_GE(examples, 3);
}

} // namespace
