// report.html's motion section (scenarios/report/report_html.h): the control-cycle, latency and CSP
// figures of a run with main_cpu.motion, both trajectory pictures, and the page of a motion-only
// run.
#include "scenarios/report/report_html.h"

#include <gtest/gtest.h>

using namespace rcsim::report;

namespace {

nlohmann::json summary(double min, double max) {
    return {{"count", 10}, {"min", min}, {"mean", (min + max) / 2}, {"p50", min}, {"p99", max}, {"max", max}};
}

nlohmann::json motion_report() {
    return {{"scenario", "xy"},
            {"passed", true},
            {"sim_time_s", 2.5},
            {"checks", nlohmann::json::array({{{"name", "circle_radial_error_pulses"}, {"passed", true},
                                                {"status", "passed"}, {"value", 0.5}, {"limit", 1.0}}})},
            {"motion",
             {{"state", "STANDSTILL"},
              {"samples", 2500},
              {"control_cycle", {{"duration_us", summary(156.25, 180)}, {"start_jitter_us", summary(0, 48.875)}}},
              {"command_latency_us", summary(5952.5, 5952.5)},
              {"csp", {{"setpoints", 2400}, {"missed_sync", 3}, {"max_setpoint_error_pulses", 10.5},
                       {"max_actual_radial_error_pulses", 1.25}}}}}};
}

const char* const kXy = "<?xml version=\"1.0\"?>\n<svg id=\"xy\"></svg>\n";
const char* const kTime = "<svg id=\"time\"></svg>\n";

} // namespace

TEST(MotionHtml, MotionSectionHasTheFiguresAndBothPictures) {
    HtmlOptions opt;
    opt.trajectory_svg = kXy;
    opt.trajectory_time_svg = kTime;
    const std::string html = render_motion_html(motion_report(), opt);
    EXPECT_NE(html.find("rcsim motion run: xy"), std::string::npos);
    EXPECT_NE(html.find("id=\"checks\""), std::string::npos);
    EXPECT_NE(html.find("circle_radial_error_pulses"), std::string::npos);
    EXPECT_NE(html.find("<svg id=\"xy\"></svg>"), std::string::npos);
    EXPECT_EQ(html.find("<?xml"), std::string::npos) << "the prolog is not inlined";
    EXPECT_NE(html.find("<svg id=\"time\"></svg>"), std::string::npos);
    EXPECT_NE(html.find("<code>trajectory_time.svg</code>"), std::string::npos);
    EXPECT_NE(html.find("control-cycle duration (its work)</td><td>10</td><td>156.25</td>"), std::string::npos) << html;
    EXPECT_NE(html.find("control-cycle start jitter</td><td>10</td><td>0.00</td>"), std::string::npos);
    EXPECT_NE(html.find("<td>48.88</td></tr>"), std::string::npos);
    EXPECT_NE(html.find("command latency (host ETX &rarr; first pulse)</td><td>10</td><td>5952.50</td>"),
              std::string::npos);
    EXPECT_NE(html.find("2400 set-points, 3 missed the drive's SYNC; set-point error max 10.50 pulses"),
              std::string::npos);
}

TEST(MotionHtml, MotionOnlyRunWithoutCycleFiguresShowsThePicturesOnly) {
    nlohmann::json r = motion_report();
    r["motion"].erase("control_cycle");
    HtmlOptions opt;
    opt.trajectory_svg = kXy;
    const std::string html = render_motion_html(r, opt);
    EXPECT_EQ(html.find("control-cycle duration"), std::string::npos);
    EXPECT_NE(html.find("<svg id=\"xy\"></svg>"), std::string::npos);
    EXPECT_EQ(html.find("trajectory_time.svg"), std::string::npos);
}
