// The semantics of the Structured Text subset: operators and their precedence (IEC 61131-3 3rd
// ed. Table 71), integer widths, each statement (§7.3.3), user FUNCTION_BLOCKs and FUNCTIONs,
// and the runtime errors that stop a program. Expected values are worked out from the standard's
// rules in the comments, not taken from a run.
#include "tests/main_cpu/st/st_test.h"

using namespace rcsim::st;
using namespace rcsim::st::test;

namespace {

std::int64_t I(const StProgram& p, const std::string& v) { return p.value(v).i; }
double R(const StProgram& p, const std::string& v) { return p.value(v).r; }

TEST(StOperators, PrecedenceFollowsTable71) {
    auto p = run_body("a, b, e, m, n : DINT; c, d : LREAL; f, g, h, x1, x2 : BOOL;",
                      "a := 2 + 3 * 4;\n"           // * before +: 14
                      "b := (2 + 3) * 4;\n"         // parentheses first: 20
                      "c := -2.0 ** 2.0;\n"         // ** before unary minus: -(4) = -4
                      "d := 2.0 ** 3.0 ** 2.0;\n"   // left to right: (2**3)**2 = 64
                      "e := 7 MOD 3 + 1;\n"         // MOD before +: 1 + 1 = 2
                      "f := NOT TRUE OR TRUE;\n"    // NOT binds tighter than OR: FALSE OR TRUE
                      "g := TRUE OR TRUE XOR TRUE;\n" // XOR before OR: TRUE OR FALSE = TRUE
                      "h := TRUE XOR TRUE AND FALSE;\n" // AND before XOR: TRUE XOR FALSE = TRUE
                      "x1 := 1 < 2 = TRUE;\n"       // comparison before equality: TRUE = TRUE
                      "x2 := 10 - 4 - 3 = 3;\n"     // left to right: (10-4)-3 = 3
                      "m := -7 / 2;\n"              // integer division truncates: -3
                      "n := -7 MOD 2;");            // the sign of the dividend: -1
    EXPECT_EQ(I(*p, "a"), 14);
    EXPECT_EQ(I(*p, "b"), 20);
    EXPECT_DOUBLE_EQ(R(*p, "c"), -4.0);
    EXPECT_DOUBLE_EQ(R(*p, "d"), 64.0);
    EXPECT_EQ(I(*p, "e"), 2);
    EXPECT_EQ(I(*p, "f"), 1);
    EXPECT_EQ(I(*p, "g"), 1);
    EXPECT_EQ(I(*p, "h"), 1);
    EXPECT_EQ(I(*p, "x1"), 1);
    EXPECT_EQ(I(*p, "x2"), 1);
    EXPECT_EQ(I(*p, "m"), -3);
    EXPECT_EQ(I(*p, "n"), -1);
}

TEST(StOperators, IntegersWrapAtTheirWidth) {
    // INT is 16 bits (-32768..32767), DINT 32, UDINT 32 unsigned: two's complement wrap.
    auto p = run_body("i : INT := 32767; d : DINT := 2147483647; u : UDINT := 0;", "i := i + 1; d := d + 1; u := u - 1;");
    EXPECT_EQ(I(*p, "i"), -32768);
    EXPECT_EQ(I(*p, "d"), -2147483648LL);
    EXPECT_EQ(I(*p, "u"), 4294967295LL);
}

TEST(StOperators, WideningMixesIntWithDintAndReal) {
    // INT widens to DINT and to REAL implicitly (IEC 61131-3 Figure 11); REAL is single precision.
    auto p = run_body("i : INT := 300; d : DINT := 100000; r : REAL; s : DINT; q : REAL := 0.1;",
                      "s := i + d; r := i; q := q * 3.0;");
    EXPECT_EQ(I(*p, "s"), 100300);
    EXPECT_DOUBLE_EQ(R(*p, "r"), 300.0);
    EXPECT_DOUBLE_EQ(R(*p, "q"), static_cast<double>(0.1f * 3.0f)); // float arithmetic, not double
}

TEST(StOperators, TimeArithmeticAndConversions) {
    auto p = run_body("a, b, c : TIME; ms : DINT; r3, r4 : INT; tr : DINT; big : TIME := T#1h2m3s4ms;",
                      "a := T#1s + T#500ms;\n"   // 1.5 s
                      "b := T#1s * 2.5;\n"       // TIME * number: 2.5 s
                      "c := T#1s - T#1500ms;\n"  // negative durations are allowed: -0.5 s
                      "ms := TIME_TO_DINT(T#1s500ms);\n" // TIME converts as milliseconds: 1500
                      "r3 := REAL_TO_INT(1.6); r4 := REAL_TO_INT(-1.6);\n" // round to nearest: 2, -2
                      "tr := TRUNC(-1.6);");     // TRUNC cuts towards zero: -1
    EXPECT_EQ(I(*p, "a"), 1'500'000);
    EXPECT_EQ(I(*p, "b"), 2'500'000);
    EXPECT_EQ(I(*p, "c"), -500'000);
    EXPECT_EQ(I(*p, "ms"), 1500);
    EXPECT_EQ(I(*p, "r3"), 2);
    EXPECT_EQ(I(*p, "r4"), -2);
    EXPECT_EQ(I(*p, "tr"), -1);
    EXPECT_EQ(I(*p, "big"), ((3600 + 120 + 3) * 1000 + 4) * 1000LL);
}

TEST(StOperators, LiteralsInEveryBase) {
    auto p = run_body("a, b, c, d : DINT; r : LREAL;", "a := 16#FF; b := 2#1010; c := 8#17; d := 1_000_000; r := 1.5E3;");
    EXPECT_EQ(I(*p, "a"), 255);
    EXPECT_EQ(I(*p, "b"), 10);
    EXPECT_EQ(I(*p, "c"), 15);
    EXPECT_EQ(I(*p, "d"), 1000000);
    EXPECT_DOUBLE_EQ(R(*p, "r"), 1500.0);
}

TEST(StStatements, IfTakesTheFirstTrueBranch) {
    auto p = run_body("x : INT := 5; r1, r2, r3 : INT;",
                      "IF x > 10 THEN r1 := 1; ELSIF x > 3 THEN r1 := 2; ELSIF x > 0 THEN r1 := 3; ELSE r1 := 4; END_IF;\n"
                      "IF x > 10 THEN r2 := 1; ELSE r2 := 9; END_IF;\n"
                      "IF x > 10 THEN r3 := 1; END_IF;");
    EXPECT_EQ(I(*p, "r1"), 2); // 5 > 3 is the first true condition
    EXPECT_EQ(I(*p, "r2"), 9);
    EXPECT_EQ(I(*p, "r3"), 0);
}

TEST(StStatements, CaseMatchesValuesListsRangesAndElse) {
    const char* body = "CASE s OF 1: r := 10; 2, 4: r := 20; 5..7: r := 30; ELSE r := 99; END_CASE;";
    for (auto [sel, want] : {std::pair{1, 10}, {2, 20}, {4, 20}, {6, 30}, {7, 30}, {3, 99}, {8, 99}}) {
        auto p = run_body("s : INT := " + std::to_string(sel) + "; r : INT;", body);
        EXPECT_EQ(I(*p, "r"), want) << "selector " << sel;
    }
}

TEST(StStatements, ForCountsUpDownAndLeavesTheVariableOnePastTheEnd) {
    auto p = run_body("i, j, k, sum, n, m : INT;",
                      "FOR i := 1 TO 10 DO sum := sum + i; END_FOR;\n" // 55; i ends at 11
                      "FOR j := 10 TO 1 BY -2 DO n := n + 1; END_FOR;\n" // 10, 8, 6, 4, 2: 5 runs, j = 0
                      "FOR k := 1 TO 0 DO m := m + 1; END_FOR;");       // the test comes first: no run
    EXPECT_EQ(I(*p, "sum"), 55);
    EXPECT_EQ(I(*p, "i"), 11);
    EXPECT_EQ(I(*p, "n"), 5);
    EXPECT_EQ(I(*p, "j"), 0);
    EXPECT_EQ(I(*p, "m"), 0);
    EXPECT_EQ(I(*p, "k"), 1);
}

TEST(StStatements, ForToTheTypeLimitEnds) {
    // FOR i := 32760 TO 32767 on an INT: 8 runs; a 16-bit counter would wrap and never end.
    auto p = run_body("i, n : INT;", "FOR i := 32760 TO 32767 DO n := n + 1; END_FOR;");
    EXPECT_EQ(I(*p, "n"), 8);
    EXPECT_TRUE(p->running());
}

TEST(StStatements, WhileTestsFirstRepeatRunsOnce) {
    auto p = run_body("w, r, x : INT := 0;",
                      "WHILE w < 3 DO w := w + 1; END_WHILE;\n"
                      "WHILE FALSE DO x := 1; END_WHILE;\n"
                      "REPEAT r := r + 1; UNTIL TRUE END_REPEAT;");
    EXPECT_EQ(I(*p, "w"), 3);
    EXPECT_EQ(I(*p, "x"), 0);
    EXPECT_EQ(I(*p, "r"), 1); // the body runs before the first test
}

TEST(StStatements, ExitLeavesOnlyTheInnermostLoop) {
    auto p = run_body("i, j, inner, outer : INT;",
                      "FOR i := 1 TO 3 DO\n  outer := outer + 1;\n"
                      "  FOR j := 1 TO 100 DO IF j = 2 THEN EXIT; END_IF; inner := inner + 1; END_FOR;\nEND_FOR;");
    EXPECT_EQ(I(*p, "outer"), 3); // the outer loop runs on
    EXPECT_EQ(I(*p, "inner"), 3); // one inner run before each EXIT
}

TEST(StStatements, ReturnEndsTheCycleAndTheNextCycleStartsAtTheTop) {
    auto p = started("PROGRAM T VAR a, b : INT; END_VAR a := a + 1; IF a < 3 THEN RETURN; END_IF; b := b + 1; END_PROGRAM");
    p->run_once(0);
    p->run_once(1000);
    EXPECT_EQ(I(*p, "a"), 2);
    EXPECT_EQ(I(*p, "b"), 0);
    p->run_once(2000);
    EXPECT_EQ(I(*p, "b"), 1);
}

TEST(StStatements, VariablesKeepTheirValuesFromCycleToCycle) {
    auto p = started("PROGRAM T VAR n : DINT := 10; END_VAR n := n + 1; END_PROGRAM");
    for (int k = 0; k < 5; ++k) p->run_once(k * 1000);
    EXPECT_EQ(I(*p, "n"), 15);
    EXPECT_EQ(p->cycles(), 5u);
}

TEST(StPou, FunctionBlockInstancesKeepStateAndPassNamedInputsAndOutputs) {
    auto p = started(R"(
FUNCTION_BLOCK ACC
VAR_INPUT add : DINT; END_VAR
VAR_OUTPUT total : DINT; calls : INT; END_VAR
total := total + add; calls := calls + 1;
END_FUNCTION_BLOCK
PROGRAM T
VAR a, b : ACC; out_a : DINT; END_VAR
a(add := 5, total => out_a);
a(add := 7);
b(add := 1);
END_PROGRAM)");
    p->run_once(0);
    EXPECT_EQ(I(*p, "a.total"), 12); // each instance has its own total
    EXPECT_EQ(I(*p, "a.calls"), 2);
    EXPECT_EQ(I(*p, "b.total"), 1);
    EXPECT_EQ(I(*p, "out_a"), 5); // => copied after the first call
}

TEST(StPou, FunctionsTakePositionalOrNamedInputsAndStartFreshEachCall) {
    auto p = started(R"(
FUNCTION SCALE : LREAL
VAR_INPUT x : LREAL; k : LREAL := 2.0; END_VAR
VAR n : INT; END_VAR
n := n + 1;
SCALE := x * k + n;
END_FUNCTION
PROGRAM T
VAR a, b, c : LREAL; END_VAR
a := SCALE(3.0, 4.0);
b := SCALE(x := 3.0);
c := SCALE(k := 1.0, x := 5.0);
END_PROGRAM)");
    p->run_once(0);
    EXPECT_DOUBLE_EQ(R(*p, "a"), 13.0); // 3*4 + 1: n starts at 0 in every call
    EXPECT_DOUBLE_EQ(R(*p, "b"), 7.0);  // k keeps its initial value 2
    EXPECT_DOUBLE_EQ(R(*p, "c"), 6.0);
}

TEST(StPou, GlobalsAreSharedAndArraysIndexFromTheirLowerBound) {
    auto p = started(R"(
VAR_GLOBAL g : INT := 7; END_VAR
FUNCTION_BLOCK BUMP
g := g + 1;
END_FUNCTION_BLOCK
PROGRAM T
VAR b : BUMP; a : ARRAY[1..3] OF INT := [10, 20]; s : INT; i : INT; END_VAR
b();
FOR i := 1 TO 3 DO s := s + a[i]; END_FOR;
a[3] := g;
END_PROGRAM)");
    p->run_once(0);
    EXPECT_EQ(I(*p, "g"), 8);
    EXPECT_EQ(I(*p, "s"), 30); // a[3] starts at 0: fewer initial values than elements
    EXPECT_EQ(I(*p, "a[3]"), 8);
}

TEST(StPou, StandardFunctions) {
    auto p = run_body("a : INT; b : LREAL; c, d, e : DINT; f : LREAL;",
                      "a := ABS(-5); b := SQRT(16.0); c := MIN(4, 2, 8); d := MAX(4, 2, 8); e := LIMIT(0, 15, 10);"
                      "f := INT_TO_LREAL(a) / 2.0;");
    EXPECT_EQ(I(*p, "a"), 5);
    EXPECT_DOUBLE_EQ(R(*p, "b"), 4.0);
    EXPECT_EQ(I(*p, "c"), 2);
    EXPECT_EQ(I(*p, "d"), 8);
    EXPECT_EQ(I(*p, "e"), 10);
    EXPECT_DOUBLE_EQ(R(*p, "f"), 2.5);
}

// The rest of IEC 61131-3 Table 22's numeric functions and EXPT (Table 24): values from their
// mathematical definitions (LOG is base 10; ATAN2(Y, X) is the angle of the point (X, Y)).
TEST(StPou, TheRealFunctionsOfTable22AndExpt) {
    auto p = run_body("a, b, c, d, e, f, g, h, i : LREAL; r : REAL;",
                      "a := EXP(0.0); b := LN(1.0); c := LOG(1000.0); d := TAN(0.0); e := ASIN(1.0);"
                      "f := ACOS(1.0); g := ATAN2(1.0, -1.0); h := EXPT(2.0, 10); i := EXP(LN(7.5));"
                      "r := EXPT(REAL#3.0, 2);");
    EXPECT_DOUBLE_EQ(R(*p, "a"), 1.0);
    EXPECT_DOUBLE_EQ(R(*p, "b"), 0.0);
    EXPECT_DOUBLE_EQ(R(*p, "c"), 3.0);
    EXPECT_DOUBLE_EQ(R(*p, "d"), 0.0);
    EXPECT_DOUBLE_EQ(R(*p, "e"), M_PI / 2);
    EXPECT_DOUBLE_EQ(R(*p, "f"), 0.0);
    EXPECT_DOUBLE_EQ(R(*p, "g"), 3 * M_PI / 4);
    EXPECT_DOUBLE_EQ(R(*p, "h"), 1024.0);
    EXPECT_NEAR(R(*p, "i"), 7.5, 1e-12);
    EXPECT_DOUBLE_EQ(R(*p, "r"), 9.0);
    EXPECT_EQ(compile_error("PROGRAM T\nVAR x : LREAL; END_VAR\nx := ATAN2(1.0);\nEND_PROGRAM"),
              "t.st:3:6: ATAN2 takes 2 arguments, not 1");
    EXPECT_NE(compile_error("PROGRAM T\nVAR x : LREAL; s : STRING; END_VAR\nx := LN(s);\nEND_PROGRAM")
                  .find("type mismatch: LN needs numbers, not STRING"),
              std::string::npos);
}

// §6.4.4.4: an ARRAY OF a STRUCT starts from a list of the STRUCTs' initial values; elements left
// out keep the type's own initial values.
TEST(StPou, AnArrayOfStructsTakesAListOfMemberInitialValues) {
    auto p = started("TYPE P : STRUCT x : INT; y : INT := 9; END_STRUCT; END_TYPE\n"
                     "PROGRAM T\nVAR pts : ARRAY[1..3] OF P := [(x := 1, y := 2), (x := 3)]; a, b, c, d, e : INT; END_VAR\n"
                     "a := pts[1].x; b := pts[1].y; c := pts[2].x; d := pts[2].y; e := pts[3].y;\nEND_PROGRAM");
    p->run_once(0);
    EXPECT_EQ(I(*p, "a"), 1);
    EXPECT_EQ(I(*p, "b"), 2);
    EXPECT_EQ(I(*p, "c"), 3);
    EXPECT_EQ(I(*p, "d"), 9);
    EXPECT_EQ(I(*p, "e"), 9);
    EXPECT_EQ(compile_error("TYPE P : STRUCT x : INT; END_STRUCT; END_TYPE\n"
                            "PROGRAM T\nVAR pts : ARRAY[1..2] OF P := [(z := 1)]; END_VAR\nEND_PROGRAM"),
              "t.st:3:33: 'z' is not a member of P");
}

// ---- runtime errors ------------------------------------------------------------------------------

// Outside its domain a function has no real value: the program stops as for a division by zero,
// rather than carry a NaN or an infinity into a set-point.
TEST(StRuntime, ARealFunctionWithoutAFiniteResultStopsTheProgramNamingTheCall) {
    const std::pair<const char*, const char*> cases[] = {
        {"LN(z)", "t.st:3:6: LN(0) has no finite real result"},
        {"ASIN(z + 2.0)", "t.st:3:6: ASIN(2) has no finite real result"},
        {"EXPT(z - 8.0, 0.5)", "t.st:3:6: EXPT(-8, 0.5) has no finite real result"},
        {"EXP(z + 1000.0)", "t.st:3:6: EXP(1000) has no finite real result"},
    };
    for (const auto& [call, message] : cases) {
        auto p = started(std::string("PROGRAM T\nVAR x, z : LREAL; END_VAR\nx := ") + call + ";\nEND_PROGRAM");
        p->run_once(0);
        EXPECT_FALSE(p->running()) << call;
        EXPECT_EQ(p->error(), message);
    }
}

TEST(StRuntime, DivisionByZeroStopsTheProgramNamingThePosition) {
    auto p = started("PROGRAM T\nVAR a : INT := 1; z : INT; after : BOOL; END_VAR\na := a / z;\nafter := TRUE;\nEND_PROGRAM");
    p->run_once(0);
    EXPECT_FALSE(p->running());
    EXPECT_EQ(p->error(), "t.st:3:8: division by zero"); // the '/' of line 3
    EXPECT_EQ(I(*p, "after"), 0);
    p->run_once(1000); // a stopped program does not run
    EXPECT_EQ(p->cycles(), 1u);
}

TEST(StRuntime, RealDivisionByZeroAndModByZeroAreErrorsToo) {
    auto p = started("PROGRAM T\nVAR r : REAL := 1.0; z : REAL; END_VAR\nr := r / z;\nEND_PROGRAM");
    p->run_once(0);
    EXPECT_EQ(p->error(), "t.st:3:8: division by zero");
    auto q = started("PROGRAM T\nVAR i : INT := 1; z : INT; END_VAR\ni := i MOD z;\nEND_PROGRAM");
    q->run_once(0);
    EXPECT_EQ(q->error(), "t.st:3:8: MOD by zero");
}

TEST(StRuntime, ArrayIndexOutsideTheBoundsStops) {
    auto p = started("PROGRAM T\nVAR a : ARRAY[0..9] OF INT; i : INT := 10; END_VAR\na[i] := 1;\nEND_PROGRAM");
    p->run_once(0);
    EXPECT_FALSE(p->running());
    EXPECT_EQ(p->error(), "t.st:3:1: index 10 outside a[0..9]");
}

TEST(StRuntime, AnEndlessLoopStopsAtTheStatementBudget) {
    StProgram::Config cfg;
    cfg.budget = 1000;
    auto p = started("PROGRAM T\nVAR n : DINT; END_VAR\nWHILE TRUE DO\n  n := n + 1;\nEND_WHILE;\nEND_PROGRAM", "T", cfg);
    p->run_once(0);
    EXPECT_FALSE(p->running());
    EXPECT_EQ(p->error(), "t.st:4:3: more than 1000 statements in one cycle (an endless loop?); the program is stopped");
    // The WHILE statement and each iteration count, then each assignment: well under 1000 runs.
    EXPECT_LT(I(*p, "n"), 1000);
    EXPECT_GT(I(*p, "n"), 300);
}

TEST(StRuntime, ABoundedLoopUnderTheBudgetRunsEveryCycle) {
    StProgram::Config cfg;
    cfg.budget = 1000;
    auto p = started("PROGRAM T\nVAR i, n : DINT; END_VAR\nFOR i := 1 TO 100 DO n := n + 1; END_FOR;\nEND_PROGRAM", "T", cfg);
    for (int k = 0; k < 3; ++k) p->run_once(k);
    EXPECT_TRUE(p->running());
    EXPECT_EQ(I(*p, "n"), 300);
    EXPECT_EQ(p->max_statements(), 201u); // the FOR, then per run its iteration and the assignment
}

// What one execution reports to the main CPU's cost model (ProgramWork): the budget's count.
TEST(StRuntime, AnExecutionReportsTheStatementsItExecuted) {
    auto p = started("PROGRAM T\nVAR x, y, w : INT; END_VAR\nx := 1;\n"
                     "IF x = 1 THEN y := 1; y := 2; ELSE y := 3; END_IF;\n"
                     "WHILE w < 3 DO w := w + 1; END_WHILE;\nEND_PROGRAM");
    const rcsim::ProgramWork w = p->run_once(0);
    // x := 1 (1); the IF and its taken branch's two assignments (3); the WHILE, its three
    // iterations and their three assignments (7).
    EXPECT_EQ(w.statements, 11u);
    EXPECT_EQ(w.motion_calls, 0u);
    EXPECT_EQ(p->max_statements(), 11u);
    p->stop();
    EXPECT_EQ(p->run_once(1000).statements, 0u); // a stopped program executes nothing
}

TEST(StRuntime, StartIsColdAndRefusesUnknownNames) {
    auto p = started("PROGRAM T VAR n : INT; END_VAR n := n + 1; END_PROGRAM");
    p->run_once(0);
    EXPECT_EQ(p->start("T"), "program 'T' is running");
    p->stop();
    EXPECT_EQ(p->start("nope"), "no PROGRAM named 'nope'");
    EXPECT_EQ(p->start("t"), ""); // names are case-insensitive
    EXPECT_EQ(I(*p, "n"), 0);    // from the initial values again
}

} // namespace
