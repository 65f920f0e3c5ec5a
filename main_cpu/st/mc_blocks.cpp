// rcsim — the PLCopen motion blocks of main_cpu/motion/plcopen.h as ST function blocks. See
// library.h; their inputs and outputs are docs/st.md "Motion blocks".
//
// Each ST instance owns one C++ block. A call copies the ST inputs into it (an AXIS_REF input
// becomes the McAxis of that number, none for -1 or an unknown number: the block answers
// invalid_axis), calls it once, and copies its outputs back.
#include "main_cpu/motion/plcopen.h"
#include "main_cpu/st/compiler.h"
#include "main_cpu/st/library.h"

namespace rcsim::st {
namespace {

using motion::McAxis;

/// Which C++ members a block's ST variables map to, in the order the layout declares them.
template <typename Fb> struct Spec {
    std::vector<std::pair<const char*, McAxis* Fb::*>> axes;
    std::vector<std::pair<const char*, bool Fb::*>> bools;
    std::vector<std::pair<const char*, double Fb::*>> reals;
    std::vector<std::pair<const char*, int Fb::*>> ints;
    motion::BufferMode Fb::*mode = nullptr; // INT BufferMode: 0 aborting, 1 buffered
    std::vector<std::pair<const char*, bool Fb::*>> bool_out;
    std::vector<std::pair<const char*, std::uint16_t Fb::*>> word_out;
};

McAxis* axis_of(const ExecContext& c, std::int64_t n) {
    return n >= 0 && static_cast<std::size_t>(n) < c.axes.size() ? c.axes[static_cast<std::size_t>(n)] : nullptr;
}

template <typename Fb> class McNative : public NativeBlock {
public:
    explicit McNative(const Spec<Fb>& s) : spec_(s) {}
    void call(Instance& self, ExecContext& ctx) override {
        std::size_t k = 0;
        auto& v = self.vars;
        for (const auto& [n, m] : spec_.axes) fb_.*m = axis_of(ctx, v[k++].i);
        for (const auto& [n, m] : spec_.bools) fb_.*m = v[k++].i != 0;
        for (const auto& [n, m] : spec_.reals) fb_.*m = v[k++].r;
        for (const auto& [n, m] : spec_.ints) fb_.*m = static_cast<int>(v[k++].i);
        if (spec_.mode) fb_.*spec_.mode = v[k++].i == 1 ? motion::BufferMode::buffered : motion::BufferMode::aborting;
        fb_.call();
        for (const auto& [n, m] : spec_.bool_out) v[k++].i = fb_.*m;
        for (const auto& [n, m] : spec_.word_out) v[k++].i = fb_.*m;
    }

private:
    const Spec<Fb>& spec_;
    Fb fb_;
};

template <typename Fb> void add_block(Unit& u, const char* name, const Spec<Fb>& s) {
    auto p = std::make_unique<PouType>();
    p->name = name;
    PouBuilder b{*p};
    for (const auto& e : s.axes) b.add(e.first, VarKind::input, Kind::AxisRef, Value{-1, 0});
    for (const auto& e : s.bools) b.add(e.first, VarKind::input, Kind::Bool);
    for (const auto& e : s.reals) b.add(e.first, VarKind::input, Kind::Lreal);
    for (const auto& e : s.ints) b.add(e.first, VarKind::input, Kind::Int);
    if (s.mode) b.add("BufferMode", VarKind::input, Kind::Int);
    for (const auto& e : s.bool_out) b.add(e.first, VarKind::output, Kind::Bool);
    for (const auto& e : s.word_out) b.add(e.first, VarKind::output, Kind::Udint);
    p->native = [&s] { return std::make_unique<McNative<Fb>>(s); };
    u.pous.push_back(std::move(p));
}

/// The outputs of every Execute-type block (PLCopen Part 1 §2.4.1).
template <typename Fb> void execute_outputs(Spec<Fb>& s, bool active) {
    s.bools.insert(s.bools.begin(), {"Execute", &Fb::Execute});
    s.bool_out = {{"Done", &Fb::Done}, {"Busy", &Fb::Busy}};
    if (active) s.bool_out.push_back({"Active", &Fb::Active});
    s.bool_out.push_back({"CommandAborted", &Fb::CommandAborted});
    s.bool_out.push_back({"Error", &Fb::Error});
    s.word_out = {{"ErrorID", &Fb::ErrorID}};
}

template <typename Fb, bool buffered>
Spec<Fb> execute_spec(std::vector<std::pair<const char*, double Fb::*>> reals, bool active) {
    Spec<Fb> s;
    s.axes = {{"Axis", &Fb::Axis}};
    s.reals = std::move(reals);
    if constexpr (buffered) s.mode = &Fb::Mode;
    execute_outputs(s, active);
    return s;
}

template <typename Fb> Spec<Fb> pair_spec(std::vector<std::pair<const char*, double Fb::*>> reals) {
    Spec<Fb> s;
    s.axes = {{"AxisX", &Fb::AxisX}, {"AxisY", &Fb::AxisY}};
    s.reals = std::move(reals);
    s.mode = &Fb::Mode;
    execute_outputs(s, true);
    return s;
}

/// MC_Power drives the motion layer's own MC_Power of the axis when there is one (ExecContext::
/// power): the layer calls that block every cycle, and two power blocks on one axis would fight.
class PowerNative : public NativeBlock {
public:
    void call(Instance& self, ExecContext& ctx) override {
        auto& v = self.vars; // Axis, Enable, Status, Valid, Error, ErrorID
        const std::int64_t n = v[0].i;
        motion::MC_Power* p = n >= 0 && static_cast<std::size_t>(n) < ctx.power.size()
                                  ? ctx.power[static_cast<std::size_t>(n)] : nullptr;
        if (!p) {
            own_.Axis = axis_of(ctx, n);
            own_.Enable = v[1].i != 0;
            own_.call();
            p = &own_;
        } else {
            p->Enable = v[1].i != 0;
        }
        v[2].i = p->Status;
        v[3].i = p->Valid;
        v[4].i = p->Error;
        v[5].i = p->ErrorID;
    }

private:
    motion::MC_Power own_;
};

} // namespace

void add_motion_blocks(Unit& u) {
    using namespace motion;
    {
        auto p = std::make_unique<PouType>();
        p->name = "MC_Power";
        PouBuilder b{*p};
        b.add("Axis", VarKind::input, Kind::AxisRef, Value{-1, 0});
        b.add("Enable", VarKind::input, Kind::Bool);
        b.add("Status", VarKind::output, Kind::Bool);
        b.add("Valid", VarKind::output, Kind::Bool);
        b.add("Error", VarKind::output, Kind::Bool);
        b.add("ErrorID", VarKind::output, Kind::Udint);
        p->native = [] { return std::make_unique<PowerNative>(); };
        u.pous.push_back(std::move(p));
    }
    static const Spec<MC_Reset> reset = execute_spec<MC_Reset, false>({}, false);
    static const Spec<MC_Stop> stop = execute_spec<MC_Stop, false>({{"Deceleration", &MC_Stop::Deceleration}}, false);
    static const Spec<MC_Halt> halt = execute_spec<MC_Halt, true>({{"Deceleration", &MC_Halt::Deceleration}}, true);
    static const Spec<MC_Home> home = [] {
        auto s = execute_spec<MC_Home, true>({{"Position", &MC_Home::Position}, {"Velocity", &MC_Home::Velocity},
                                        {"Acceleration", &MC_Home::Acceleration}}, true);
        s.ints = {{"Direction", &MC_Home::Direction}};
        return s;
    }();
    static const Spec<MC_MoveAbsolute> move_abs = execute_spec<MC_MoveAbsolute, true>(
        {{"Position", &MC_MoveAbsolute::Position}, {"Velocity", &MC_MoveAbsolute::Velocity},
         {"Acceleration", &MC_MoveAbsolute::Acceleration}, {"Deceleration", &MC_MoveAbsolute::Deceleration}},
        true);
    static const Spec<MC_MoveRelative> move_rel = execute_spec<MC_MoveRelative, true>(
        {{"Distance", &MC_MoveRelative::Distance}, {"Velocity", &MC_MoveRelative::Velocity},
         {"Acceleration", &MC_MoveRelative::Acceleration}, {"Deceleration", &MC_MoveRelative::Deceleration}},
        true);
    static const Spec<MC_LineMove2> line = pair_spec<MC_LineMove2>(
        {{"X", &MC_LineMove2::X}, {"Y", &MC_LineMove2::Y}, {"Velocity", &MC_LineMove2::Velocity},
         {"Acceleration", &MC_LineMove2::Acceleration}, {"Deceleration", &MC_LineMove2::Deceleration}});
    static const Spec<MC_CircleCenterMove> circle = [] {
        auto s = pair_spec<MC_CircleCenterMove>(
            {{"CenterX", &MC_CircleCenterMove::CenterX}, {"CenterY", &MC_CircleCenterMove::CenterY},
             {"EndX", &MC_CircleCenterMove::EndX}, {"EndY", &MC_CircleCenterMove::EndY},
             {"Velocity", &MC_CircleCenterMove::Velocity}, {"Acceleration", &MC_CircleCenterMove::Acceleration},
             {"Deceleration", &MC_CircleCenterMove::Deceleration}});
        s.ints = {{"Direction", &MC_CircleCenterMove::Direction}}; // 0 counter-clockwise, 1 clockwise (AXL)
        return s;
    }();
    add_block(u, "MC_Reset", reset);
    add_block(u, "MC_Stop", stop);
    add_block(u, "MC_Halt", halt);
    add_block(u, "MC_Home", home);
    add_block(u, "MC_MoveAbsolute", move_abs);
    add_block(u, "MC_MoveRelative", move_rel);
    add_block(u, "MC_LineMove2", line);
    add_block(u, "MC_CircleCenterMove", circle);
}

} // namespace rcsim::st
