// The main-CPU cost model of the motion layer (docs/motion.md "Main-CPU cost"), the first-pulse
// watch behind the command latency, the snapshot, and the cyclic-position (CSP) path.
#include "main_cpu/motion/motion_controller.h"
#include "motion_loop.h"

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <vector>

using namespace rcsim::motion;
using rcsim::motion::test::MotionLoop;
using rcsim::motion::test::run_motion;
using sc_core::sc_time;
using sc_core::SC_US;

namespace {

sc_time us_(double v) { return sc_time(v, SC_US); }

/// The simulated time one control cycle takes (it is called from MotionLoop's thread).
sc_time cycle_cost(MotionLoop& b) {
    const sc_time t0 = sc_core::sc_time_stamp();
    b.mc.control_cycle(t0);
    return sc_core::sc_time_stamp() - t0;
}

MotionConfig with_cost(double bus_hz, unsigned access_cycles, double fb_us) {
    MotionConfig c;
    if (bus_hz > 0) c.cost.bus_cycle = sc_time(1.0 / bus_hz, sc_core::SC_SEC);
    c.cost.access_cycles = access_cycles;
    c.cost.fb_call = us_(fb_us);
    return c;
}

/// One control cycle's cost and the chip accesses it made, under `cfg`, after power-on.
std::pair<sc_time, std::uint64_t> one_cycle(const MotionConfig& cfg) {
    sc_time cost;
    std::uint64_t accesses = 0;
    run_motion(
        [&](MotionLoop& b) {
            b.power_on();
            const std::uint64_t a0 = b.mc.chip_accesses();
            cost = cycle_cost(b);
            accesses = b.mc.chip_accesses() - a0;
        },
        cfg);
    return {cost, accesses};
}

} // namespace

TEST(MotionCost, NoCostModelTakesNoTime) {
    const auto [cost, accesses] = one_cycle(MotionConfig{});
    EXPECT_EQ(cost, sc_core::SC_ZERO_TIME);
    EXPECT_GT(accesses, 0u) << "the cycle reads the chip";
}

// Every block is called once a cycle: per axis MC_Power and the seven blocks of Blocks (reset,
// home, move_abs, move_rel, move_vel, halt, stop), then MC_LineMove2, MC_LineMove (the LM token)
// and MC_CircleCenterMove: 4 x 8 + 3 = 35 calls.
TEST(MotionCost, EveryBlockCallCostsFbCall) {
    const auto [cost, accesses] = one_cycle(with_cost(0, 4, 5));
    EXPECT_EQ(cost, us_(35 * 5.0));
}

namespace {

/// Several controllers with their own configurations in one simulation (one sc_start a process):
/// `body` runs in a checked thread with all of them.
void run_many(const std::vector<MotionConfig>& cfgs, const std::function<void(std::vector<MotionController*>&)>& body) {
    std::vector<std::unique_ptr<MotionController>> mcs;
    std::vector<MotionController*> raw;
    for (std::size_t i = 0; i < cfgs.size(); ++i) {
        mcs.push_back(std::make_unique<MotionController>(("mc" + std::to_string(i)).c_str(), cfgs[i]));
        raw.push_back(mcs.back().get());
    }
    rcsim::test::spawn_checked([&] {
        body(raw);
        sc_core::sc_stop();
    });
    sc_core::sc_start();
}

/// Powers every controller on (SV 1, six 1 ms cycles each), then measures one cycle of each.
std::vector<std::pair<sc_time, std::uint64_t>> cycle_costs(const std::vector<MotionConfig>& cfgs) {
    std::vector<std::pair<sc_time, std::uint64_t>> out;
    run_many(cfgs, [&](std::vector<MotionController*>& mcs) {
        for (MotionController* mc : mcs) mc->command("SV", "1");
        for (int i = 0; i < 6; ++i) {
            for (MotionController* mc : mcs) mc->control_cycle(sc_core::sc_time_stamp());
            sc_core::wait(sc_time(1, sc_core::SC_MS));
        }
        for (MotionController* mc : mcs) {
            const std::uint64_t a0 = mc->chip_accesses();
            const sc_time t0 = sc_core::sc_time_stamp();
            mc->control_cycle(t0);
            out.emplace_back(sc_core::sc_time_stamp() - t0, mc->chip_accesses() - a0);
        }
    });
    return out;
}

} // namespace

