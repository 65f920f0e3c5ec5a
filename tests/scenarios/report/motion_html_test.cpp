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

// Issue 29 items 9 and 11: the swept-angle check reads ">=" (its relation in report.json), and a
// motion run's page lists every function block's outcome against its expectation, the largest
// following error and the final positions.
TEST(MotionHtml, MotionPageShowsRelationsFbOutcomesFollowingErrorAndFinalPositions) {
    nlohmann::json r = motion_report();
    r["checks"].push_back({{"name", "circle_swept_angle_rad"}, {"passed", true}, {"status", "passed"},
                           {"value", 6.283}, {"relation", ">="}, {"limit", 6.2829}});
    r["motion"]["commands"] = nlohmann::json::array(
        {{{"at_ms", 0.0}, {"token", "SV"}, {"data", "1"}},
         {{"at_ms", 10.0}, {"fb", "MC_CircleCenterMove"}, {"expect", "done"}, {"outcome", "done"}, {"outcome_ms", 1680.0}},
         {{"at_ms", 20.0}, {"fb", "MC_MoveAbsolute"}, {"expect", "error"}, {"expect_error_id", 28674},
          {"outcome", "error"}, {"error_id", 28673}, {"outcome_ms", 21.0}}});
    r["motion"]["max_following_error_pulses"] = 40.5;
    r["motion"]["final_cmd_pulses"] = {0, -12, 0, 0};
    r["motion"]["final_act_pulses"] = {0, -11, 0, 0};
    const std::string html = render_motion_html(r, HtmlOptions{});
    EXPECT_NE(html.find("circle_swept_angle_rad</td><td class=\"v\">6.283</td><td>&ge;</td>"), std::string::npos) << html;
    const std::size_t radial = html.find("circle_radial_error_pulses</td>");
    ASSERT_NE(radial, std::string::npos);
    EXPECT_EQ(html.find("<td>&le;</td>", radial), html.find("<td>", html.find("class=\"v\"", radial) + 1));
    EXPECT_NE(html.find("<td>10</td><td class=\"l\">MC_CircleCenterMove</td><td>done</td><td>done</td><td>1680</td>"
                        "<td></td><td class=\"ok\">as expected</td>"),
              std::string::npos);
    // The wrong ErrorID makes an expected error not as expected.
    EXPECT_NE(html.find("<td class=\"l\">MC_MoveAbsolute</td><td>error</td><td>error</td><td>21</td><td>28673</td>"
                        "<td class=\"ko\">NOT as expected</td>"),
              std::string::npos);
    EXPECT_EQ(html.find(">SV<"), std::string::npos); // tokens are not function blocks
    EXPECT_NE(html.find("maximum following error (command &minus; actual, any axis): 40.5 pulses"), std::string::npos);
    EXPECT_NE(html.find("final command position [pulses]</td><td>0</td><td>-12</td>"), std::string::npos);
    EXPECT_NE(html.find("final actual position [pulses]</td><td>0</td><td>-11</td>"), std::string::npos);
}
