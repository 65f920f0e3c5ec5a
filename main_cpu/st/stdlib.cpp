// rcsim — the IEC 61131-3 standard function blocks of the subset. See library.h.
#include "main_cpu/st/compiler.h"
#include "main_cpu/st/library.h"

namespace rcsim::st {

std::size_t PouBuilder::add(const std::string& name, VarKind kind, Kind type, Value init) {
    VarInfo v;
    v.name = name;
    v.type = Type::of(type);
    v.kind = kind;
    v.slot = pou.value_slots++;
    v.init = {init};
    pou.index[upper(name)] = pou.vars.size();
    pou.vars.push_back(std::move(v));
    return pou.vars.back().slot;
}

// The bistable, edge and counter blocks as IEC 61131-3 (3rd ed., §6.6.3.5.2-.4, Tables 43-45)
// writes them in ST. F_TRIG's M starts TRUE, as IEC 61131-8 recommends: otherwise the block
// reports a falling edge on its first call with CLK = FALSE. The counters' CU and CD are R_EDGE
// inputs: an R_TRIG inside each. SR is set-dominant (Q1 := S1 OR (NOT R AND Q1)), RS
// reset-dominant (Q1 := NOT R1 AND (S OR Q1)). The INT counters stop at -32768 and 32767
// (PVmin, PVmax).
const std::string& standard_prelude() {
    static const std::string text = R"(
FUNCTION_BLOCK R_TRIG
VAR_INPUT CLK : BOOL; END_VAR
VAR_OUTPUT Q : BOOL; END_VAR
VAR M : BOOL; END_VAR
Q := CLK AND NOT M;
M := CLK;
END_FUNCTION_BLOCK

FUNCTION_BLOCK F_TRIG
VAR_INPUT CLK : BOOL; END_VAR
VAR_OUTPUT Q : BOOL; END_VAR
VAR M : BOOL := TRUE; END_VAR
Q := NOT CLK AND NOT M;
M := NOT CLK;
END_FUNCTION_BLOCK

FUNCTION_BLOCK CTU
VAR_INPUT CU : BOOL; R : BOOL; PV : INT; END_VAR
VAR_OUTPUT Q : BOOL; CV : INT; END_VAR
VAR CU_EDGE : R_TRIG; END_VAR
CU_EDGE(CLK := CU);
IF R THEN
    CV := 0;
ELSIF CU_EDGE.Q AND (CV < 32767) THEN
    CV := CV + 1;
END_IF;
Q := CV >= PV;
END_FUNCTION_BLOCK

FUNCTION_BLOCK CTD
VAR_INPUT CD : BOOL; LD : BOOL; PV : INT; END_VAR
VAR_OUTPUT Q : BOOL; CV : INT; END_VAR
VAR CD_EDGE : R_TRIG; END_VAR
CD_EDGE(CLK := CD);
IF LD THEN
    CV := PV;
ELSIF CD_EDGE.Q AND (CV > -32768) THEN
    CV := CV - 1;
END_IF;
Q := CV <= 0;
END_FUNCTION_BLOCK

FUNCTION_BLOCK CTUD
VAR_INPUT CU : BOOL; CD : BOOL; R : BOOL; LD : BOOL; PV : INT; END_VAR
VAR_OUTPUT QU : BOOL; QD : BOOL; CV : INT; END_VAR
VAR CU_EDGE : R_TRIG; CD_EDGE : R_TRIG; END_VAR
CU_EDGE(CLK := CU);
CD_EDGE(CLK := CD);
IF R THEN
    CV := 0;
ELSIF LD THEN
    CV := PV;
ELSIF NOT (CU_EDGE.Q AND CD_EDGE.Q) THEN
    IF CU_EDGE.Q AND (CV < 32767) THEN
        CV := CV + 1;
    ELSIF CD_EDGE.Q AND (CV > -32768) THEN
        CV := CV - 1;
    END_IF;
END_IF;
QU := CV >= PV;
QD := CV <= 0;
END_FUNCTION_BLOCK

FUNCTION_BLOCK SR
VAR_INPUT S1 : BOOL; R : BOOL; END_VAR
VAR_OUTPUT Q1 : BOOL; END_VAR
Q1 := S1 OR (NOT R AND Q1);
END_FUNCTION_BLOCK

FUNCTION_BLOCK RS
VAR_INPUT S : BOOL; R1 : BOOL; END_VAR
VAR_OUTPUT Q1 : BOOL; END_VAR
Q1 := NOT R1 AND (S OR Q1);
END_FUNCTION_BLOCK
)";
    return text;
}

