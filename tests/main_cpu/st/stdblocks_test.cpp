// The IEC 61131-3 standard function blocks of the subset, cycle by cycle against the standard's
// definitions (3rd ed. §6.6.3.5: SR/RS Table 43, R_TRIG/F_TRIG Table 44, CTU/CTD/CTUD Table 45,
// TON/TOF/TP Table 46 and their timing diagrams). The test drives the inputs between cycles; each expectation is derived in a
// comment.
#include "tests/main_cpu/st/st_test.h"

using namespace rcsim::st;
using namespace rcsim::st::test;

namespace {

void set_bool(StProgram& p, const char* v, bool b) { p.set_value(v, Value{b ? 1 : 0, 0}); }
bool get_bool(const StProgram& p, const char* v) { return p.value(v).i != 0; }

const char* trig_program = R"(
PROGRAM T
VAR clk : BOOL; r : R_TRIG; f : F_TRIG; rq, fq : BOOL; END_VAR
r(CLK := clk, Q => rq);
f(CLK := clk, Q => fq);
END_PROGRAM)";

TEST(StStandardBlocks, RTrigIsTrueForOneCallAfterEachRisingEdge) {
    auto p = started(trig_program);
    // CLK:  F  T  T  F  T       Q = CLK AND NOT (CLK of the previous call, FALSE at first)
    // Q:    F  T  F  F  T
    const bool clk[] = {false, true, true, false, true}, q[] = {false, true, false, false, true};
    for (int k = 0; k < 5; ++k) {
        set_bool(*p, "clk", clk[k]);
        p->run_once(k * 1000);
        EXPECT_EQ(get_bool(*p, "rq"), q[k]) << "call " << k;
    }
}

TEST(StStandardBlocks, FTrigIsTrueForOneCallAfterEachFallingEdgeAndNotAtStart) {
    auto p = started(trig_program);
    // CLK:  F  T  F  F  T  F    Q = NOT CLK AND NOT M, M = NOT CLK of the previous call, TRUE at
    // Q:    F  F  T  F  F  T    first (IEC 61131-8): a CLK that starts FALSE is no falling edge.
    const bool clk[] = {false, true, false, false, true, false}, q[] = {false, false, true, false, false, true};
    for (int k = 0; k < 6; ++k) {
        set_bool(*p, "clk", clk[k]);
        p->run_once(k * 1000);
        EXPECT_EQ(get_bool(*p, "fq"), q[k]) << "call " << k;
    }
}

TEST(StStandardBlocks, CtuCountsRisingEdgesUpToPvAndResets) {
    auto p = started(R"(
PROGRAM T
VAR cu, r : BOOL; c : CTU; END_VAR
c(CU := cu, R := r, PV := 3);
END_PROGRAM)");
    auto step = [&](bool cu, bool r, int k) {
        set_bool(*p, "cu", cu);
        set_bool(*p, "r", r);
        p->run_once(k * 1000);
    };
    int k = 0;
    step(true, false, k++);  // edge 1: CV = 1
    step(true, false, k++);  // still high: no edge, CV = 1
    EXPECT_EQ(p->value("c.CV").i, 1);
    step(false, false, k++);
    step(true, false, k++);  // edge 2
    step(false, false, k++);
    EXPECT_FALSE(get_bool(*p, "c.Q")); // CV = 2 < PV
    step(true, false, k++);  // edge 3: CV = 3 >= PV
    EXPECT_EQ(p->value("c.CV").i, 3);
    EXPECT_TRUE(get_bool(*p, "c.Q"));
    step(true, true, k++);   // R: CV = 0, Q = 0 >= 3 = FALSE
    EXPECT_EQ(p->value("c.CV").i, 0);
    EXPECT_FALSE(get_bool(*p, "c.Q"));
}

