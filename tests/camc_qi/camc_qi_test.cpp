// Tests of the CAMC-QI chip model through its TLM target: registers, profiles, stops, limit
// switches, interpolation drives, interrupts and bad data. Each TEST runs in its own process.
#include "tests/camc_qi/chip_host.h"
#include "camc_qi/camc_qi.h"
#include "models/bus.h"
#include "models/clock.h"
#include "tests/support/sc_test.h"

#include <tlm_utils/simple_initiator_socket.h>

#include <cmath>
#include <functional>

using namespace rcsim;
using namespace rcsim::camc;
using sc_core::sc_time;
using sc_core::SC_MS;
using sc_core::SC_US;

namespace {

using camc_test::Host;
using camc_test::run;

constexpr std::uint32_t mode(std::uint32_t m) { return m << dcfg::mode_shift; }
constexpr std::uint32_t axes_mask(std::uint32_t m) { return m << dcfg::axes_shift; }

TEST(CamcQi, RegistersRoundTripThroughTheBusWithWaitStates) {
    run([](Host& h) {
        h.cmd(2, qi::write | qi::OBJ, 123456);
        EXPECT_EQ(h.read(2, qi::OBJ), 123456u);
        EXPECT_EQ(h.last_wait_states, 1u);
        h.cmd(1, qi::write | qi::POS, static_cast<std::uint32_t>(-4711));
        EXPECT_EQ(static_cast<std::int32_t>(h.read(1, qi::POS)), -4711);
        EXPECT_EQ(h.read(0, qi::OBJ), 1000u); // axes are independent (reset value)
        std::uint8_t id = 0;
        EXPECT_TRUE(h.access(false, win::chip_id, &id, 1).ok());
        EXPECT_EQ(id, 0x06);
        std::uint8_t b = 0;
        EXPECT_EQ(h.access(false, win::size, &b, 1).status, tlm::TLM_ADDRESS_ERROR_RESPONSE);
        // Presetting the counters.
        h.cmd(3, qi::write | qi::CNT1, 1000);
        EXPECT_EQ(h.cnt1(3), 1000);
        EXPECT_EQ(static_cast<std::int32_t>(h.read(3, qi::CNT2)), 1000); // loop-back encoder
        h.cmd(3, qi::write | qi::CNT2, 0);
        EXPECT_EQ(static_cast<std::int32_t>(h.read(3, qi::CNT3)), 1000);
    });
}

TEST(CamcQi, TrapezoidPresetReachesAndLeavesObjectSpeedAndEndsExactly) {
    run([](Host& h) {
        // STD 100, OBJ 10 kpps, 100 kpps/s: ramps of 0.099 s covering 499.95 pulses each.
        h.setup(0, 100, 10000, 100000, 100000, mode(dcfg::preset));
        h.chip.trace_pulses(0, true);
        h.cmd(0, qi::write | qi::POS, 50000);
        const sc_time t0 = sc_core::sc_time_stamp();
        h.cmd(0, qi::STRN);
        wait(sc_time(50, SC_MS));
        EXPECT_TRUE(h.read(0, qi::STAT2) & drvst::up);
        EXPECT_NEAR(h.read(0, qi::CURSPD), 100 + 100000 * 0.050, 2);
        wait(sc_time(1000, SC_MS));
        EXPECT_TRUE(h.read(0, qi::STAT2) & drvst::constant);
        EXPECT_EQ(h.read(0, qi::CURSPD), 10000u);
        const double T = 0.099 + (50000 - 2 * 499.95) / 10000.0 + 0.099;
        wait(sc_time(T - 1.050 - 0.05, sc_core::SC_SEC));
        EXPECT_TRUE(h.read(0, qi::STAT2) & drvst::down);
        h.wait_idle(0, sc_time(10, SC_US));
        const double took = (sc_core::sc_time_stamp() - t0).to_seconds();
        EXPECT_NEAR(took, T, 20e-6);
        EXPECT_EQ(h.cnt1(0), 50000);
        EXPECT_EQ(h.read(0, qi::DRPCNT), 50000u);
        EXPECT_EQ(h.read(0, qi::STAT1), 0u); // normal end
        // The pulse train: 50000 pulses, 100 us apart in the cruise, the last ones near 1/STD.
        const auto& tr = h.chip.pulse_trace();
        ASSERT_EQ(tr.size(), 50000u);
        const double mid = (tr[25001].time - tr[25000].time).to_seconds();
        EXPECT_NEAR(mid, 1e-4, 1e-9);
        const double last = (tr[49999].time - tr[49998].time).to_seconds();
        EXPECT_GT(last, 1.0 / 1500);
        EXPECT_LE((tr.back().time - t0).to_seconds(), T + 1e-9);
    });
}

TEST(CamcQi, SCurveSymmetricRampAndShortTriangleMove) {
    run([](Host& h) {
        // Symmetric S (profile 2) with 60 % of the ramp in jerk: the ramp takes dv/(a*(1-0.3)).
        h.setup(1, 0 + 10, 20010, 200000, 200000, mode(dcfg::preset) | 2);
        h.cmd(1, qi::write | qi::SW1, 60);
        h.cmd(1, qi::write | qi::POS, static_cast<std::uint32_t>(-100000));
        h.cmd(1, qi::STRN);
        const double ramp = 20000.0 / (200000 * 0.7), tj = 0.3 * ramp;
        // In the first jerk ramp the speed grows quadratically: dv = a/tj * t^2 / 2.
        wait(sc_time(0.1 * ramp, sc_core::SC_SEC));
        const double t = 0.1 * ramp;
        EXPECT_NEAR(h.chip.current_speed(1) - 10, 200000 / tj * t * t / 2, 0.5);
        wait(sc_time(0.4 * ramp, sc_core::SC_SEC));
        // Half-way through the symmetric ramp the speed is half-way between STD and OBJ.
        EXPECT_NEAR(h.chip.current_speed(1), 10010, 1);
        EXPECT_TRUE(h.read(1, qi::STAT2) & drvst::negative);
        h.wait_idle(1);
        EXPECT_EQ(h.cnt1(1), -100000);

        // A move too short for OBJ: triangle with peak sqrt(STD^2 + d*a) (a = d symmetric).
        h.setup(2, 100, 100000, 50000, 50000, mode(dcfg::preset));
        h.cmd(2, qi::write | qi::POS, 2000);
        h.cmd(2, qi::STRN);
        double peak = 0;
        while (h.busy(2)) {
            peak = std::max(peak, h.chip.current_speed(2));
            wait(sc_time(200, SC_US));
        }
        EXPECT_NEAR(peak, std::sqrt(100.0 * 100 + 2000.0 * 50000), 60);
        EXPECT_LT(peak, 100000);
        EXPECT_EQ(h.cnt1(2), 2000);
    });
}

TEST(CamcQi, ContinuousDriveSlowDownAndImmediateStop) {
    run([](Host& h) {
        h.setup(0, 500, 5000, 50000, 25000, mode(dcfg::cont_pos) | 1); // asymmetric trapezoid
        h.cmd(0, qi::STRN);
        wait(sc_time(500, SC_MS));
        EXPECT_TRUE(h.read(0, qi::STAT2) & drvst::continuous);
        const std::int32_t at_stop = h.cnt1(0);
        h.cmd(0, qi::SSTOP);
        // Decel 5000 -> 500 at 25 kpps/s: 0.18 s, (5000^2-500^2)/(2*25000) = 495 pulses.
        wait(sc_time(100, SC_MS));
        EXPECT_TRUE(h.busy(0));
        EXPECT_TRUE(h.read(0, qi::STAT2) & drvst::down);
        wait(sc_time(81, SC_MS));
        EXPECT_FALSE(h.busy(0));
        EXPECT_NEAR(h.cnt1(0) - at_stop, 495, 1);
        EXPECT_EQ(h.read(0, qi::STAT1), endst::slowdown_cmd);

        h.setup(3, 500, 5000, 50000, 25000, mode(dcfg::cont_neg));
        h.cmd(3, qi::STRN);
        wait(sc_time(300, SC_MS));
        const std::int32_t before = h.cnt1(3);
        h.cmd(3, qi::STOP);
        EXPECT_FALSE(h.busy(3));
        EXPECT_EQ(h.cnt1(3), before); // frozen at once
        EXPECT_LT(before, 0);
        EXPECT_EQ(h.read(3, qi::STAT1), endst::stop_cmd);
    });
}

TEST(CamcQi, LimitSwitchStopsPerStopMode) {
    run([](Host& h) {
        // Emergency mode (reset default): PELM freezes the axis at once.
        h.setup(0, 1000, 20000, 100000, 100000, mode(dcfg::preset));
        h.cmd(0, qi::write | qi::POS, 100000);
        h.cmd(0, qi::STRN);
        wait(sc_time(400, SC_MS));
        const std::int32_t at = h.cnt1(0);
        h.chip.set_pin(0, Pin::pelm, true);
        EXPECT_FALSE(h.busy(0));
        EXPECT_EQ(h.cnt1(0), at);
        EXPECT_EQ(h.read(0, qi::STAT1), endst::pelm);
        EXPECT_EQ(h.read(0, qi::REMAIN), static_cast<std::uint32_t>(100000 - at));
        EXPECT_TRUE(h.read(0, qi::STAT3) & mech::pelm);
        // Further + moves are refused while PELM is active; - moves are allowed.
        h.cmd(0, qi::write | qi::POS, 10);
        h.cmd(0, qi::STRN);
        EXPECT_FALSE(h.busy(0));
        EXPECT_EQ(h.read(0, qi::STAT1), endst::pelm);
        h.cmd(0, qi::write | qi::POS, static_cast<std::uint32_t>(-10));
        h.cmd(0, qi::STRN);
        EXPECT_TRUE(h.busy(0));
        h.wait_idle(0);
        EXPECT_EQ(h.cnt1(0), at - 10);

        // Slow-down mode: NELM decelerates to STD, so the axis runs on past the switch.
        h.cmd(1, qi::write | qi::UCFG1, ucfg::reset_value | ucfg::limit_slowdown);
        h.setup(1, 1000, 20000, 100000, 100000, mode(dcfg::cont_neg));
        h.cmd(1, qi::STRN);
        wait(sc_time(400, SC_MS));
        const std::int32_t at1 = h.cnt1(1);
        h.chip.set_pin(1, Pin::nelm, true);
        EXPECT_TRUE(h.busy(1));
        h.wait_idle(1, sc_time(10, SC_US));
        // (20000^2 - 1000^2) / (2 * 100000) = 1995 pulses of deceleration.
        EXPECT_NEAR(at1 - h.cnt1(1), 1995, 1);
        EXPECT_EQ(h.read(1, qi::STAT1), endst::nelm);
        // An unused limit input is ignored.
        h.cmd(2, qi::write | qi::UCFG1, ucfg::reset_value & ~ucfg::pelm_used);
        h.chip.set_pin(2, Pin::pelm, true);
        h.setup(2, 1000, 20000, 100000, 100000, mode(dcfg::preset));
        h.cmd(2, qi::write | qi::POS, 100);
        h.cmd(2, qi::STRN);
        h.wait_idle(2);
        EXPECT_EQ(h.cnt1(2), 100);
    });
}

TEST(CamcQi, LinearInterpolationDriveEmitsExactPulses) {
    run([](Host& h) {
        h.setup(0, 100, 8000, 80000, 80000, mode(dcfg::linear) | axes_mask(0b1011));
        h.cmd(0, qi::write | qi::POS, 8000);
        h.cmd(1, qi::write | qi::POS, static_cast<std::uint32_t>(-4800));
        h.cmd(3, qi::write | qi::POS, 3);
        for (unsigned a : {0u, 1u, 3u}) h.chip.trace_pulses(a, true);
        h.cmd(0, qi::STRN);
        EXPECT_TRUE(h.read(1, qi::STAT2) & drvst::linear);
        wait(sc_time(500, SC_MS));
        // Mid-path every axis is within half a pulse of the line through the end point.
        const double k = h.cnt1(0);
        EXPECT_LE(std::abs(h.cnt1(1) - (-4800.0 * k / 8000)), 0.5);
        h.wait_idle(0);
        EXPECT_EQ(h.cnt1(0), 8000);
        EXPECT_EQ(h.cnt1(1), -4800);
        EXPECT_EQ(h.cnt1(3), 3);
        int n[4] = {};
        for (const PulseEvent& e : h.chip.pulse_trace()) n[e.axis] += e.dir;
        EXPECT_EQ(n[0], 8000);
        EXPECT_EQ(n[1], -4800);
        EXPECT_EQ(n[3], 3);
    });
}

TEST(CamcQi, CircleDriveClosesAndIsnumSetsTheDeceleration) {
    run([](Host& h) {
        // Full circle R = 5000 about a centre 5000 pulses in -X from the start.
        auto circle = [&](std::uint32_t isnum) {
            h.setup(0, 200, 20000, 100000, 100000, mode(dcfg::circle_ccw) | axes_mask(0b0011));
            h.cmd(0, qi::write | qi::CENT, static_cast<std::uint32_t>(-5000));
            h.cmd(1, qi::write | qi::CENT, 0);
            h.cmd(0, qi::write | qi::POS, 0);
            h.cmd(1, qi::write | qi::POS, 0);
            h.cmd(0, qi::write | qi::ISNUM, isnum);
            const sc_time t0 = sc_core::sc_time_stamp();
            h.cmd(0, qi::STRN);
            double worst = 0;
            while (h.busy(0)) {
                const double x = h.cnt1(0) + 5000.0, y = h.cnt1(1);
                worst = std::max(worst, std::abs(std::hypot(x, y) - 5000));
                wait(sc_time(1, SC_MS));
            }
            EXPECT_LE(worst, 1.0);
            EXPECT_EQ(h.cnt1(0), 0);
            EXPECT_EQ(h.cnt1(1), 0);
            return (sc_core::sc_time_stamp() - t0).to_seconds();
        };
        const std::uint64_t steps = circle_step_count({5000, 0}, {5000, 0}, ArcDirection::ccw);
        const double exact = circle(static_cast<std::uint32_t>(steps));
        const double slow = circle(static_cast<std::uint32_t>(steps / 2)); // decelerates half-way
        // Half the steps are then driven at STD (200 steps/s): many seconds longer.
        EXPECT_GT(slow - exact, 0.5 * steps / 200.0 - 2);
    });
}

TEST(CamcQi, AlarmDuringInterpolationStopsBothAxesAndRaisesInt) {
    run([](Host& h) {
        h.cmd(0, qi::write | qi::IMASK1, intf::error_stop);
        h.setup(0, 100, 10000, 100000, 100000, mode(dcfg::linear) | axes_mask(0b0011));
        h.cmd(0, qi::write | qi::POS, 30000);
        h.cmd(1, qi::write | qi::POS, 30000);
        h.cmd(0, qi::STRN);
        wait(sc_time(200, SC_MS));
        EXPECT_FALSE(h.chip.irq.read());
        h.chip.set_pin(1, Pin::alarm, true);
        wait(sc_core::SC_ZERO_TIME);
        wait(sc_core::SC_ZERO_TIME);
        EXPECT_FALSE(h.busy(0));
        EXPECT_FALSE(h.busy(1));
        EXPECT_EQ(h.read(0, qi::STAT1) & endst::alarm, endst::alarm);
        EXPECT_EQ(h.read(1, qi::STAT1) & endst::alarm, endst::alarm);
        EXPECT_TRUE(h.chip.irq.read());
        std::uint8_t pend = 0;
        h.access(false, win::irq_pending, &pend, 1);
        EXPECT_EQ(pend, 0x01);
        h.cmd(0, qi::IFCLR1, 0xFFFFFFFF);
        wait(sc_core::SC_ZERO_TIME);
        wait(sc_core::SC_ZERO_TIME);
        EXPECT_FALSE(h.chip.irq.read());
        // A start with the alarm still active is refused (AXL MOVE_SENSOR_CHECK).
        h.cmd(0, qi::ESCLR);
        h.cmd(0, qi::STRN);
        EXPECT_FALSE(h.busy(0));
        EXPECT_EQ(h.read(1, qi::STAT1), endst::alarm);
    });
}

TEST(CamcQi, DriveEndInterruptAndEmergencyStopOfAllAxes) {
    run([](Host& h) {
        h.cmd(2, qi::write | qi::IMASK1, intf::drive_end);
        h.setup(2, 1000, 1000, 1000, 1000, mode(dcfg::preset));
        h.cmd(2, qi::write | qi::POS, 10); // 10 pulses at 1 kpps: 10 ms
        h.cmd(2, qi::STRN);
        wait(h.chip.irq.posedge_event());
        EXPECT_NEAR(sc_core::sc_time_stamp().to_seconds(), 0.010, 1e-9);
        EXPECT_EQ(h.cnt1(2), 10);
        h.cmd(2, qi::IFCLR1, intf::drive_end);

        for (unsigned a : {0u, 1u, 3u}) {
            h.setup(a, 1000, 5000, 10000, 10000, mode(dcfg::cont_pos));
            h.cmd(a, qi::STRN);
        }
        wait(sc_time(100, SC_MS));
        h.cmd(3, qi::ESTOP);
        for (unsigned a : {0u, 1u, 3u}) {
            EXPECT_FALSE(h.busy(a));
            EXPECT_EQ(h.read(a, qi::STAT1), endst::estop_cmd);
        }
        // The ESTOP input pin refuses starts.
        h.chip.set_estop_pin(true);
        h.cmd(0, qi::STRN);
        EXPECT_FALSE(h.busy(0));
        EXPECT_EQ(h.read(0, qi::STAT1), endst::estop_signal);
    });
}

TEST(CamcQi, OriginSearchStopsOnTheHomeSensor) {
    run([](Host& h) {
        h.setup(0, 500, 5000, 50000, 50000, mode(dcfg::origin_neg));
        h.cmd(0, qi::write | qi::OBJORG, 2000);
        h.cmd(0, qi::STRN);
        EXPECT_TRUE(h.read(0, qi::STAT2) & drvst::home);
        wait(sc_time(300, SC_MS));
        EXPECT_EQ(h.chip.current_speed(0), 2000); // the origin speed, not OBJ
        h.chip.set_pin(0, Pin::org, true);
        h.wait_idle(0, sc_time(10, SC_US));
        EXPECT_EQ(h.read(0, qi::STAT1), endst::home_ok);
        EXPECT_TRUE(h.read(0, qi::STAT3) & mech::org);
    });
}

TEST(CamcQi, BadDriveDataIsRefusedWithEndStatus) {
    run([](Host& h) {
        h.setup(0, 100, 0, 1000, 1000, mode(dcfg::preset)); // OBJ = 0
        h.cmd(0, qi::write | qi::POS, 100);
        h.cmd(0, qi::STRN);
        EXPECT_FALSE(h.busy(0));
        EXPECT_EQ(h.read(0, qi::STAT1), endst::data_error);
        h.setup(0, 100, 20000000, 1000, 1000, mode(dcfg::preset)); // above 10 Mpps
        h.cmd(0, qi::STRN);
        EXPECT_EQ(h.read(0, qi::STAT1), endst::data_error);
        // A circle whose end is off the track: invalid interpolation data (b19).
        {
            test::ScAllowWarnings allow;
            h.setup(0, 100, 1000, 1000, 1000, mode(dcfg::circle_cw) | axes_mask(0b0011));
            h.cmd(0, qi::write | qi::CENT, static_cast<std::uint32_t>(-1000));
            h.cmd(1, qi::write | qi::CENT, 0);
            h.cmd(0, qi::write | qi::POS, 4000);
            h.cmd(1, qi::write | qi::POS, 4000);
            h.cmd(0, qi::STRN);
        }
        EXPECT_FALSE(h.busy(0));
        EXPECT_EQ(h.read(1, qi::STAT1), endst::interp_data | endst::data_error);
        // A code the model does not implement is reported, not silently accepted.
        test::ScAllowWarnings allow;
        h.read(0, 0x45);
        ASSERT_FALSE(allow.messages().empty());
        EXPECT_NE(allow.messages().back().find("0x45"), std::string::npos);
    });
}

} // namespace

