// Homing and limit switches at exact times (docs/motion.md "Homing", camc_qi/README.md "Sensors
// and homing"): the switches are positions on the axis, the chip stops at the time its profile
// reaches them, and MC_Home / HM run the CAMC-QI library's search, back-off, approach (and Z)
// steps. Every expected position is derived from the profile equations in the comments:
//   a ramp STD -> v at rate a covers (v^2 - STD^2) / (2a) pulses; the chip counts floor(s).
#include "tests/main_cpu/motion/motion_loop.h"

#include <cmath>

using namespace rcsim::motion;
using namespace rcsim::motion::test;

namespace {

constexpr double std_speed = 100, accel = 40000; // MotionConfig start speed, MC_Home's default

double ramp(double v) { return (v * v - std_speed * std_speed) / (2 * accel); }

struct HomingCase {
    double velocity;
    std::int64_t home; // the switch is on at and below this machine position
};

class Homing : public ::testing::TestWithParam<HomingCase> {};

TEST_P(Homing, McHomeStopsOnTheSwitchEdgeToThePulse) {
    const HomingCase c = GetParam();
    MotionConfig cfg;
    cfg.switches[0].home = c.home;
    cfg.switches[0].nelm = -40000;
    // The search reaches its velocity before the switch (a cruise at the edge).
    ASSERT_LT(ramp(c.velocity), static_cast<double>(-c.home));
    run_motion([c](MotionLoop& b) {
        b.power_on();
        MC_Home& h = b.mc.blocks(0).home;
        h.Velocity = c.velocity, h.Position = 500;
        h.Execute = true;
        std::vector<std::int64_t> stops; // machine position at every drive end
        bool was_busy = false;
        for (int i = 0; i < 20000 && !h.Done && !h.Error; ++i) {
            b.cycles(1);
            const bool busy = b.mc.chip().busy(0);
            if (was_busy && !busy) stops.push_back(b.mc.chip().pulse_count(0));
            was_busy = busy;
        }
        ASSERT_TRUE(h.Done) << h.ErrorID;
        ASSERT_EQ(stops.size(), 3u);
        // 1. Search: the switch turns on at c.home, at cruise speed; the slow-down stop from there
        //    runs floor(ramp(v)) pulses further. Sampled once per 1 ms cycle it would stop up to
        //    v/1000 pulses later.
        EXPECT_EQ(stops[0], c.home - static_cast<std::int64_t>(std::floor(ramp(c.velocity))));
        // 2. Back off at 10 kpps: off at c.home + 1, which the ramp reaches at cruise as long as
        //    the search overshoot exceeds ramp(10000); then floor(ramp(10000)) pulses more.
        const std::int64_t off = c.home + 1;
        ASSERT_GT(off - stops[0], ramp(10000));
        EXPECT_EQ(stops[1], off + static_cast<std::int64_t>(std::floor(ramp(10000))));
        // 3. Approach at 2 kpps and stop on the edge itself: the home position, exact.
        EXPECT_EQ(stops[2], c.home);
        EXPECT_EQ(b.mc.chip().pulse_count(0), c.home);
        EXPECT_EQ(b.mc.chip().command_position(0), 500); // set to MC_Home.Position
        EXPECT_EQ(b.mc.axis(0).state(), AxisState::standstill);
    }, cfg);
}

INSTANTIATE_TEST_SUITE_P(Speeds, Homing,
                         ::testing::Values(HomingCase{10000, -2500}, HomingCase{20000, -9000},
                                           HomingCase{30000, -15000}),
                         [](const auto& info) { return std::to_string(int(info.param.velocity / 1000)) + "kpps"; });

TEST(HomingToken, HmAtTheDefault10KppsAndAt30KppsEndsOnTheSwitch) {
    MotionConfig cfg;
    cfg.switches[1].home = -2500;
    cfg.switches[1].nelm = -4000; // 1500 behind the switch: more than the search overshoot
    cfg.switches[2].home = -20000;
    run_motion([](MotionLoop& b) {
        b.power_on();
        // 10 kpps: the search overshoot is floor(ramp(10000)) = 1249 pulses, NELM 1500 behind.
        ASSERT_EQ(b.mc.command("HM", "2").bch, 0x00);
        ASSERT_EQ(b.mc.command("HM", "4,30000").bch, 0x00);
        b.cycles(1);
        EXPECT_EQ(b.mc.state(), "HOMING");
        b.until([&] { return b.mc.state() == "STANDSTILL"; });
        EXPECT_EQ(b.mc.chip().pulse_count(1), -2500);
        EXPECT_EQ(b.mc.chip().command_position(1), 0);
        EXPECT_EQ(b.mc.chip().pulse_count(2), -20000);
        EXPECT_EQ(b.mc.chip().command_position(2), 0);
        EXPECT_EQ(b.mc.command("HM", "2,abc").bch, 0x02);
        EXPECT_EQ(b.mc.command("HM", "2,20000000").data, std::to_string(err::velocity_out_of_bound));
    }, cfg);
}

TEST(HomingToken, ZPhaseAfterTheApproachStopsOnTheNextZPulse) {
    MotionConfig cfg;
    cfg.switches[0].home = -2500;
    cfg.zphase[0] = {1000, 137}; // Z at ..., -2863, -1863, ... (137 mod 1000)
    run_motion([](MotionLoop& b) {
        b.power_on();
        MC_Home& h = b.mc.blocks(0).home;
        h.ZPhase = true, h.ZVelocity = 1000, h.Position = -7;
        h.Execute = true;
        b.until([&] { return h.Done || h.Error; });
        ASSERT_TRUE(h.Done);
        // From the switch edge -2500 the Z search leaves the switch (+): the next Z is -1863.
        EXPECT_EQ(b.mc.chip().pulse_count(0), -1863);
        EXPECT_EQ(b.mc.chip().command_position(0), -7);
    }, cfg);
}

TEST(Limits, NelmStopsAtItsPositionWithoutAHomeSwitchAndPelmDuringAMove) {
    MotionConfig cfg;
    cfg.switches[0].nelm = -5000; // no home switch: the search runs into NELM
    cfg.switches[1].pelm = 12345;
    run_motion([](MotionLoop& b) {
        b.power_on();
        ASSERT_EQ(b.mc.command("HM", "1").bch, 0x00);
        b.until([&] { return b.mc.state() == "ERRORSTOP"; });
        EXPECT_EQ(b.mc.axis(0).error_id(), err::limit_negative);
        // Emergency stop mode (the reset UCFG1): frozen on the switch's first position.
        EXPECT_EQ(b.mc.chip().pulse_count(0), -5000);
        EXPECT_EQ(b.mc.command("RS", "1").bch, 0x00);
        b.until([&] { return b.mc.axis(0).state() == AxisState::standstill; }, 100);
        // PELM during a 30 kpps move: stopped on 12345, not a cycle's 30 pulses later.
        ASSERT_EQ(b.mc.command("MA", "1,50000,30000,300000,300000").bch, 0x00);
        b.until([&] { return b.mc.axis(1).state() == AxisState::error_stop; });
        EXPECT_EQ(b.mc.axis(1).error_id(), err::limit_positive);
        EXPECT_EQ(b.mc.chip().pulse_count(1), 12345);
        EXPECT_EQ(b.mc.chip().read_register(1, rcsim::camc::qi::REMAIN), 50000u - 12345u);
    }, cfg);
}

} // namespace
