// The motion controller's token interface (the scenario runner is tested in tests/scenarios).
#include "tests/main_cpu/motion/motion_loop.h"

using namespace rcsim::motion;
using namespace rcsim::motion::test;

namespace {

TEST(MotionController, TokensMoveAndReportWithBchCodes) {
    run_motion([](MotionLoop& b) {
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
    run_motion([](MotionLoop& b) {
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

namespace {

constexpr std::int64_t range = (std::int64_t{1} << 30) - 1; // the chip's +-(2^30 - 1)
constexpr std::int64_t above_float = (std::int64_t{1} << 24) + 1; // the first integer a float rounds

TEST(MotionController, PositionsStayIntegersFromTokenToChip) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        // 2^24 + 1 has no float: through a float the move would end at 2^24.
        ASSERT_EQ(b.mc.command("MA", "0," + std::to_string(above_float) + ",10000000,100000000,100000000").bch, 0x00);
        b.cycles(1);
        b.until([&] { return b.mc.axis(0).state() == AxisState::standstill; });
        EXPECT_EQ(b.mc.chip().command_position(0), above_float);
        ASSERT_EQ(b.mc.command("MR", "0,-" + std::to_string(above_float) + ",10000000,100000000,100000000").bch, 0x00);
        b.cycles(1);
        b.until([&] { return b.mc.axis(0).state() == AxisState::standstill; });
        EXPECT_EQ(b.mc.chip().command_position(0), 0);

        // The ends of the chip's range: start 5000 pulses short of them (CNT1/CNT2 preset).
        for (std::int64_t end : {range, -range}) {
            b.mc.api().SetPos(1, end > 0 ? end - 5000 : end + 5000);
            ASSERT_EQ(b.mc.command("MA", "1," + std::to_string(end) + ",100000,1000000,1000000").bch, 0x00);
            b.cycles(1);
            b.until([&] { return b.mc.axis(1).state() == AxisState::standstill; });
            EXPECT_EQ(b.mc.chip().command_position(1), end);
            b.cycles(20);
            EXPECT_EQ(b.mc.positions()[1], end); // the encoder (drive) side too
        }
        // One beyond is refused with 4251 (AXL POSITION_OUTOFBOUND), and fractions are bad data.
        for (const char* d : {"1,1073741824,1000,1000,1000", "1,-1073741824,1000,1000,1000"}) {
            const auto r = b.mc.command("MA", d);
            EXPECT_EQ(r.bch, 0x02) << d;
            EXPECT_EQ(r.data, "4251") << d;
        }
        EXPECT_EQ(b.mc.command("MA", "1,100.5,1000,1000,1000").bch, 0x02);
        EXPECT_EQ(b.mc.command("MA", "1,1e3,1000,1000,1000").bch, 0x02);
        EXPECT_EQ(b.mc.command("ML", "1073741824,0,1000,1000,1000").data, "4251");
        // MR whose target leaves the range: the block reports 4251 when it starts.
        MC_MoveRelative& r = b.mc.blocks(1).move_rel;
        r.Distance = -10, r.Velocity = 1000, r.Acceleration = 10000, r.Deceleration = 10000;
        r.Execute = true;
        b.cycles(1);
        EXPECT_TRUE(r.Error);
        EXPECT_EQ(r.ErrorID, err::position_out_of_bound);
        MC_MoveAbsolute& m = b.mc.blocks(1).move_abs;
        m.Position = static_cast<std::int32_t>(range + 1), m.Velocity = 1000, m.Acceleration = 10000, m.Deceleration = 10000;
        m.Execute = true;
        m.call();
        EXPECT_EQ(m.ErrorID, err::position_out_of_bound);
    });
}

TEST(MotionController, LineAndCircleTokensCarryIntegersAbove2To24) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        const std::string r = std::to_string(above_float);
        ASSERT_EQ(b.mc.command("ML", r + ",-" + r + ",10000000,100000000,100000000").bch, 0x00);
        b.cycles(1);
        b.until([&] { return b.mc.state() == "STANDSTILL"; });
        EXPECT_EQ(b.mc.chip().command_position(0), above_float);
        EXPECT_EQ(b.mc.chip().command_position(1), -above_float);
        // Quarter circle CCW about a centre R = 2^24 + 1 away in +X: from 180 to 270 degrees,
        // ending at centre + (0, -R). A float centre would be 2^24 and the end off this circle.
        b.mc.api().SetPos(0, 0);
        b.mc.api().SetPos(1, 0);
        ASSERT_EQ(b.mc.command("MC", r + ",0," + r + ",-" + r + ",0,9000000").bch, 0x00);
        EXPECT_EQ(b.mc.chip().read_register(0, rcsim::camc::qi::CENT), static_cast<std::uint32_t>(above_float));
        b.cycles(1);
        b.until([&] { return b.mc.state() == "STANDSTILL"; });
        EXPECT_EQ(b.mc.chip().command_position(0), above_float);
        EXPECT_EQ(b.mc.chip().command_position(1), -above_float);
    });
}

} // namespace

