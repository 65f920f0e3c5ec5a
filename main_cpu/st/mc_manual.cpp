// rcsim — PLCopen Part 1 blocks for manual and corrective motion as ST function blocks, each
// mapped onto the motion layer's blocks (main_cpu/motion/plcopen.h): MC_ReadActualVelocity,
// MC_Jog (MC_MoveVelocity while a jog input is held, MC_Halt when released) and
// MC_MoveSuperimposed (MC_MoveRelative in Standstill; refused on a moving axis, which the CAMC-QI
// cannot superimpose on). Their inputs, outputs and limits are docs/st.md "Motion blocks".
#include "main_cpu/motion/plcopen.h"
#include "main_cpu/st/compiler.h"
#include "main_cpu/st/library.h"

#include <cmath>

namespace rcsim::st {
namespace {

using motion::AxisState;
using motion::McAxis;

McAxis* axis_of(const ExecContext& c, std::int64_t n) {
    return n >= 0 && static_cast<std::size_t>(n) < c.axes.size() ? c.axes[static_cast<std::size_t>(n)] : nullptr;
}

/// Part 1 MC_ReadActualVelocity: the drive's actual velocity (0x606C, pulses/s, signed).
class ReadActualVelocity : public motion::McEnableFb {
public:
    double Velocity = 0;

protected:
    std::uint16_t read() override {
        Velocity = Axis->drive().actual_velocity();
        return 0;
    }
    void clear() override { Velocity = 0; }
};

class ReadVelocityNative : public NativeBlock {
public:
    enum Slot { axis, enable, valid, busy, error, error_id, velocity };
    void call(Instance& self, ExecContext& ctx) override {
        ++ctx.motion_calls;
        auto& v = self.vars;
        fb_.Axis = axis_of(ctx, v[axis].i);
        fb_.Enable = v[enable].i != 0;
        fb_.call();
        v[valid].i = fb_.Valid;
        v[busy].i = fb_.Busy;
        v[error].i = fb_.Error;
        v[error_id].i = fb_.ErrorID;
        v[velocity].r = fb_.Velocity;
    }

private:
    ReadActualVelocity fb_;
};

/// MC_Jog: while exactly one of JogForward, JogBackward is TRUE the axis runs that way at
/// Velocity (an MC_MoveVelocity, aborting what ran); when it falls (or both are TRUE) an MC_Halt
/// with Deceleration stops it and Done rises at standstill. Another block aborting the jog gives
/// CommandAborted; a refusal gives Error and the motion block's ErrorID. Both stay until the next
/// jog starts; a jog input must fall and rise again to start one.
class JogNative : public NativeBlock {
public:
    enum Slot { axis, forward, backward, velocity, acceleration, deceleration, jerk,
                done, busy, aborted, error, error_id };
    void call(Instance& self, ExecContext& ctx) override {
        ++ctx.motion_calls;
        auto& v = self.vars;
        const bool f = v[forward].i != 0, b = v[backward].i != 0;
        const int want = f && !b ? 1 : b && !f ? -1 : 0;
        McAxis* a = axis_of(ctx, v[axis].i);
        if (want != dir_) {
            if (want != 0) start(v, a, want);
            else if (mv_.Busy) release(v, a);
            dir_ = want;
        }
        mv_.call();
        if (halting_) halt_.call();
        if (mv_.Error || halt_.Error) {
            error_ = true;
            error_id_ = mv_.Error ? mv_.ErrorID : halt_.ErrorID;
        }
        // The halt aborting our own MoveVelocity is the jog's end, not an abort.
        if ((mv_.CommandAborted && !halting_) || halt_.CommandAborted) aborted_ = true;
        v[done].i = halting_ && halt_.Done;
        v[busy].i = !error_ && !aborted_ && (mv_.Busy || halt_.Busy);
        v[aborted].i = aborted_;
        v[error].i = error_;
        v[error_id].i = error_id_;
    }

private:
    motion::MC_MoveVelocity mv_;
    motion::MC_Halt halt_;
    int dir_ = 0;
    bool halting_ = false, aborted_ = false, error_ = false;
    std::uint16_t error_id_ = 0;