// A byte takes access_cycles + the chip's one wait state (camc_qi/README.md) bus cycles: with
// access_cycles 4 at 16 MHz 312.5 ns, with 9 twice that, at 8 MHz twice again.
TEST(MotionCost, ChipAccessesCostBusCyclesWithWaitStates) {
    const auto r = cycle_costs({with_cost(16e6, 4, 0), with_cost(16e6, 9, 0), with_cost(8e6, 4, 0)});
    const auto [c16, n16] = r[0];
    ASSERT_GT(c16, sc_core::SC_ZERO_TIME);
    EXPECT_EQ(r[1].second, n16);
    EXPECT_EQ(r[2].second, n16);
    EXPECT_EQ(r[1].first, c16 * 2.0);
    EXPECT_EQ(r[2].first, c16 * 2.0);
    // At least one byte per access: 5 cycles of 62.5 ns.
    EXPECT_GE(c16, sc_time(312.5 * double(n16), sc_core::SC_NS));
}

TEST(MotionCost, CommandCostsItsBlockCallsToo) {
    sc_time cost;
    run_motion(
        [&](MotionLoop& b) {
            b.power_on();
            const sc_time t0 = sc_core::sc_time_stamp();
            EXPECT_EQ(b.mc.command("MA", "0,1000,10000,100000,100000").bch, 0);
            cost = sc_core::sc_time_stamp() - t0;
        },
        with_cost(0, 4, 5));
    // The Execute edge: one call with Execute low, one with it high (MotionController::execute_now).
    EXPECT_EQ(cost, us_(2 * 5.0));
}

// A console command between two sc_start()s (the remote monitor's) runs outside any thread: its
// cost cannot be waited for there, so the next control cycle spends it on top of its own 35 block
// calls (EveryBlockCallCostsFbCall).
TEST(MotionCost, CostOutsideAThreadIsSpentAtTheNextControlCycle) {
    MotionController mc("mc", with_cost(0, 4, 5));
    const sc_time before = mc.fb_time();
    mc.command("SV", "1");
    mc.command("MA", "0,1000,10000,100000,100000");
    const sc_time deferred = mc.fb_time() - before;
    ASSERT_GT(deferred, sc_core::SC_ZERO_TIME) << "the commands called blocks";
    EXPECT_EQ(sc_core::sc_time_stamp(), sc_core::SC_ZERO_TIME) << "no time passed outside a thread";
    sc_time first, second;
    rcsim::test::spawn_checked([&] {
        sc_time t0 = sc_core::sc_time_stamp();
        mc.control_cycle(t0);
        first = sc_core::sc_time_stamp() - t0;
        t0 = sc_core::sc_time_stamp();
        mc.control_cycle(t0);
        second = sc_core::sc_time_stamp() - t0;
        sc_core::sc_stop();
    });
    sc_core::sc_start();
    EXPECT_EQ(first, us_(35 * 5.0) + deferred);
    EXPECT_EQ(second, us_(35 * 5.0));
}

// The first pulse of a move from standstill comes when the profile has made one step: with
// start speed STD and acceleration a, s(t) = STD t + a t^2 / 2 = 1. At STD = 100 pulses/s and
// a = 1e5 pulses/s^2: t = (-100 + sqrt(100^2 + 2e5)) / 1e5 = 3.58 ms, measured to the 1 us poll.
TEST(MotionCost, FirstPulseOfAMoveIsWatched) {
    MotionConfig cfg;
    cfg.first_pulse_poll = us_(1);
    run_motion(
        [&](MotionLoop& b) {
            b.power_on();
            ASSERT_EQ(b.mc.command("MA", "0,1000,10000,100000,100000").bch, 0);
            EXPECT_EQ(b.mc.command("MA", "9,1,1,1,1").bch, 2); // refused: no record
            b.cycles(20);
            ASSERT_EQ(b.mc.moves().size(), 1u);
            const MoveRecord& m = b.mc.moves()[0];
            EXPECT_EQ(m.token, "MA");
            ASSERT_TRUE(m.first_pulse);
            const double ms = (*m.first_pulse - m.accepted).to_seconds() * 1e3;
            EXPECT_NEAR(ms, 3.583, 0.003);
        },
        cfg);
}

