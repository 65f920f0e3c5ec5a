// rcsim — the PLCopen motion blocks of main_cpu/motion/plcopen.h as ST function blocks. See
// library.h; their inputs and outputs are docs/st.md "Motion blocks".
//
// Each ST instance owns one C++ block. A call copies the ST inputs into it (an AXIS_REF input
// becomes the McAxis of that number, none for -1 or an unknown number: the block answers
// invalid_axis), calls it once, and copies its outputs back.
#include "main_cpu/motion/plcopen.h"
#include "main_cpu/st/compiler.h"
#include "main_cpu/st/library.h"

#include <functional>
#include <limits>
#include <type_traits>
#include <utility>

namespace rcsim::st {
namespace {

using motion::McAxis;

McAxis* axis_of(const ExecContext& c, std::int64_t n) {
    return n >= 0 && static_cast<std::size_t>(n) < c.axes.size() ? c.axes[static_cast<std::size_t>(n)] : nullptr;
}

/// One ST variable of a motion block and the C++ member it maps to. The ST type follows the
/// member's: McAxis* AXIS_REF, bool BOOL, floating LREAL, BufferMode and enums INT, other
/// integers DINT (inputs) or UDINT (ErrorID).
template <typename Fb> struct Field {
    const char* name;
    VarKind kind;
    Kind type;
    Value init;
    std::function<void(Fb&, const Value&, const ExecContext&)> in;
    std::function<void(const Fb&, Value&)> out;
};

template <typename Fb, typename C, typename M> Field<Fb> input(const char* name, M C::*m) {
    Field<Fb> f{name, VarKind::input, Kind::Dint, {}, {}, {}};
    if constexpr (std::is_same_v<M, McAxis*>) {
        f.type = Kind::AxisRef;
        f.init = Value{-1, 0};
        f.in = [m](Fb& b, const Value& v, const ExecContext& c) { b.*m = axis_of(c, v.i); };
    } else if constexpr (std::is_same_v<M, bool>) {
        f.type = Kind::Bool;
        f.in = [m](Fb& b, const Value& v, const ExecContext&) { b.*m = v.i != 0; };
    } else if constexpr (std::is_floating_point_v<M>) {
        f.type = Kind::Lreal;
        f.in = [m](Fb& b, const Value& v, const ExecContext&) { b.*m = static_cast<M>(v.r); };
    } else if constexpr (std::is_enum_v<M>) {
        f.type = Kind::Int;
        f.init = Value{static_cast<std::int64_t>(Fb{}.*m), 0};
        // Through the underlying type; a value it cannot hold becomes its largest, never a valid
        // value by wrapping (BufferMode 259 must be refused as 259, not run as 3).
        f.in = [m](Fb& b, const Value& v, const ExecContext&) {
            using U = std::underlying_type_t<M>;
            const bool fits = v.i >= std::numeric_limits<U>::min() && v.i <= std::numeric_limits<U>::max();
            b.*m = static_cast<M>(fits ? static_cast<U>(v.i) : std::numeric_limits<U>::max());
        };
    } else {
        f.init = Value{static_cast<std::int64_t>(Fb{}.*m), 0};
        f.in = [m](Fb& b, const Value& v, const ExecContext&) { b.*m = static_cast<M>(v.i); };
    }
    if constexpr (std::is_floating_point_v<M>) f.init = Value{0, static_cast<double>(Fb{}.*m)};
    return f;
}

template <typename Fb, typename C, typename M> Field<Fb> output(const char* name, M C::*m) {
    Field<Fb> f{name, VarKind::output, std::is_same_v<M, bool> ? Kind::Bool : Kind::Udint, {}, {}, {}};
    if constexpr (std::is_floating_point_v<M>) {
        f.type = Kind::Lreal;
        f.out = [m](const Fb& b, Value& v) { v.r = static_cast<double>(b.*m); };
    } else {
        f.out = [m](const Fb& b, Value& v) { v.i = static_cast<std::int64_t>(b.*m); };
    }
    return f;
}

template <typename Fb> class McNative : public NativeBlock {
public:
    explicit McNative(const std::vector<Field<Fb>>& f) : fields_(f) {}
    void call(Instance& self, ExecContext& ctx) override {
        ++ctx.motion_calls;
        for (std::size_t k = 0; k < fields_.size(); ++k)
            if (fields_[k].in) fields_[k].in(fb_, self.vars[k], ctx);
        fb_.call();
        for (std::size_t k = 0; k < fields_.size(); ++k)
            if (fields_[k].out) fields_[k].out(fb_, self.vars[k]);
    }

private:
    const std::vector<Field<Fb>>& fields_;
    Fb fb_;
};

template <typename Fb> void add_block(Unit& u, const char* name, const std::vector<Field<Fb>>& fields) {
    auto p = std::make_unique<PouType>();
    p->name = name;
    PouBuilder b{*p};
    for (const Field<Fb>& f : fields) b.add(f.name, f.kind, f.type, f.init); // slot k = fields[k]
    p->native = [&fields] { return std::make_unique<McNative<Fb>>(fields); };
    u.pous.push_back(std::move(p));
}

/// Execute and the outputs of every Execute-type block (PLCopen Part 1 §2.4.1), around `inputs`.
template <typename Fb> std::vector<Field<Fb>> execute_block(std::vector<Field<Fb>> inputs, bool active) {
    std::vector<Field<Fb>> f = std::move(inputs);
    f.insert(f.begin() + 1, input<Fb>("Execute", &Fb::Execute)); // after the axis
    f.push_back(output<Fb>("Done", &Fb::Done));
    f.push_back(output<Fb>("Busy", &Fb::Busy));
    if (active) f.push_back(output<Fb>("Active", &Fb::Active));
    f.push_back(output<Fb>("CommandAborted", &Fb::CommandAborted));
    f.push_back(output<Fb>("Error", &Fb::Error));
    f.push_back(output<Fb>("ErrorID", &Fb::ErrorID));
    return f;
}

/// Axis, Enable and the outputs of every Enable-type block (PLCopen Part 1 §2.4.2), around
/// `inputs` (after Enable) and `values` (after ErrorID).
template <typename Fb>
std::vector<Field<Fb>> enable_block(std::vector<Field<Fb>> inputs, std::vector<Field<Fb>> values) {
    std::vector<Field<Fb>> f = {input<Fb>("Axis", &Fb::Axis), input<Fb>("Enable", &Fb::Enable)};
    f.insert(f.end(), inputs.begin(), inputs.end());
    for (auto o : {output<Fb>("Valid", &Fb::Valid), output<Fb>("Busy", &Fb::Busy), output<Fb>("Error", &Fb::Error),
                   output<Fb>("ErrorID", &Fb::ErrorID)})
        f.push_back(o);
    f.insert(f.end(), values.begin(), values.end());
    return f;
}

/// MC_LineMove over 2-4 axes with the inputs of MC_LineMove2 extended by a third and a fourth
/// axis: AxisX and AxisY always take part (no axis there: invalid_axis, as for MC_LineMove2),
/// AxisZ and AxisU when they name an axis. The group and its distances are formed from them on
/// every call; the block reads them at Execute's rising edge.
struct LineMoveN : motion::MC_LineMove {
    McAxis *AxisX = nullptr, *AxisY = nullptr, *AxisZ = nullptr, *AxisU = nullptr;
    std::int32_t X = 0, Y = 0, Z = 0, U = 0;
    void call() {
        Axes = {AxisX, AxisY};
        Distances = {X, Y};
        for (const auto& [a, d] : {std::pair{AxisZ, Z}, std::pair{AxisU, U}})
            if (a) Axes.push_back(a), Distances.push_back(d);
        MC_LineMove::call();
    }
};

/// MC_Power drives the motion layer's own MC_Power of the axis when there is one (ExecContext::
/// power): the layer calls that block every cycle, and two power blocks on one axis would fight.
class PowerNative : public NativeBlock {
public:
    void call(Instance& self, ExecContext& ctx) override {
        ++ctx.motion_calls;
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
    // MC_BUFFER_MODE's values as PLC runtimes number them (PLCopen Part 1 §2.4.2): INT constants,
    // so that BufferMode takes a name or a number (a number outside 0..5 gets ErrorID 0x7020).
    static const std::pair<const char*, BufferMode> buffer_modes[] = {
        {"mcAborting", BufferMode::aborting},         {"mcBuffered", BufferMode::buffered},
        {"mcBlendingLow", BufferMode::blending_low},   {"mcBlendingPrevious", BufferMode::blending_previous},
        {"mcBlendingNext", BufferMode::blending_next}, {"mcBlendingHigh", BufferMode::blending_high},
    };
    for (const auto& [name, mode] : buffer_modes) {
        PouBuilder{u.globals}.add(name, VarKind::global, Kind::Int, Value{static_cast<std::int64_t>(mode), 0});
        u.globals.vars.back().read_only = u.globals.vars.back().constant = true;
    }
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
    // Inputs in PLCopen's order; the interpolating blocks take two AXIS_REFs (AxisX, AxisY), the
    // pair rcsim's blocks drive as a two-axis group, MC_LineMove up to four (LineMoveN).
    static const auto reset = execute_block<MC_Reset>({input<MC_Reset>("Axis", &MC_Reset::Axis)}, false);
    static const auto stop = execute_block<MC_Stop>(
        {input<MC_Stop>("Axis", &MC_Stop::Axis), input<MC_Stop>("Deceleration", &MC_Stop::Deceleration),
         input<MC_Stop>("Emergency", &MC_Stop::Emergency)}, false);
    static const auto halt = execute_block<MC_Halt>(
        {input<MC_Halt>("Axis", &MC_Halt::Axis), input<MC_Halt>("Deceleration", &MC_Halt::Deceleration),
         input<MC_Halt>("BufferMode", &MC_Halt::Mode)}, true);
    static const auto home = execute_block<MC_Home>(
        {input<MC_Home>("Axis", &MC_Home::Axis), input<MC_Home>("Position", &MC_Home::Position),
         input<MC_Home>("Direction", &MC_Home::Direction), input<MC_Home>("Velocity", &MC_Home::Velocity),
         input<MC_Home>("Acceleration", &MC_Home::Acceleration),
         input<MC_Home>("BackOffVelocity", &MC_Home::BackOffVelocity),
         input<MC_Home>("ApproachVelocity", &MC_Home::ApproachVelocity), input<MC_Home>("ZVelocity", &MC_Home::ZVelocity),
         input<MC_Home>("ZPhase", &MC_Home::ZPhase), input<MC_Home>("BufferMode", &MC_Home::Mode)}, true);
    using MA = MC_MoveAbsolute;
    static const auto move_abs = execute_block<MA>(
        {input<MA>("Axis", &MA::Axis), input<MA>("Position", &MA::Position), input<MA>("Velocity", &MA::Velocity),
         input<MA>("Acceleration", &MA::Acceleration), input<MA>("Deceleration", &MA::Deceleration),
         input<MA>("Jerk", &MA::Jerk), input<MA>("BufferMode", &MA::Mode)}, true);
    using MR = MC_MoveRelative;
    static const auto move_rel = execute_block<MR>(
        {input<MR>("Axis", &MR::Axis), input<MR>("Distance", &MR::Distance), input<MR>("Velocity", &MR::Velocity),
         input<MR>("Acceleration", &MR::Acceleration), input<MR>("Deceleration", &MR::Deceleration),
         input<MR>("Jerk", &MR::Jerk), input<MR>("BufferMode", &MR::Mode)}, true);
    // MC_MoveVelocity reports InVelocity in place of Done (PLCopen Part 1 §3.4). Direction:
    // -1 negative, 0 current, 1 positive (MC_DIRECTION).
    using MV = MC_MoveVelocity;
    static const auto move_vel = [] {
        auto f = execute_block<MV>({input<MV>("Axis", &MV::Axis), input<MV>("Velocity", &MV::Velocity),
                                    input<MV>("Acceleration", &MV::Acceleration),
                                    input<MV>("Deceleration", &MV::Deceleration), input<MV>("Jerk", &MV::Jerk),
                                    input<MV>("Direction", &MV::Direction), input<MV>("BufferMode", &MV::Mode)},
                                   true);
        for (auto& x : f)
            if (std::string(x.name) == "Done") x = output<MV>("InVelocity", &MV::InVelocity);
        return f;
    }();
    using LM = MC_LineMove2;
    static const auto line = execute_block<LM>(
        {input<LM>("AxisX", &LM::AxisX), input<LM>("AxisY", &LM::AxisY), input<LM>("X", &LM::X), input<LM>("Y", &LM::Y),
         input<LM>("Velocity", &LM::Velocity), input<LM>("Acceleration", &LM::Acceleration),
         input<LM>("Deceleration", &LM::Deceleration), input<LM>("BufferMode", &LM::Mode)}, true);
    using LN = LineMoveN;
    static const auto line_n = execute_block<LN>(
        {input<LN>("AxisX", &LN::AxisX), input<LN>("AxisY", &LN::AxisY), input<LN>("AxisZ", &LN::AxisZ),
         input<LN>("AxisU", &LN::AxisU), input<LN>("X", &LN::X), input<LN>("Y", &LN::Y), input<LN>("Z", &LN::Z),
         input<LN>("U", &LN::U), input<LN>("Velocity", &LN::Velocity), input<LN>("Acceleration", &LN::Acceleration),
         input<LN>("Deceleration", &LN::Deceleration), input<LN>("BufferMode", &LN::Mode)}, true);
    using CC = MC_CircleCenterMove;
    static const auto circle = execute_block<CC>(
        {input<CC>("AxisX", &CC::AxisX), input<CC>("AxisY", &CC::AxisY), input<CC>("CenterX", &CC::CenterX),
         input<CC>("CenterY", &CC::CenterY), input<CC>("EndX", &CC::EndX), input<CC>("EndY", &CC::EndY),
         input<CC>("Direction", &CC::Direction), // 0 counter-clockwise, 1 clockwise (AXL DIR_CCW/DIR_CW)
         input<CC>("Velocity", &CC::Velocity), input<CC>("Acceleration", &CC::Acceleration),
         input<CC>("Deceleration", &CC::Deceleration), input<CC>("BufferMode", &CC::Mode)}, true);
    // The axis reads (Enable-type) and MC_SetPosition (PLCopen Part 1 §3.8, 3.10-3.13).
    using RS = MC_ReadStatus;
    static const auto read_status = enable_block<RS>(
        {}, {output<RS>("ErrorStop", &RS::ErrorStop), output<RS>("Disabled", &RS::Disabled),
             output<RS>("Stopping", &RS::Stopping), output<RS>("Homing", &RS::Homing),
             output<RS>("Standstill", &RS::Standstill), output<RS>("DiscreteMotion", &RS::DiscreteMotion),
             output<RS>("ContinuousMotion", &RS::ContinuousMotion),
             output<RS>("SynchronizedMotion", &RS::SynchronizedMotion)});
    using RP = MC_ReadActualPosition;
    static const auto read_pos = enable_block<RP>({}, {output<RP>("Position", &RP::Position)});
    using RE = MC_ReadAxisError;
    static const auto read_err = enable_block<RE>({}, {output<RE>("AxisErrorID", &RE::AxisErrorID)});
    using RA = MC_ReadParameter;
    static const auto read_par = enable_block<RA>({input<RA>("ParameterNumber", &RA::ParameterNumber)},
                                                  {output<RA>("Value", &RA::Value)});
    using SP = MC_SetPosition;
    static const auto set_pos = execute_block<SP>(
        {input<SP>("Axis", &SP::Axis), input<SP>("Position", &SP::Position), input<SP>("Relative", &SP::Relative)},
        false);
    add_block(u, "MC_ReadStatus", read_status);
    add_block(u, "MC_ReadActualPosition", read_pos);
    add_block(u, "MC_ReadAxisError", read_err);
    add_block(u, "MC_ReadParameter", read_par);
    add_block(u, "MC_SetPosition", set_pos);
    // MC_WriteParameter (Part 1 §3.11; issue #49 item 5): the limits by their Part 1 numbers.
    using WP = MC_WriteParameter;
    static const auto write_par = execute_block<WP>(
        {input<WP>("Axis", &WP::Axis), input<WP>("ParameterNumber", &WP::ParameterNumber),
         input<WP>("Value", &WP::Value)}, false);
    add_block(u, "MC_WriteParameter", write_par);
    add_block(u, "MC_Reset", reset);
    add_block(u, "MC_Stop", stop);
    add_block(u, "MC_Halt", halt);
    add_block(u, "MC_Home", home);
    add_block(u, "MC_MoveAbsolute", move_abs);
    add_block(u, "MC_MoveRelative", move_rel);
    add_block(u, "MC_MoveVelocity", move_vel);
    add_block(u, "MC_LineMove2", line);
    add_block(u, "MC_LineMove", line_n);
    add_block(u, "MC_CircleCenterMove", circle);
}

} // namespace rcsim::st
