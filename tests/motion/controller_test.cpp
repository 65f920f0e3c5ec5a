// The motion controller's token interface (the scenario runner is tested in tests/scenarios).
#include "tests/motion/motion_bench.h"

using namespace rcsim::motion;
using namespace rcsim::motion::test;

namespace {

TEST(MotionController, TokensMoveAndReportWithBchCodes) {
    run_bench([](Bench& b) {
        EXPECT_EQ(b.mc.command("XX", "").bch, 0x01);
        EXPECT_EQ(b.mc.command("SV", "2").bch, 0x02);
        EXPECT_EQ(b.mc.command("MA", "0,100,1000,1000,1000").bch, 0x04); // not powered
        EXPECT_EQ(b.mc.command("MA", "0,100,abc,1000,1000").bch, 0x02);
        EXPECT_EQ(b.mc.state(), "DISABLED");
        b.power_on();
        EXPECT_EQ(b.mc.state(), "STANDSTILL");
        EXPECT_EQ(b.mc.command("MA", "2,-3000,20000,200000,200000").bch, 0x00);
        EXPECT_EQ(b.mc.command("ML", "1000,2000,20000,200000,200000").bch, 0x00);
        b.until([&] { return b.mc.state() == "STANDSTILL"; });
        b.cycles(20); // let the drives settle
        const auto p = b.mc.positions();
        EXPECT_EQ(p[0], 1000);
        EXPECT_EQ(p[1], 2000);
        EXPECT_EQ(p[2], -3000);
        // Half circle CCW about (0,2000) from (1000,2000) to (-1000,2000).
        EXPECT_EQ(b.mc.command("MC", "0,2000,-1000,2000,0,10000").bch, 0x00);
        b.cycles(1);
        b.until([&] { return b.mc.state() == "STANDSTILL"; });
        EXPECT_EQ(b.mc.chip().command_position(0), -1000);
        EXPECT_EQ(b.mc.chip().command_position(1), 2000);
        EXPECT_EQ(b.mc.command("SV", "0").bch, 0x00);
        b.cycles(1);
        EXPECT_EQ(b.mc.state(), "DISABLED");
    });
}

TEST(MotionController, ConsecutiveTokensOnOneBlockEachMove) {
    run_bench([](Bench& b) {
        b.power_on();
        for (int target : {4000, -2000, 1000}) {
            ASSERT_EQ(b.mc.command("MA", "0," + std::to_string(target) + ",30000,200000,200000").bch, 0x00);
            b.cycles(1);
            EXPECT_EQ(b.mc.axis(0).state(), AxisState::discrete_motion) << target;
            b.until([&] { return b.mc.axis(0).state() == AxisState::standstill; });
            EXPECT_EQ(b.mc.chip().command_position(0), target);
        }
    });
}

} // namespace