    void start(const std::vector<Value>& v, McAxis* a, int dir) {
        // Execute low then high within this call: a rising edge even when a jog in the other
        // direction was running (the new MoveVelocity aborts it, as an aborting command does).
        mv_.Execute = false;
        mv_.call();
        mv_.Axis = a;
        mv_.Velocity = v[velocity].r > 0 ? v[velocity].r : 0; // 0: the block's invalid-velocity error
        mv_.Acceleration = v[acceleration].r;
        mv_.Deceleration = v[deceleration].r;
        mv_.Jerk = v[jerk].r;
        mv_.Direction = dir > 0 ? motion::McDirection::positive : motion::McDirection::negative;
        mv_.Execute = true;
        halt_.Execute = false;
        halt_.call();
        halting_ = aborted_ = error_ = false;
        error_id_ = 0;
    }
    void release(const std::vector<Value>& v, McAxis* a) {
        mv_.Execute = false;
        halt_.Axis = a;
        halt_.Deceleration = v[deceleration].r;
        halt_.Execute = true;
        halting_ = true;
    }
};

/// MC_MoveSuperimposed: in Standstill, Part 1 has it act as MC_MoveRelative (VelocityDiff the
/// velocity); on an axis that moves the CAMC-QI has no way to add a distance to the running drive
/// (it cannot change a running drive's target), so the block answers Error with
/// superimposed_in_motion instead of faking it. CoveredDistance: the command position's travel
/// since Execute rose.
class SuperimposedNative : public NativeBlock {
public:
    enum Slot { axis, execute, distance, velocity_diff, acceleration, deceleration, jerk,
                done, busy, active, aborted, error, error_id, covered };
    void call(Instance& self, ExecContext& ctx) override {
        ++ctx.motion_calls;
        auto& v = self.vars;
        McAxis* a = axis_of(ctx, v[axis].i);
        const bool exec = v[execute].i != 0;
        if (exec && !prev_) {
            refused_ = a && moving(a->state());
            start_ = a ? a->api().CmdPos(static_cast<int>(a->index())) : 0;
            axis_ = a;
        }
        if (!exec) refused_ = false;
        prev_ = exec;
        mr_.Axis = a;
        mr_.Distance = static_cast<std::int32_t>(v[distance].i);
        mr_.Velocity = v[velocity_diff].r;
        mr_.Acceleration = v[acceleration].r;
        mr_.Deceleration = v[deceleration].r;
        mr_.Jerk = v[jerk].r;
        mr_.Execute = exec && !refused_;
        mr_.call();
        v[done].i = mr_.Done;
        v[busy].i = mr_.Busy;
        v[active].i = mr_.Active;
        v[aborted].i = mr_.CommandAborted;
        v[error].i = refused_ || mr_.Error;
        v[error_id].i = refused_ ? superimposed_in_motion : mr_.ErrorID;
        const bool moved = !refused_ && axis_ && (mr_.Busy || mr_.Done || mr_.CommandAborted);
        v[covered].r = moved ? static_cast<double>(axis_->api().CmdPos(static_cast<int>(axis_->index())) - start_) : 0;
    }

private:
    motion::MC_MoveRelative mr_;
    McAxis* axis_ = nullptr;
    std::int64_t start_ = 0;
    bool prev_ = false, refused_ = false;

    static bool moving(AxisState s) {
        return s == AxisState::discrete_motion || s == AxisState::continuous_motion ||
               s == AxisState::synchronized_motion;
    }
};

template <typename Native> void add(Unit& u, const char* name, void (*vars)(PouBuilder&)) {
    auto p = std::make_unique<PouType>();
    p->name = name;
    PouBuilder b{*p};
    vars(b);
    p->native = [] { return std::make_unique<Native>(); };
    u.pous.push_back(std::move(p));
}

} // namespace

void add_manual_motion_blocks(Unit& u) {
    // Slots in each Native's Slot order: PLCopen's inputs, then its outputs.
    add<ReadVelocityNative>(u, "MC_ReadActualVelocity", [](PouBuilder& b) {
        b.add("Axis", VarKind::input, Kind::AxisRef, Value{-1, 0});
        b.add("Enable", VarKind::input, Kind::Bool);
        for (const char* o : {"Valid", "Busy", "Error"}) b.add(o, VarKind::output, Kind::Bool);
        b.add("ErrorID", VarKind::output, Kind::Udint);
        b.add("Velocity", VarKind::output, Kind::Lreal);
    });
    add<JogNative>(u, "MC_Jog", [](PouBuilder& b) {
        b.add("Axis", VarKind::input, Kind::AxisRef, Value{-1, 0});
        b.add("JogForward", VarKind::input, Kind::Bool);
        b.add("JogBackward", VarKind::input, Kind::Bool);
        for (const char* i : {"Velocity", "Acceleration", "Deceleration", "Jerk"}) b.add(i, VarKind::input, Kind::Lreal);
        for (const char* o : {"Done", "Busy", "CommandAborted", "Error"}) b.add(o, VarKind::output, Kind::Bool);
        b.add("ErrorID", VarKind::output, Kind::Udint);
    });
    add<SuperimposedNative>(u, "MC_MoveSuperimposed", [](PouBuilder& b) {
        b.add("Axis", VarKind::input, Kind::AxisRef, Value{-1, 0});
        b.add("Execute", VarKind::input, Kind::Bool);
        b.add("Distance", VarKind::input, Kind::Dint);
        for (const char* i : {"VelocityDiff", "Acceleration", "Deceleration", "Jerk"})
            b.add(i, VarKind::input, Kind::Lreal);
        for (const char* o : {"Done", "Busy", "Active", "CommandAborted", "Error"})
            b.add(o, VarKind::output, Kind::Bool);
        b.add("ErrorID", VarKind::output, Kind::Udint);
        b.add("CoveredDistance", VarKind::output, Kind::Lreal);
    });
}

} // namespace rcsim::st