namespace {

// TON and TOF (IEC 61131-3 §6.6.3.5.5, Figure 15): ET counts from the edge of IN in the cycle's
// time, stops at PT; TON's Q is ET = PT while IN, TOF's Q is IN or ET < PT after IN fell.
enum TimerSlot : std::size_t { in_slot, pt_slot, q_slot, et_slot };

class Ton : public NativeBlock {
public:
    void call(Instance& self, ExecContext& ctx) override {
        auto& v = self.vars;
        const bool in = v[in_slot].i != 0;
        if (!in) {
            v[q_slot].i = v[et_slot].i = 0;
        } else {
            if (!prev_) start_ = ctx.now_us;
            const std::int64_t pt = v[pt_slot].i, et = ctx.now_us - start_;
            v[et_slot].i = et >= pt ? pt : et;
            v[q_slot].i = et >= pt;
        }
        prev_ = in;
    }

private:
    bool prev_ = false;
    std::int64_t start_ = 0;
};

class Tof : public NativeBlock {
public:
    void call(Instance& self, ExecContext& ctx) override {
        auto& v = self.vars;
        const bool in = v[in_slot].i != 0;
        if (in) {
            v[q_slot].i = 1;
            v[et_slot].i = 0;
            timing_ = false;
        } else if (prev_ || timing_) {
            if (prev_) start_ = ctx.now_us;
            timing_ = true;
            const std::int64_t pt = v[pt_slot].i, et = ctx.now_us - start_;
            v[et_slot].i = et >= pt ? pt : et;
            v[q_slot].i = et < pt;
            if (et >= pt) timing_ = false;
        }
        prev_ = in;
    }

private:
    bool prev_ = false, timing_ = false;
    std::int64_t start_ = 0;
};

// TP (Figure 15 a): a rising edge of IN while no pulse runs starts one; Q is TRUE for PT whatever
// IN does meanwhile, ET counts up to PT. After the pulse ET stays at PT while IN is TRUE and goes
// to 0 when IN is FALSE.
class Tp : public NativeBlock {
public:
    void call(Instance& self, ExecContext& ctx) override {
        auto& v = self.vars;
        const bool in = v[in_slot].i != 0;
        if (!pulsing_ && in && !prev_) {
            pulsing_ = true;
            start_ = ctx.now_us;
        }
        if (pulsing_) {
            const std::int64_t pt = v[pt_slot].i, et = ctx.now_us - start_;
            if (et >= pt) pulsing_ = false;
            v[q_slot].i = pulsing_;
            v[et_slot].i = pulsing_ ? et : in ? pt : 0;
        } else {
            v[q_slot].i = 0;
            if (!in) v[et_slot].i = 0;
        }
        prev_ = in;
    }

private:
    bool prev_ = false, pulsing_ = false;
    std::int64_t start_ = 0;
};

template <typename Impl> void add_timer(Unit& u, const char* name) {
    auto p = std::make_unique<PouType>();
    p->name = name;
    PouBuilder b{*p};
    b.add("IN", VarKind::input, Kind::Bool);
    b.add("PT", VarKind::input, Kind::Time);
    b.add("Q", VarKind::output, Kind::Bool);
    b.add("ET", VarKind::output, Kind::Time);
    p->native = [] { return std::make_unique<Impl>(); };
    u.pous.push_back(std::move(p));
}

} // namespace

void add_timer_blocks(Unit& u) {
    add_timer<Ton>(u, "TON");
    add_timer<Tof>(u, "TOF");
    add_timer<Tp>(u, "TP");
}

} // namespace rcsim::st
