// The CAMC-QI's blended start (camc_qi/README.md "Blending", issue #49 item 2): a drive queued
// behind a running one, which re-plans its end to JEXIT and hands over at that speed, no stop.
// Expected values are the kinematics of the programmed ramps.
#include "tests/camc_qi/chip_host.h"

#include <algorithm>
#include <functional>

using namespace rcsim;
using namespace rcsim::camc;
using sc_core::sc_time;
using sc_core::SC_MS;
using sc_core::SC_US;

namespace {

using camc_test::Host;
using camc_test::run;

/// A preset drive of `dist` at `obj`, 100000 pulses/s^2 both ways, STD 100; blended if `jspd`.
void move(Host& h, std::int32_t dist, std::uint32_t obj, std::uint32_t jspd = 0, std::uint32_t jexit = 0) {
    h.cmd(0, qi::write | qi::STD, 100);
    h.cmd(0, qi::write | qi::OBJ, obj);
    h.cmd(0, qi::write | qi::RATE1, 100000);
    h.cmd(0, qi::write | qi::RATE2, 100000);
    h.cmd(0, qi::write | qi::JSPD, jspd);
    h.cmd(0, qi::write | qi::JEXIT, jexit);
    h.cmd(0, qi::write | qi::DCFG, (dcfg::preset << dcfg::mode_shift) | 1u | (jspd ? dcfg::blend : 0));
    h.cmd(0, qi::write | qi::POS, static_cast<std::uint32_t>(dist));
    h.cmd(0, qi::STRN);
}

TEST(CamcQiBlend, AQueuedDriveTakesOverAtTheJunctionSpeedWithoutAStop) {
    run([](Host& h) {
        h.chip.trace_pulses(0, true);
        move(h, 10000, 20000);
        wait(sc_time(300, SC_MS)); // cruising at 20000 (the ramp takes 0.2 s, 2000 pulses)
        move(h, 10000, 10000, 15000, 15000);
        EXPECT_FALSE(h.chip.drive_status(0) & drvst::queue_empty) << "the blended drive waits";
        bool stopped = false;
        while (h.chip.busy(0)) {
            wait(sc_time(100, SC_US));
            // Below 1000 pulses/s before the second drive's own final ramp (its last 500 pulses).
            stopped |= h.chip.busy(0) && h.chip.current_speed(0) < 1000 && h.chip.command_position(0) < 19000;
        }
        EXPECT_EQ(h.chip.command_position(0), 20000) << "both drives end exactly";
        EXPECT_TRUE(h.chip.drive_status(0) & drvst::queue_empty);
        const auto& tr = h.chip.pulse_trace();
        ASSERT_EQ(tr.size(), 20000u);
        // At the junction (pulse 10000) the pulses are 1/15000 s apart: the first drive slowed
        // from 20000 to JEXIT = 15000 on its last 875 pulses, the second starts at JSPD = 15000.
        EXPECT_NEAR((tr[10000].time - tr[9999].time).to_seconds(), 1 / 15000.0, 1e-6);
        EXPECT_NEAR((tr[9000].time - tr[8999].time).to_seconds(), 1 / 20000.0, 1e-7) << "before the 875";
        // The second drive then slows to its 10000 within (15000^2 - 10000^2) / 200000 = 625 pulses.
        EXPECT_NEAR((tr[10700].time - tr[10699].time).to_seconds(), 1 / 10000.0, 1e-7);
        EXPECT_FALSE(stopped);
    });
}

TEST(CamcQiBlend, AStopCancelsTheQueuedDriveAndAPlainStartWhileBusyIsIgnored) {
    run([](Host& h) {
        move(h, 10000, 20000);
        wait(sc_time(300, SC_MS));
        {
            test::ScAllowWarnings allow;
            move(h, 10000, 10000); // no blend bit: ignored, as before (a warning)
        }
        EXPECT_TRUE(h.chip.drive_status(0) & drvst::queue_empty);
        move(h, 10000, 10000, 15000, 15000);
        EXPECT_FALSE(h.chip.drive_status(0) & drvst::queue_empty);
        h.cmd(0, qi::SSTOP);
        while (h.chip.busy(0)) wait(sc_time(100, SC_US));
        EXPECT_LT(h.chip.command_position(0), 10000) << "the slow-down stop ends the first drive early";
        EXPECT_TRUE(h.chip.drive_status(0) & drvst::queue_empty);
        wait(sc_time(100, SC_MS));
        EXPECT_FALSE(h.chip.busy(0)) << "the queued drive never starts";
    });
}

// Take-over (PLCopen Aborting): a continuous drive at 10000 replaced by a preset to the absolute
// position 20000 at 15000 goes on from 10000, never slower, and ends exactly there; a take-over
// that reverses is ignored.
TEST(CamcQiBlend, ATakeOverReplacesTheDriveFromItsPresentSpeed) {
    run([](Host& h) {
        h.cmd(0, qi::write | qi::OBJ, 10000);
        h.cmd(0, qi::write | qi::RATE1, 100000);
        h.cmd(0, qi::write | qi::RATE2, 100000);
        h.cmd(0, qi::write | qi::DCFG, (dcfg::cont_pos << dcfg::mode_shift) | 1u);
        h.cmd(0, qi::STRN);
        wait(sc_time(300, SC_MS));
        {
            test::ScAllowWarnings allow;
            h.cmd(0, qi::write | qi::DCFG, (dcfg::cont_neg << dcfg::mode_shift) | 1u | dcfg::take_over);
            h.cmd(0, qi::STRN); // the other way: ignored
        }
        EXPECT_EQ(h.chip.current_speed(0), 10000);
        h.cmd(0, qi::write | qi::OBJ, 15000);
        h.cmd(0, qi::write | qi::POS, 20000);
        h.cmd(0, qi::write | qi::DCFG, (dcfg::preset << dcfg::mode_shift) | 1u | dcfg::take_over);
        h.cmd(0, qi::STRN);
        EXPECT_TRUE(h.chip.drive_status(0) & drvst::preset);
        double min_speed = 1e9;
        while (h.chip.busy(0)) {
            // Until the final ramp: 15000^2 / 200000 = 1125 pulses before the end.
            if (h.chip.command_position(0) < 20000 - 1200) min_speed = std::min(min_speed, h.chip.current_speed(0));
            wait(sc_time(100, SC_US));
        }
        EXPECT_GE(min_speed, 10000);
        EXPECT_EQ(h.chip.command_position(0), 20000);
    });
}

} // namespace