namespace {

TEST(MotionController, LmTokenMovesTwoToFourAxesOnOneLine) {
    run_motion([](MotionLoop& b) {
        b.power_on();
        // Three axes: the long axis 0 pulses every step, the others stay within half a pulse of
        // the line (the DDA's round-half-up, camc_qi/README.md).
        ASSERT_EQ(b.mc.command("LM", "7,8000,-4800,3,20000,200000,200000").bch, 0x00);
        b.cycles(1);
        for (unsigned a : {0u, 1u, 2u}) EXPECT_EQ(b.mc.axis(a).state(), AxisState::synchronized_motion) << a;
        EXPECT_EQ(b.mc.axis(3).state(), AxisState::standstill);
        b.cycles(150);
        const double k = static_cast<double>(b.mc.chip().command_position(0));
        ASSERT_GT(k, 100);
        ASSERT_LT(k, 8000);
        EXPECT_LE(std::abs(b.mc.chip().command_position(1) - (-4800.0 * k / 8000)), 0.5);
        EXPECT_LE(std::abs(b.mc.chip().command_position(2) - (3.0 * k / 8000)), 0.5);
        b.until([&] { return b.mc.state() == "STANDSTILL"; });
        EXPECT_EQ(b.mc.chip().command_position(0), 8000);
        EXPECT_EQ(b.mc.chip().command_position(1), -4800);
        EXPECT_EQ(b.mc.chip().command_position(2), 3);
        // Four axes, absolute targets (axis 3 is the long one now).
        ASSERT_EQ(b.mc.command("LM", "15,8100,-4700,-997,-20000,20000,200000,200000").bch, 0x00);
        b.cycles(1);
        EXPECT_EQ(b.mc.axis(3).state(), AxisState::synchronized_motion);
        b.until([&] { return b.mc.state() == "STANDSTILL"; });
        const std::int64_t want[] = {8100, -4700, -997, -20000};
        for (unsigned a = 0; a < 4; ++a) EXPECT_EQ(b.mc.chip().command_position(a), want[a]) << a;
        // Bad data: one axis, a wrong field count, a fraction, beyond the range.
        EXPECT_EQ(b.mc.command("LM", "1,100,1000,1000,1000").bch, 0x02);
        EXPECT_EQ(b.mc.command("LM", "3,100,1000,1000,1000").bch, 0x02);
        EXPECT_EQ(b.mc.command("LM", "3,100,0.5,1000,1000,1000").bch, 0x02);
        EXPECT_EQ(b.mc.command("LM", "3,100,1073741824,1000,1000,1000").data, "4251");
        EXPECT_EQ(b.mc.command("LM", "3,100,100,0,1000,1000").data, "4113");
    });
}

} // namespace