const char* timer_program = R"(
PROGRAM T
VAR in : BOOL; on : TON; off : TOF; END_VAR
on(IN := in, PT := T#10ms);
off(IN := in, PT := T#10ms);
END_PROGRAM)";

TEST(StStandardBlocks, TonSetsQWhenInHasBeenTrueForPt) {
    auto p = started(timer_program);
    set_bool(*p, "in", true);
    p->run_once(100'000); // IN rises at t = 100 ms: ET = 0
    EXPECT_EQ(p->value("on.ET").i, 0);
    p->run_once(109'000); // 9 ms: ET = 9 ms < PT, Q = FALSE
    EXPECT_EQ(p->value("on.ET").i, 9'000);
    EXPECT_FALSE(get_bool(*p, "on.Q"));
    p->run_once(110'000); // 10 ms: ET = PT, Q = TRUE
    EXPECT_TRUE(get_bool(*p, "on.Q"));
    p->run_once(150'000); // ET stops at PT
    EXPECT_EQ(p->value("on.ET").i, 10'000);
    set_bool(*p, "in", false);
    p->run_once(151'000); // IN falls: Q = FALSE, ET = 0
    EXPECT_FALSE(get_bool(*p, "on.Q"));
    EXPECT_EQ(p->value("on.ET").i, 0);
    set_bool(*p, "in", true);
    p->run_once(152'000); // a new edge starts from 0
    p->run_once(161'000);
    EXPECT_FALSE(get_bool(*p, "on.Q"));
    EXPECT_EQ(p->value("on.ET").i, 9'000);
}

TEST(StStandardBlocks, TofHoldsQForPtAfterInFalls) {
    auto p = started(timer_program);
    p->run_once(0);
    EXPECT_FALSE(get_bool(*p, "off.Q")); // IN never TRUE: Q = FALSE
    set_bool(*p, "in", true);
    p->run_once(1'000);
    EXPECT_TRUE(get_bool(*p, "off.Q")); // Q follows IN at once
    set_bool(*p, "in", false);
    p->run_once(5'000); // IN falls at 5 ms: timing starts, Q stays TRUE
    EXPECT_TRUE(get_bool(*p, "off.Q"));
    p->run_once(14'000); // 9 ms after the edge: ET = 9 ms
    EXPECT_TRUE(get_bool(*p, "off.Q"));
    EXPECT_EQ(p->value("off.ET").i, 9'000);
    p->run_once(15'000); // 10 ms = PT: Q = FALSE, ET = PT
    EXPECT_FALSE(get_bool(*p, "off.Q"));
    EXPECT_EQ(p->value("off.ET").i, 10'000);
    p->run_once(30'000); // ET stays at PT until IN rises
    EXPECT_EQ(p->value("off.ET").i, 10'000);
    set_bool(*p, "in", true);
    p->run_once(31'000);
    EXPECT_EQ(p->value("off.ET").i, 0);
}

TEST(StStandardBlocks, TpGivesOnePulseOfPtPerRisingEdge) {
    // Figure 15 a (TP): an edge of IN while no pulse runs starts one; Q stays TRUE for PT whatever
    // IN does; an edge during the pulse is ignored. After it ET stays at PT while IN is TRUE and
    // goes to 0 with IN.
    auto p = started(R"(
PROGRAM T
VAR in : BOOL; tp1 : TP; END_VAR
tp1(IN := in, PT := T#10ms);
END_PROGRAM)");
    auto at = [&](bool in, std::int64_t ms) {
        set_bool(*p, "in", in);
        p->run_once(ms * 1000);
    };
    at(true, 100); // edge: Q = TRUE, ET = 0
    EXPECT_TRUE(get_bool(*p, "tp1.Q"));
    EXPECT_EQ(p->value("tp1.ET").i, 0);
    at(false, 104); // IN falls: the pulse goes on
    EXPECT_TRUE(get_bool(*p, "tp1.Q"));
    EXPECT_EQ(p->value("tp1.ET").i, 4'000);
    at(true, 108); // an edge during the pulse: ignored
    EXPECT_TRUE(get_bool(*p, "tp1.Q"));
    EXPECT_EQ(p->value("tp1.ET").i, 8'000);
    at(true, 110); // PT reached: Q = FALSE, ET = PT while IN
    EXPECT_FALSE(get_bool(*p, "tp1.Q"));
    EXPECT_EQ(p->value("tp1.ET").i, 10'000);
    at(true, 130); // IN held: no new pulse, ET stays
    EXPECT_FALSE(get_bool(*p, "tp1.Q"));
    EXPECT_EQ(p->value("tp1.ET").i, 10'000);
    at(false, 131); // IN falls: ET = 0
    EXPECT_EQ(p->value("tp1.ET").i, 0);
    at(true, 140); // a new edge: a new pulse
    EXPECT_TRUE(get_bool(*p, "tp1.Q"));
    at(false, 149);
    EXPECT_TRUE(get_bool(*p, "tp1.Q"));
    at(false, 150); // PT after the edge, IN FALSE: Q = FALSE, ET = 0
    EXPECT_FALSE(get_bool(*p, "tp1.Q"));
    EXPECT_EQ(p->value("tp1.ET").i, 0);
}

TEST(StStandardBlocks, CtdLoadsPvAndCountsDownRisingEdges) {
    // Table 45 CTD: LD loads CV := PV; each rising edge of CD decrements; Q := CV <= 0.
    auto p = started(R"(
PROGRAM T
VAR cd, ld : BOOL; c : CTD; END_VAR
c(CD := cd, LD := ld, PV := 2);
END_PROGRAM)");
    int k = 0;
    auto step = [&](bool cd, bool ld) {
        set_bool(*p, "cd", cd);
        set_bool(*p, "ld", ld);
        p->run_once(k++ * 1000);
    };
    step(false, true); // CV = 2
    EXPECT_EQ(p->value("c.CV").i, 2);
    EXPECT_FALSE(get_bool(*p, "c.Q"));
    step(true, false); // edge: 1
    step(true, false); // held: still 1
    EXPECT_EQ(p->value("c.CV").i, 1);
    step(false, false);
    step(true, false); // edge: 0, Q = TRUE
    EXPECT_EQ(p->value("c.CV").i, 0);
    EXPECT_TRUE(get_bool(*p, "c.Q"));
    step(false, false);
    step(true, false); // CV goes on below 0 (down to PVmin): -1
    EXPECT_EQ(p->value("c.CV").i, -1);
    EXPECT_TRUE(get_bool(*p, "c.Q"));
}

TEST(StStandardBlocks, CtudCountsBothWaysWithQuAndQd) {
    // Table 45 CTUD: R resets (before LD), LD loads PV; an edge of CU counts up, of CD down, both
    // in one call none; QU := CV >= PV, QD := CV <= 0.
    auto p = started(R"(
PROGRAM T
VAR cu, cd, r, ld : BOOL; c : CTUD; END_VAR
c(CU := cu, CD := cd, R := r, LD := ld, PV := 2);
END_PROGRAM)");
    int k = 0;
    auto step = [&](bool cu, bool cd, bool r, bool ld) {
        set_bool(*p, "cu", cu);
        set_bool(*p, "cd", cd);
        set_bool(*p, "r", r);
        set_bool(*p, "ld", ld);
        p->run_once(k++ * 1000);
    };
    step(false, false, false, false); // CV = 0: QD
    EXPECT_TRUE(get_bool(*p, "c.QD"));
    EXPECT_FALSE(get_bool(*p, "c.QU"));
    step(true, false, false, false); // up: 1, neither
    EXPECT_EQ(p->value("c.CV").i, 1);
    EXPECT_FALSE(get_bool(*p, "c.QD"));
    EXPECT_FALSE(get_bool(*p, "c.QU"));
    step(false, false, false, false);
    step(true, false, false, false); // up: 2 = PV: QU
    EXPECT_EQ(p->value("c.CV").i, 2);
    EXPECT_TRUE(get_bool(*p, "c.QU"));
    step(false, false, false, false);
    step(true, true, false, false); // both edges in one call: no change
    EXPECT_EQ(p->value("c.CV").i, 2);
    step(false, false, false, false);
    step(false, true, false, false); // down: 1
    EXPECT_EQ(p->value("c.CV").i, 1);
    step(false, false, true, true); // R and LD: R wins, CV = 0
    EXPECT_EQ(p->value("c.CV").i, 0);
    step(false, false, false, true); // LD: CV = PV
    EXPECT_EQ(p->value("c.CV").i, 2);
    EXPECT_TRUE(get_bool(*p, "c.QU"));
}

TEST(StStandardBlocks, SrIsSetDominantAndRsResetDominant) {
    // Table 43: SR Q1 := S1 OR (NOT R AND Q1); RS Q1 := NOT R1 AND (S OR Q1).
    auto p = started(R"(
PROGRAM T
VAR s, r : BOOL; sr1 : SR; rs1 : RS; END_VAR
sr1(S1 := s, R := r);
rs1(S := s, R1 := r);
END_PROGRAM)");
    int k = 0;
    auto step = [&](bool s, bool r) {
        set_bool(*p, "s", s);
        set_bool(*p, "r", r);
        p->run_once(k++ * 1000);
    };
    step(true, true); // both: SR sets, RS resets
    EXPECT_TRUE(get_bool(*p, "sr1.Q1"));
    EXPECT_FALSE(get_bool(*p, "rs1.Q1"));
    step(true, false); // set: both TRUE
    EXPECT_TRUE(get_bool(*p, "rs1.Q1"));
    step(false, false); // neither: both hold
    EXPECT_TRUE(get_bool(*p, "sr1.Q1"));
    EXPECT_TRUE(get_bool(*p, "rs1.Q1"));
    step(false, true); // reset: both FALSE
    EXPECT_FALSE(get_bool(*p, "sr1.Q1"));
    EXPECT_FALSE(get_bool(*p, "rs1.Q1"));
    step(false, false); // neither: both hold FALSE
    EXPECT_FALSE(get_bool(*p, "sr1.Q1"));
    EXPECT_FALSE(get_bool(*p, "rs1.Q1"));
}

} // namespace