namespace {

TEST(CamcQi, PresetDriveAcrossTheWholeRangeEndsExactly) {
    run([](Host& h) {
        // From -(2^30 - 1) to +(2^30 - 1): POS = 2^31 - 2, the largest distance of the range.
        constexpr std::int32_t end = (1 << 30) - 1;
        h.cmd(0, qi::write | qi::CNT1, static_cast<std::uint32_t>(-end));
        h.setup(0, 1000, 10000000, 100000000, 100000000, mode(dcfg::preset));
        h.cmd(0, qi::write | qi::POS, static_cast<std::uint32_t>(2 * end));
        h.cmd(0, qi::STRN);
        h.wait_idle(0, sc_time(1, sc_core::SC_SEC));
        EXPECT_EQ(h.cnt1(0), end);
        EXPECT_EQ(h.read(0, qi::DRPCNT), static_cast<std::uint32_t>(2 * end));
        EXPECT_EQ(h.read(0, qi::STAT1), 0u);
    });
}

} // namespace

namespace {

// Sensors as positions (README "Sensors and homing"): the chip acts at the time the profile
// reaches a sensor's edge. A ramp v0 -> v1 at rate a covers (v1^2 - v0^2) / (2a) pulses, and the
// chip's step count is floor(s).

TEST(CamcQiSensors, LimitEdgesActAtTheirExactTimeInBothStopModes) {
    run([](Host& h) {
        Sensors s;
        s.pelm = 5000;
        h.chip.set_sensors(0, s);
        h.cmd(0, qi::write | qi::IMASK1, intf::drive_end);
        // STD 1000 -> 20000 at 100000: 0.19 s over 1995 pulses, then 3005 pulses at 20 kpps:
        // PELM's first position 5000 is reached at 0.19 + 3005/20000 = 0.34025 s.
        h.setup(0, 1000, 20000, 100000, 100000, mode(dcfg::preset));
        h.cmd(0, qi::write | qi::POS, 100000);
        const sc_time t0 = sc_core::sc_time_stamp();
        h.cmd(0, qi::STRN);
        wait(h.chip.irq.posedge_event());
        EXPECT_NEAR((sc_core::sc_time_stamp() - t0).to_seconds(), 0.34025, 1e-9);
        EXPECT_EQ(h.cnt1(0), 5000);
        EXPECT_EQ(h.read(0, qi::STAT1), endst::pelm);
        EXPECT_TRUE(h.read(0, qi::STAT3) & mech::pelm);
        EXPECT_EQ(h.read(0, qi::REMAIN), 95000u);

        // Slow-down mode: from 20 kpps at the edge -3000 down to STD 1000 at 90000:
        // (20000^2 - 1000^2) / 180000 = 2216.67 pulses past it, floored.
        s = {};
        s.nelm = -3000;
        h.chip.set_sensors(1, s);
        h.cmd(1, qi::write | qi::UCFG1, ucfg::reset_value | ucfg::limit_slowdown);
        h.setup(1, 1000, 20000, 100000, 90000, mode(dcfg::cont_neg) | 1);
        h.cmd(1, qi::STRN);
        h.wait_idle(1);
        EXPECT_EQ(h.cnt1(1), -3000 - 2216);
        EXPECT_EQ(h.read(1, qi::STAT1), endst::nelm);
        // CNT1 presets do not move the sensors: they are on the machine (pulse) position.
        h.cmd(1, qi::write | qi::CNT1, 0);
        EXPECT_TRUE(h.read(1, qi::STAT3) & mech::nelm);
        h.setup(1, 1000, 20000, 100000, 90000, mode(dcfg::preset));
        h.cmd(1, qi::write | qi::POS, static_cast<std::uint32_t>(-10));
        h.cmd(1, qi::STRN);
        EXPECT_FALSE(h.busy(1)); // refused: NELM is on in the direction of motion
        EXPECT_EQ(h.read(1, qi::STAT1), endst::nelm);
    });
}

TEST(CamcQiSensors, InterpolationStopsOnTheStepThatReachesALimit) {
    run([](Host& h) {
        // Line (8000, 4000): axis 1 is at floor(k/2 + 1/2) after step k, so its PELM at 1000 is
        // reached at step 1999, where axis 0 is at 1999.
        Sensors s;
        s.pelm = 1000;
        h.chip.set_sensors(1, s);
        h.setup(0, 100, 8000, 80000, 80000, mode(dcfg::linear) | axes_mask(0b0011));
        h.cmd(0, qi::write | qi::POS, 8000);
        h.cmd(1, qi::write | qi::POS, 4000);
        h.cmd(0, qi::STRN);
        h.wait_idle(0);
        EXPECT_EQ(h.cnt1(0), 1999);
        EXPECT_EQ(h.cnt1(1), 1000);
        EXPECT_EQ(h.read(0, qi::STAT1), endst::pelm);

        // A circle about (-1000, 0) from (0, 0), CCW, and PELM on axis 3 (Y) at 500: the stop is
        // on the first track point with y = 500, found here by walking the interpolator.
        s.pelm = 500;
        h.chip.set_sensors(3, s);
        h.chip.set_sensors(1, {});
        CirclePath path({1000, 0}, {1000, 0}, ArcDirection::ccw);
        std::uint64_t k = 0;
        Point p;
        do p = path.at(++k); while (p.y < 500);
        h.setup(2, 100, 8000, 80000, 80000, mode(dcfg::circle_ccw) | axes_mask(0b1100));
        h.cmd(2, qi::write | qi::CENT, static_cast<std::uint32_t>(-1000));
        h.cmd(3, qi::write | qi::CENT, 0);
        h.cmd(2, qi::write | qi::POS, 0);
        h.cmd(3, qi::write | qi::POS, 0);
        h.cmd(2, qi::STRN);
        h.wait_idle(2);
        EXPECT_EQ(h.cnt1(2), p.x - 1000);
        EXPECT_EQ(h.cnt1(3), 500);
        EXPECT_EQ(h.read(2, qi::DRPCNT), k);
    });
}

TEST(CamcQiSensors, SignalSearchesStopOnTheChosenEdge) {
    run([](Host& h) {
        Sensors s;
        s.org = -2000;
        s.z_pitch = 500, s.z_offset = 7;
        h.chip.set_sensors(0, s);
        auto search = [&](std::uint32_t m, std::uint32_t sig, std::uint32_t flags, std::uint32_t vel) {
            h.setup(0, 100, vel, 50000, 50000, mode(m) | (sig << dcfg::signal_shift) | flags);
            h.cmd(0, qi::write | qi::OBJORG, vel);
            h.cmd(0, qi::STRN);
            h.wait_idle(0, sc_time(10, SC_US));
        };
        // Negative, immediate: frozen on the switch's first position.
        search(dcfg::origin_neg, dcfg::sig_org, dcfg::search_immediate, 5000);
        EXPECT_EQ(h.cnt1(0), -2000);
        EXPECT_EQ(h.read(0, qi::STAT1), endst::home_ok);
        // Positive until inactive, slow-down, at 300 pps: the ramp from STD, (300^2 - 100^2) /
        // 100000 = 0.8 pulse, ends before the edge -1999 (one pulse on), and the slow-down from
        // there runs 0.8 pulse: floor(1 + 0.8) = 1 pulse, the stop is on -1999.
        search(dcfg::origin_pos, dcfg::sig_org, dcfg::search_inactive, 300);
        EXPECT_EQ(h.cnt1(0), -1999);
        EXPECT_EQ(h.read(0, qi::STAT1), endst::home_ok);
        EXPECT_FALSE(h.read(0, qi::STAT3) & mech::org);
        // Z, positive, immediate: the next position = 7 (mod 500) above.
        const std::int32_t from = h.cnt1(0);
        search(dcfg::origin_pos, dcfg::sig_z, dcfg::search_immediate, 1000);
        const std::int32_t z = from + 1 + ((7 - (from + 1)) % 500 + 500) % 500;
        EXPECT_EQ(h.cnt1(0), z);
        EXPECT_EQ(h.read(0, qi::STAT1), endst::signal_ok);
        EXPECT_TRUE(h.read(0, qi::STAT3) & mech::zphase);
        // A search whose edge is already behind (on Z, looking for Z) ends at once, no motion.
        search(dcfg::origin_pos, dcfg::sig_z, dcfg::search_immediate, 1000);
        EXPECT_EQ(h.cnt1(0), z);
        EXPECT_EQ(h.read(0, qi::STAT1), endst::signal_ok);
    });
}

// A search for a limit switch is not stopped by that switch (camc_qi/README.md "Sensors and
// homing"): it drives into it and stops on its first active position with the signal-search bit,
// not the limit's error bit. PELM is on at and above 3000, NELM at and below -3000.
TEST(CamcQiSensors, ALimitSearchDrivesIntoItsSwitch) {
    run([](Host& h) {
        Sensors s;
        s.pelm = 3000, s.nelm = -3000;
        h.chip.set_sensors(0, s);
        auto search = [&](std::uint32_t m, std::uint32_t sig) {
            h.setup(0, 100, 20000, 500000, 500000, mode(m) | (sig << dcfg::signal_shift) | dcfg::search_immediate);
            h.cmd(0, qi::write | qi::OBJORG, 20000);
            h.cmd(0, qi::STRN);
            EXPECT_TRUE(h.busy(0));
            h.wait_idle(0);
        };
        search(dcfg::origin_pos, dcfg::sig_pelm);
        EXPECT_EQ(h.cnt1(0), 3000);
        EXPECT_EQ(h.read(0, qi::STAT1), endst::signal_ok);
        EXPECT_TRUE(h.read(0, qi::STAT3) & mech::pelm);
        // From the active PELM the other way: PELM does not refuse a start away from it.
        search(dcfg::origin_neg, dcfg::sig_nelm);
        EXPECT_EQ(h.cnt1(0), -3000);
        EXPECT_EQ(h.read(0, qi::STAT1), endst::signal_ok);
        EXPECT_TRUE(h.read(0, qi::STAT3) & mech::nelm);
    });
}

// A limit search started on its active switch has its edge behind: it ends at once with the
// signal-search bit and no motion (the start check must not refuse it as a start into an active
// limit). The other limit still refuses a start towards it.
TEST(CamcQiSensors, ALimitSearchStartedOnItsActiveSwitchEndsAtOnce) {
    run([](Host& h) {
        auto search = [&](unsigned axis, std::uint32_t m, std::uint32_t sig) {
            h.setup(axis, 100, 20000, 500000, 500000, mode(m) | (sig << dcfg::signal_shift) | dcfg::search_immediate);
            h.cmd(axis, qi::write | qi::OBJORG, 20000);
            h.cmd(axis, qi::STRN);
        };
        h.chip.set_pin(0, Pin::pelm, true);
        search(0, dcfg::origin_pos, dcfg::sig_pelm);
        EXPECT_FALSE(h.busy(0));
        EXPECT_EQ(h.read(0, qi::STAT1), endst::signal_ok);
        EXPECT_EQ(h.cnt1(0), 0);

        h.chip.set_pin(1, Pin::nelm, true);
        search(1, dcfg::origin_neg, dcfg::sig_nelm);
        EXPECT_FALSE(h.busy(1));
        EXPECT_EQ(h.read(1, qi::STAT1), endst::signal_ok);
        EXPECT_EQ(h.cnt1(1), 0);
        // A PELM search towards the active NELM is a start into a limit: refused.
        search(1, dcfg::origin_neg, dcfg::sig_pelm);
        EXPECT_FALSE(h.busy(1));
        EXPECT_EQ(h.read(1, qi::STAT1), endst::nelm);
        EXPECT_EQ(h.cnt1(1), 0);
    });
}

} // namespace