TEST(MotionCost, SnapshotHasPositionsAndStates) {
    run_motion([&](MotionLoop& b) {
        b.power_on();
        ASSERT_EQ(b.mc.command("MR", "1,500,10000,100000,100000").bch, 0);
        b.cycles(300);
        const MotionSnapshot s = b.mc.snapshot();
        EXPECT_EQ(s.cmd[1], 500);
        EXPECT_EQ(s.cmd[0], 0);
        EXPECT_EQ(s.axis_state[1], AxisState::standstill);
        EXPECT_EQ(s.state, "STANDSTILL");
        EXPECT_DOUBLE_EQ(s.t_s, sc_core::sc_time_stamp().to_seconds());
    });
}

namespace {

MotionConfig csp_config(double fb_us) {
    MotionConfig cfg = with_cost(0, 4, fb_us);
    MotionConfig::Csp csp;
    csp.start = sc_time(10, sc_core::SC_MS);
    csp.sync_offset = us_(250);
    cfg.csp = csp;
    return cfg;
}

} // namespace

// The set-point is the cycle's first work: written one block call (the CSP computation) into the
// cycle, before the cycle's 30 block calls. At 10 us a call those take 300 us, past the SYNC at
// 250 us, yet every set-point is in time (written after them, every one missed its SYNC).
TEST(MotionCost, CspSetPointIsWrittenBeforeTheCyclesBlockCalls) {
    std::vector<CspStats> st;
    run_many({csp_config(10)}, [&](std::vector<MotionController*>& mcs) {
        mcs[0]->command("SV", "1");
        for (int k = 0; k < 300; ++k) {
            const sc_time ideal(k, sc_core::SC_MS);
            if (sc_core::sc_time_stamp() < ideal) sc_core::wait(ideal - sc_core::sc_time_stamp());
            mcs[0]->control_cycle(sc_core::sc_time_stamp());
        }
        st.push_back(mcs[0]->csp_stats());
    });
    ASSERT_EQ(st.size(), 1u);
    EXPECT_GT(st[0].setpoints, 280u);
    EXPECT_EQ(st[0].missed, 0u);
    EXPECT_FALSE(st[0].first_miss);
    EXPECT_LE(st[0].max_setpoint_error, 0.5);
}

// A cycle that gets the processor 245 us after its ideal start writes its set-point 10 us later,
// 5 us after the SYNC at 250 us: the drive takes the set-point of the cycle before, one cycle of
// path behind: v T = 10000 pulses/s x 1 ms = 10 pulses (rounding: +-1). The first miss keeps
// its SYNC, the cycle's late start and who held the processor.
TEST(MotionCost, CspSetPointOfALateCycleMissesTheSync) {
    std::vector<CspStats> st;
    run_many({csp_config(10)}, [&](std::vector<MotionController*>& mcs) {
        mcs[0]->command("SV", "1");
        for (int k = 0; k < 300; ++k) {
            const sc_time ideal(k, sc_core::SC_MS), start = ideal + us_(245);
            if (sc_core::sc_time_stamp() < start) sc_core::wait(start - sc_core::sc_time_stamp());
            mcs[0]->cycle_context(ideal, "the INT_R handler");
            mcs[0]->control_cycle(sc_core::sc_time_stamp());
        }
        st.push_back(mcs[0]->csp_stats());
    });
    ASSERT_EQ(st.size(), 1u);
    EXPECT_EQ(st[0].missed, st[0].setpoints);
    EXPECT_NEAR(st[0].max_setpoint_error, 10.0, 1.0);
    ASSERT_TRUE(st[0].first_miss);
    const CspStats::Miss& m = *st[0].first_miss;
    EXPECT_EQ(m.sync, sc_time(10, sc_core::SC_MS) + us_(250)); // the first cycle of the path (start 10 ms)
    EXPECT_EQ(m.cycle_ideal, sc_time(10, sc_core::SC_MS));
    EXPECT_EQ(m.cycle_start - m.cycle_ideal, us_(245));
    EXPECT_EQ(m.written - m.sync, us_(5));
    EXPECT_EQ(m.held_by, "the INT_R handler");
}
