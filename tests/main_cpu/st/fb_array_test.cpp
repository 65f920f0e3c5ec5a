// Arrays of function block instances and instance initialisers (IEC 61131-3 3rd ed. §6.5.2.2:
// an FB instance is declared like a variable, so an ARRAY OF one and `t : TON := (PT := ...)`
// are declarations like any other; issue #49 item 8). Timings from TON's Table 46 definition:
// Q rises when IN has been TRUE for PT.
#include "tests/main_cpu/st/st_test.h"

using namespace rcsim::st;
using namespace rcsim::st::test;

namespace {

const char* three_timers = R"(
PROGRAM T
VAR t : ARRAY[1..3] OF TON; i : INT; done : ARRAY[1..3] OF BOOL; n : INT; END_VAR
n := 0;
FOR i := 1 TO 3 DO
    t[i](IN := TRUE, PT := T#10ms * i);
    done[i] := t[i].Q;
    IF t[i].Q THEN n := n + 1; END_IF;
END_FOR;
END_PROGRAM)";

TEST(StFbArrays, EachElementIsItsOwnInstance) {
    // PT of t[i] is i * 10 ms and IN is TRUE from t = 0: at 15 ms only t[1] has timed out, at
    // 25 ms t[1] and t[2], at 30 ms all three (ET >= PT).
    auto p = started(three_timers);
    p->run_once(0);
    EXPECT_EQ(p->value("n").i, 0);
    p->run_once(15000);
    EXPECT_EQ(p->value("n").i, 1);
    EXPECT_EQ(p->value("done[1]").i, 1);
    EXPECT_EQ(p->value("t[2].Q").i, 0);
    p->run_once(25000);
    EXPECT_EQ(p->value("n").i, 2);
    EXPECT_EQ(p->value("t[2].ET").i, 20000); // ET stops at PT
    p->run_once(30000);
    EXPECT_EQ(p->value("n").i, 3);
    EXPECT_EQ(p->variables()["t[3].Q"], true);
}

TEST(StFbArrays, AnIndexOutsideTheBoundsStopsTheProgram) {
    auto p = started(R"(
PROGRAM T
VAR t : ARRAY[1..3] OF TON; i : INT := 4; q : BOOL; END_VAR
q := t[2].Q;
t[i](IN := TRUE);
END_PROGRAM)");
    p->run_once(0);
    EXPECT_FALSE(p->running());
    EXPECT_EQ(p->error(), "t.st:5:1: index 4 outside t[1..3]");
    auto r = started(R"(
PROGRAM T
VAR t : ARRAY[1..3] OF TON; i : INT := 0; q : BOOL; END_VAR
q := t[i].Q;
END_PROGRAM)");
    r->run_once(0);
    EXPECT_EQ(r->error(), "t.st:4:6: index 0 outside t[1..3]");
}

TEST(StFbArrays, InstancesTakeTheirInitialInputs) {
    // t[1] starts with PT = 5 ms, t[2] with 20 ms, t[3] (no initial value) with TIME's default,
    // T#0s; u with 1 ms. At 10 ms of IN: t[1] and t[3] are done, t[2] is not, u is.
    auto p = started(R"(
PROGRAM T
VAR t : ARRAY[1..3] OF TON := [(PT := T#5ms), (PT := T#20ms)]; u : TON := (IN := TRUE, PT := T#1ms);
    i : INT; END_VAR
FOR i := 1 TO 3 DO t[i](IN := TRUE); END_FOR;
u();
END_PROGRAM)");
    p->run_once(0);
    p->run_once(10000);
    EXPECT_EQ(p->value("t[1].Q").i, 1);
    EXPECT_EQ(p->value("t[2].Q").i, 0);
    EXPECT_EQ(p->value("t[3].Q").i, 1);
    EXPECT_EQ(p->value("u.Q").i, 1);
    EXPECT_EQ(p->value("t[2].PT").i, 20000);
}

TEST(StFbArrays, AnArrayOfUserBlocksHoldsTheirState) {
    auto p = started(R"(
FUNCTION_BLOCK Counter
VAR_INPUT step : INT; END_VAR
VAR_OUTPUT total : INT; END_VAR
total := total + step;
END_FUNCTION_BLOCK
PROGRAM T
VAR c : ARRAY[0..1] OF Counter; END_VAR
c[0](step := 1);
c[1](step := 10);
END_PROGRAM)");
    for (int k = 0; k < 3; ++k) p->run_once(k * 1000);
    EXPECT_EQ(p->value("c[0].total").i, 3);
    EXPECT_EQ(p->value("c[1].total").i, 30);
}

TEST(StFbArrays, AGlobalArrayIsSharedByEveryPou) {
    // A VAR_GLOBAL array of R_TRIG: the FUNCTION_BLOCK calls g[2], the program reads g[2].Q.
    auto p = started(R"(
VAR_GLOBAL g : ARRAY[1..2] OF R_TRIG; END_VAR
FUNCTION_BLOCK Edge
VAR_INPUT clk : BOOL; END_VAR
g[2](CLK := clk);
END_FUNCTION_BLOCK
PROGRAM T
VAR e : Edge; clk : BOOL; rose : INT; END_VAR
e(clk := clk);
IF g[2].Q THEN rose := rose + 1; END_IF;
END_PROGRAM)");
    const bool clk[] = {false, true, true, false, true};
    for (int k = 0; k < 5; ++k) {
        p->set_value("clk", Value{clk[k] ? 1 : 0, 0});
        p->run_once(k * 1000);
    }
    EXPECT_EQ(p->value("rose").i, 2); // two rising edges of CLK
    EXPECT_EQ(p->value("g[1].Q").i, 0); // never called
}

TEST(StFbArrays, MisusesAreNamed) {
    const std::string head = "PROGRAM T\nVAR t : ARRAY[1..3] OF TON; u : TON; x : BOOL; END_VAR\n";
    EXPECT_EQ(compile_error(head + "t(IN := TRUE);\nEND_PROGRAM"),
              "t.st:3:1: 't' is ARRAY[1..3] OF TON; call one element: t[1](...)");
    EXPECT_EQ(compile_error(head + "u[1](IN := TRUE);\nEND_PROGRAM"),
              "t.st:3:1: 'u' is TON, not an ARRAY of function block instances");
    EXPECT_EQ(compile_error(head + "t[4](IN := TRUE);\nEND_PROGRAM"), "t.st:3:3: index 4 outside t[1..3]");
    EXPECT_EQ(compile_error(head + "x := t[1];\nEND_PROGRAM"),
              "t.st:3:6: 't' is a TON instance, not a value (use its outputs, e.g. t.Q)");
    EXPECT_EQ(compile_error(head + "x := t[1](IN := TRUE);\nEND_PROGRAM"),
              "t.st:3:7: 't[...](...)' calls a function block instance: a statement, not a value");
    EXPECT_EQ(compile_error("PROGRAM T VAR t : ARRAY[1..2] OF TON := [(Q := TRUE)]; END_VAR END_PROGRAM"),
              "t.st:1:43: 'Q' is not an input of TON");
    EXPECT_EQ(compile_error("PROGRAM T VAR t : ARRAY[1..2] OF TON := [(PT := T#1s), (PT := T#1s), (PT := T#1s)]; "
                            "END_VAR END_PROGRAM"),
              "t.st:1:41: 3 initial values for 2 elements of 't'");
    EXPECT_EQ(compile_error("FUNCTION_BLOCK B VAR_INPUT t : ARRAY[1..2] OF TON; END_VAR END_FUNCTION_BLOCK"),
              "t.st:1:32: an ARRAY of function block instances as VAR_INPUT is not supported (docs/st.md); "
              "declare it in VAR");
    // Arrays of blocks holding arrays of blocks multiply: the count is bounded, not the memory.
    EXPECT_EQ(compile_error("FUNCTION_BLOCK B VAR t : ARRAY[1..1000] OF TON; END_VAR END_FUNCTION_BLOCK\n"
                            "PROGRAM T VAR b : ARRAY[1..1000] OF B; END_VAR END_PROGRAM"),
              "t.st:2:15: 'T' would hold more than 65536 function block instances");
}

} // namespace
