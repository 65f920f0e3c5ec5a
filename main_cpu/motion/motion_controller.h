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
#include <optional>
#include <string>
#include <vector>
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
    /// The main CPU's cost of the motion work (docs/motion.md "Main-CPU cost"). With a bus cycle
    /// set, every CAMC-QI access takes (access_cycles + the chip's wait states) bus cycles per
    /// byte (a byte-wide bus, like the DP-RAM's) and every block call `fb_call`; the controller
    /// then spends that time with wait(), so it must be called from an SC_THREAD. Zero: no cost
    /// (the motion scenario's default, where nothing else competes for the processor).
    struct Cost {
        sc_core::sc_time bus_cycle = sc_core::SC_ZERO_TIME;
        unsigned access_cycles = 4;
        sc_core::sc_time fb_call = sc_core::SC_ZERO_TIME;
    } cost;
    /// A cyclic-position path (CiA402 CSP, mode 8) on two axes the CAMC-QI does not drive: every
    /// control cycle the main CPU computes the set-point of a circle and writes it to the drive's
    /// 0x607A; the drive takes it at its own SYNC instant, `sync_offset` after each ideal cycle
    /// start (multiples of `period` from time 0). A set-point written after that instant misses
    /// it: the drive goes on with the previous one for that period, and the path shows it.
    struct Csp {
        unsigned axis_x = 2, axis_y = 3;
        double radius = 2000;   // pulses; the centre is `radius` in -X of the start: CCW from (0, 0)
        double velocity = 10000; // pulses/s along the path
        sc_core::sc_time start = sc_core::sc_time(100, sc_core::SC_MS);
        sc_core::sc_time period = sc_core::sc_time(1, sc_core::SC_MS);
        sc_core::sc_time sync_offset = sc_core::sc_time(250, sc_core::SC_US);
    };
    std::optional<Csp> csp;
    /// Command latency: after each accepted move the pulse counters are polled this often until
    /// the first pulse (zero: not measured).
    sc_core::sc_time first_pulse_poll = sc_core::SC_ZERO_TIME;
};

/// What the motion layer looks like at one instant, for reports and live views.
struct MotionSnapshot {
    double t_s = 0;
    std::array<std::int64_t, 4> cmd{}, act{}; // CAMC-QI CNT1 / CNT2, pulses
    std::array<AxisState, 4> axis_state{};
    std::string state;                         // the ST token's robot state
};

/// What the CSP path did: set-points written, SYNC instants missed, and how far the set-point
/// the drive took was from the path at its SYNC instant.
struct CspStats {
    /// A SYNC the set-point came too late for, and why: the cycle's start against its ideal one,
    /// and who held the processor then.
    struct Miss {
        sc_core::sc_time sync, written, cycle_ideal, cycle_start;
        std::string held_by; // "" when the processor was free at the ideal start
        double setpoint_error = 0; // pulses: the set-point taken against the path at this SYNC
    };
    std::optional<Miss> first_miss;
    std::uint64_t setpoints = 0, missed = 0;
    double max_setpoint_error = 0; // pulses, per axis
    double max_actual_radial_error = 0; // pulses: the drives' actual path from the circle
};

/// An accepted MC token in absolute pulses of axes 0/1, and when its block reported an outcome.
struct CircleRecord {
    sc_core::sc_time at;
    double start_x = 0, start_y = 0, center_x = 0, center_y = 0, end_x = 0, end_y = 0;
    bool ccw = true;
    std::optional<sc_core::sc_time> outcome_at;
};

/// An accepted move token (MA MR ML MC HM): when it was accepted and when the first pulse left.
struct MoveRecord {
    std::string token;
    sc_core::sc_time accepted;
    std::optional<sc_core::sc_time> first_pulse;
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
    void cycle_context(const sc_core::sc_time& ideal, const std::string& held_by) override;
    std::vector<std::int64_t> positions() const override;
    std::string state() const override;

    camc::CamcQi& chip() { return chip_; }
    Cia402Drive& drive(unsigned a) { return drives_[a]; }
    McAxis& axis(unsigned a) { return *axes_[a]; }
    QiMotionApi& api() { return api_; }
    MC_Power& power(unsigned a) { return power_[a]; }
    TrajectoryRecorder& recorder() { return recorder_; }
    MotionSnapshot snapshot() const;
    /// The last accepted MC token (none before one).
    const std::optional<CircleRecord>& last_circle() const { return circle_record_; }
    /// The first kMaxMoveRecords accepted move tokens.
    static constexpr std::size_t kMaxMoveRecords = 256;
    const std::vector<MoveRecord>& moves() const { return moves_; }
    /// Bus time spent on CAMC-QI accesses and block calls (the cost model), in all.
    sc_core::sc_time bus_time() const { return bus_time_; }
    sc_core::sc_time fb_time() const { return fb_time_; }
    std::uint64_t chip_accesses() const { return chip_accesses_; }
    const CspStats& csp_stats() const { return csp_stats_; }

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
        MC_SetPosition set_pos;
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
    std::optional<CircleRecord> circle_record_;
    std::vector<MoveRecord> moves_;
    sc_core::sc_event move_accepted_;
    sc_core::sc_time bus_time_, fb_time_;
    sc_core::sc_time deferred_cost_; // work done outside a thread, spent at the next control cycle
    std::uint64_t chip_accesses_ = 0;
    CspStats csp_stats_;
    std::array<std::int32_t, 2> csp_latched_{}; // the set-points the CSP drives took at their SYNC
    std::array<std::int32_t, 2> csp_written_{}; // the last set-points written
    bool csp_running_ = false;
    void csp_cycle();
    sc_core::sc_time cycle_ideal_, cycle_start_; // this control cycle's (cycle_context)
    std::string cycle_held_by_;
    bool context_given_ = false;
    /// The CSP circle's set-point at `t` (before the start: the start point).
    std::array<double, 2> csp_point(const sc_core::sc_time& t) const;

    /// The cost model: spends `t` of processor time (wait) in the calling thread; called from
    /// outside a thread (a monitor's console command between two sc_start()s) it is kept and
    /// spent at the start of the next control cycle, so the work still costs the processor.
    void spend(const sc_core::sc_time& t);
    void call_block(McExecuteFb& fb);
    void note_move(const std::string& token);
    void first_pulse_watch();
    MotionReply execute(const std::string& token, const std::string& data);

    void update_mechanism();
    MotionReply fb_reply(std::uint16_t error_id) const;
    MotionReply home(unsigned mask, double velocity); // HM: MC_Home on every axis of the mask
    template <typename Fb> MotionReply execute_now(Fb& fb);
};

} // namespace rcsim::motion
