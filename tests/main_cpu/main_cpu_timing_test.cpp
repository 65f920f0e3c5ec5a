// Tests of the main CPU's one processor in time: the control cycle's jitter and overruns, the
// INT_R handler's latency, BUSY wait states on each access, and a control cycle whose length
// comes from the motion work. Frames and mailbox words are main_cpu_test.cpp; the set-up both use
// is main_cpu_on_fakes.h.
#include "tests/main_cpu/main_cpu_on_fakes.h"

#include <vector>

using namespace rcsim;
using namespace rcsim::dpram_layout;
using namespace rcsim::test::main_cpu;
using rcsim::test::CommSide;
using sc_core::sc_time;

TEST(MainCpu, ControlCycleJitterIsZeroWithoutTraffic) {
    MainCpuOnFakes b;
    sc_core::sc_start(ms(10) - us(1));
    const Summary s = b.cpu.cycle_jitter_us().summary();
    EXPECT_EQ(s.count, 10u);
    EXPECT_EQ(s.max, 0.0);
    EXPECT_EQ(b.cpu.cycle_overruns(), 0u);
}

TEST(MainCpu, DpramBurstOverlappingACycleStartDelaysItByTheRestOfTheBurst) {
    MainCpuOnFakes b;
    b.comm.script = [](CommSide& c) {
        sc_core::wait(ms(1) - us(20)); // a full 339-byte chunk arrives just before the 1 ms cycle
        c.put_chunk(0, cmd("EC", std::string(400, 'b')).substr(0, chunk_size));
    };
    sc_core::sc_start(ms(3) - us(1));
    const auto acks = b.ram.writes_to(int2ext);
    ASSERT_EQ(acks.size(), 1u);
    // The handler holds the processor until its ACK write's bus cycle ends; the cycle starts then.
    const sc_time handler_end = acks[0].time + b.cycle();
    ASSERT_GT(handler_end, ms(1));
    const Summary s = b.cpu.cycle_jitter_us().summary();
    EXPECT_EQ(s.count, 3u);
    EXPECT_DOUBLE_EQ(s.max, to_us(handler_end - ms(1)));
    EXPECT_EQ(s.min, 0.0); // cycles 0 and 2 are on time
}

TEST(MainCpu, ControlCycleDelaysTheIntRHandler) {
    MainCpuOnFakes b;
    b.comm.script = [](CommSide& c) {
        sc_core::wait(ms(1) + us(10)); // during the 1 ms cycle's 100 us of work
        c.put_chunk(0, cmd("EC", "x"));
    };
    sc_core::sc_start(ms(2) - us(1));
    const Summary lat = b.cpu.irq_latency_us().summary();
    ASSERT_EQ(lat.count, 1u);
    // Waits for the cycle to end at 1.1 ms, then the 5 us entry.
    EXPECT_DOUBLE_EQ(lat.max, to_us(b.cpu.config().cycle_time - us(10) + b.cpu.config().irq_entry));
}

TEST(MainCpu, IntRLatencyOfAnIdleProcessorIsTheEntryTime) {
    MainCpuOnFakes b;
    b.comm.script = [](CommSide& c) {
        sc_core::wait(us(500)); // between two control cycles
        c.put_chunk(0, cmd("EC", "x"));
    };
    sc_core::sc_start(ms(1) - us(1));
    const Summary lat = b.cpu.irq_latency_us().summary();
    ASSERT_EQ(lat.count, 1u);
    EXPECT_DOUBLE_EQ(lat.max, to_us(b.cpu.config().irq_entry));
}

TEST(MainCpu, ACycleStartedAfterItsSuccessorsIdealStartSkipsAPeriod) {
    MainCpuOnFakes b;
    b.ram.busy_wait_states = 70; // 339 bytes x 78 clocks: the handler holds the CPU 1.65 ms
    b.comm.script = [](CommSide& c) {
        sc_core::wait(us(950));
        c.put_chunk(0, cmd("EC", std::string(400, 'o')).substr(0, chunk_size));
    };
    sc_core::sc_start(ms(4) - us(1));
    // Cycle 0 on time; cycle 1 (ideal 1 ms) starts after 2 ms, so the 2 ms start is skipped;
    // cycle 3 on time.
    EXPECT_EQ(b.cpu.cycle_overruns(), 1u);
    EXPECT_EQ(b.cpu.control_cycles(), 3u);
    const Summary s = b.cpu.cycle_jitter_us().summary();
    EXPECT_GT(s.max, 1000.0);
    EXPECT_EQ(s.min, 0.0);
}

TEST(MainCpu, BusyWaitStatesFromTheTargetExtendEachAccess) {
    MainCpuOnFakes b;
    b.ram.busy_wait_states = 3;
    b.comm.script = [](CommSide& c) { c.send_frame(0, cmd("EC", "abcdef")); };
    sc_core::sc_start(ms(1) - us(1));
    std::vector<test::RightAccess> reads; // the handler's copy loop over data[0]
    for (const auto& a : b.ram.log)
        if (a.kind == BusCycle::mem_read && a.addr < chunk_size) reads.push_back(a);
    ASSERT_GE(reads.size(), 10u);
    // Consecutive copy-loop reads are one bus cycle + 3 BUSY cycles + the loop overhead apart.
    const sc_time step = b.cycle(3, b.cpu.config().copy_loop_cycles);
    for (std::size_t i = 1; i < reads.size(); ++i) EXPECT_EQ(reads[i].time - reads[i - 1].time, step);
    EXPECT_EQ(b.cpu.busy_wait(), Clock(b.cpu.config().bus_clock_hz).cycles(3 * b.cpu.dpram_accesses()));
    EXPECT_GT(b.cpu.busy_wait(), sc_core::SC_ZERO_TIME);
}

namespace {
/// A motion layer whose control cycle spends `work` of processor time (a cost model).
class WorkingMotion : public FakeMotion {
public:
    sc_time work = us(300);
    void control_cycle(const sc_time& now) override {
        FakeMotion::control_cycle(now);
        sc_core::wait(work);
    }
};
} // namespace

// The cycle's duration is its motion work plus cycle_time (100 us), and the work holds the
// processor: an INT_R that comes during it waits for its end.
TEST(MainCpu, ControlCycleDurationComesFromTheMotionWork) {
    MainCpuOnFakes b;
    WorkingMotion m;
    b.cpu.set_motion(&m);
    b.comm.script = [](CommSide& c) {
        sc_core::wait(ms(1) + us(50)); // 50 us into the 1 ms cycle's 400 us
        c.put_chunk(0, cmd("EC", "x"));
    };
    sc_core::sc_start(ms(3) - us(1));
    const Summary d = b.cpu.cycle_duration_us().summary();
    EXPECT_EQ(d.count, 3u);
    EXPECT_DOUBLE_EQ(d.min, 400.0);
    EXPECT_DOUBLE_EQ(d.max, 400.0);
    const Summary lat = b.cpu.irq_latency_us().summary();
    ASSERT_EQ(lat.count, 1u);
    EXPECT_DOUBLE_EQ(lat.max, 350.0 + to_us(b.cpu.config().irq_entry));
    EXPECT_EQ(b.cpu.report()["cycle_duration_us"]["max"], 400.0);
}

TEST(MainCpu, ReportHasNoCycleDurationWithoutAMotionLayer) {
    MainCpuOnFakes b;
    sc_core::sc_start(ms(2) - us(1));
    EXPECT_EQ(b.cpu.cycle_duration_us().summary().count, 2u);
    EXPECT_FALSE(b.cpu.report().contains("cycle_duration_us")); // reports of such runs stay as they were
}
