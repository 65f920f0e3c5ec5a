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

// The bistable and edge blocks as IEC 61131-3 (3rd ed., §6.6.3.5.3/.5, Tables 44 and 45) writes
// them in ST. F_TRIG's M starts TRUE, as IEC 61131-8 recommends: otherwise the block reports a
// falling edge on its first call with CLK = FALSE. CTU's CU is R_EDGE: an R_TRIG inside.
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
}

} // namespace rcsim::st
