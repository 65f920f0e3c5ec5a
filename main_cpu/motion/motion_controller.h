// rcsim — the main CPU's motion layer as one module: CAMC-QI chip (TLM target, reached through
// this module's initiator socket by the paper's C library), four CiA402 drives, PLCopen blocks
// per axis, the motion tokens of docs/system.md §7.2, and a trajectory recorder.
//
// Wiring per axis: chip PULSE/DIR -> drive pulse input (mode -1); drive actual position ->
// chip encoder counter (A/B); drive ALM -> chip ALARM input; chip SVON/ALMRST -> drive.
// The drives and the blocks advance in control_cycle(), which the main CPU calls every cycle.
#pragma once

#include "camc_qi/camc_qi.h"
#include "main_cpu/motion/cia402_drive.h"
#include "main_cpu/motion/plcopen.h"
#include "main_cpu/motion/qi_api.h"
#include "main_cpu/motion/trajectory.h"
#include "main_cpu/motion_interface.h"

#include <tlm_utils/simple_initiator_socket.h>

#include <array>
#include <memory>
#include <set>

namespace rcsim::motion {

struct MotionConfig {
    Cia402Drive::Config drive;
    double start_speed = 100;        // STD of every move, pulses/s
    bool record = true;              // keep a trajectory sample per control cycle
    /// Mechanism: limit switch and home switch positions per axis, in pulses of the axis' pulse
    /// output (machine position: presets of the counters do not move them). PELM is on at and
    /// above its position, NELM and the home switch at and below theirs. Unset = no switch. The
    /// chip acts at the exact time its profile reaches a switch (camc_qi/README.md).
    struct Switches {
        std::optional<std::int64_t> pelm, nelm, home;
    };
    std::array<Switches, 4> switches{};
    /// Encoder Z pulse per axis: one position in every `pitch` pulses (0 = none).
    struct ZPhase {
        std::int64_t pitch = 0, offset = 0;
    };
    std::array<ZPhase, 4> zphase{};
};

class MotionController : public sc_core::sc_module, public MotionInterface {
public:
    static constexpr unsigned axes = 4;
    tlm_utils::simple_initiator_socket<MotionController> bus;

    MotionController(sc_core::sc_module_name name, const MotionConfig& cfg = {});
    ~MotionController() override;

    // MotionInterface
    MotionReply command(const std::string& token, const std::string& data) override;
    void control_cycle(const sc_core::sc_time& now) override;
    std::vector<std::int64_t> positions() const override;
    std::string state() const override;

    camc::CamcQi& chip() { return chip_; }
    Cia402Drive& drive(unsigned a) { return drives_[a]; }
    McAxis& axis(unsigned a) { return *axes_[a]; }
    QiMotionApi& api() { return api_; }
    MC_Power& power(unsigned a) { return power_[a]; }
    TrajectoryRecorder& recorder() { return recorder_; }

    /// The blocks the tokens drive, one instance per axis (or per pair); scenarios may set their
    /// inputs directly, the controller calls them every cycle.
    struct Blocks {
        MC_Reset reset;
        MC_Stop stop;
        MC_Home home;
        MC_MoveAbsolute move_abs;
        MC_MoveRelative move_rel;
        MC_MoveVelocity move_vel;
        MC_Halt halt;
    };
    Blocks& blocks(unsigned a) { return blocks_[a]; }
    MC_LineMove2& line_move() { return line_; }
    MC_LineMove& line_move_n() { return line_n_; } // 2-4 axes (the LM token)
    MC_CircleCenterMove& circle_move() { return circle_; }
    /// Calls every block once (the "PLC program" of one cycle).
    void run_blocks();
    /// Marks a block as driven by the token program: its Execute drops once it reports Done,
    /// Error or CommandAborted (blocks set directly keep Execute until their user drops it).
    void auto_release(McExecuteFb& fb) { auto_.insert(&fb); }

private:
    class Bus;
    camc::CamcQi chip_;
    std::unique_ptr<Bus> qi_bus_;
    QiMotionApi api_;
    MotionConfig cfg_;
    std::array<Cia402Drive, axes> drives_;
    std::array<std::unique_ptr<McAxis>, axes> axes_;
    std::array<MC_Power, axes> power_;
    std::array<Blocks, axes> blocks_;
    MC_LineMove2 line_;
    MC_LineMove line_n_;
    MC_CircleCenterMove circle_;
    TrajectoryRecorder recorder_;
    sc_core::sc_time last_;
    bool first_cycle_ = true;
    std::set<McExecuteFb*> auto_;

    void update_mechanism();
    MotionReply fb_reply(std::uint16_t error_id) const;
    MotionReply home(unsigned mask, double velocity); // HM: MC_Home on every axis of the mask
    template <typename Fb> MotionReply execute_now(Fb& fb);
};

} // namespace rcsim::motion
