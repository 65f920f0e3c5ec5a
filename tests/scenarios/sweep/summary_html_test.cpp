// summary.html's charts (scenarios/sweep/summary_html.h): whole-valued axes (wait states) ticked
// at whole values only, the legend outside the plot, and a failed run's point naming its checks.
#include "scenarios/sweep/merge.h"
#include "scenarios/sweep/summary_html.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <regex>
#include <string>
#include <vector>

using namespace rcsim::sweep;
using json = nlohmann::json;

namespace {

html::XySeries series(const std::string& label, const std::vector<double>& xs) {
    html::XySeries s;
    s.label = label;
    for (double x : xs) s.points.push_back({x, 10 + x, false, label});
    return s;
}

/// The y of every <text> whose content is `label`.
std::vector<double> text_y(const std::string& svg, const std::string& label) {
    std::vector<double> ys;
    const std::regex text("<text[^>]* y=\"([0-9.]+)\"[^>]*>" + label + "</text>");
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), text); it != std::sregex_iterator(); ++it)
        ys.push_back(std::stod((*it)[1]));
    return ys;
}

} // namespace

TEST(XyChart, AWholeValuedAxisIsTickedAtWholeValuesOnly) {
    const std::string svg = html::xy_chart("t", "board.wait_states.rom", "y", {series("a", {0, 1, 2})});
    for (const char* tick : {"0", "1", "2"}) EXPECT_EQ(text_y(svg, tick).size(), 1u) << tick << "\n" << svg;
    for (const char* between : {"0.5", "1.5", "0.2", "0.4"}) EXPECT_TRUE(text_y(svg, between).empty()) << between;
    // A fractional axis keeps its fractional ticks.
    const std::string frac = html::xy_chart("t", "x", "y", {series("a", {0.5, 1.0, 1.5})});
    EXPECT_FALSE(text_y(frac, "0.6").empty() && text_y(frac, "0.5").empty()) << frac;
}

TEST(XyChart, TheLegendSitsBelowThePlotNotOnIt) {
    const std::string svg =
        html::xy_chart("t", "x", "y", {series("first", {1, 2}), series("second", {1, 2}), series("third", {1, 2})});
    // The plot's x axis title is the lowest text of the plot area; every legend row is below it.
    const double axis_title = text_y(svg, "x").at(0);
    for (const char* label : {"first", "second", "third"}) {
        const auto ys = text_y(svg, label);
        ASSERT_EQ(ys.size(), 1u) << label;
        EXPECT_GT(ys[0], axis_title) << label;
    }
    EXPECT_NE(svg.find("height=\"329\""), std::string::npos) << "280 + 3 rows of 15 + 4";
}

TEST(SummaryHtml, AFailedRunsPointNamesItsFailedChecks) {
    json run = {{"id", "grid-rom=2"},
                {"entry", "grid"},
                {"status", "failed"},
                {"outcome", "failed"},
                {"parameters", {{"board.wait_states.rom", 2}}},
                {"figures", {{"table3.margin_us", -5.0}}},
                {"checks", {{"table3_margin_us", {{"passed", false}}}, {"overruns", {{"passed", true}}}}}};
    json ok = run;
    ok["id"] = "grid-rom=0", ok["status"] = "passed", ok["outcome"] = "passed";
    ok["parameters"]["board.wait_states.rom"] = 0;
    ok["checks"]["table3_margin_us"]["passed"] = true;
    const std::string page = summary_html({{"results", json::array({ok, run})}, {"passed", 1}, {"failed", 1}});
    EXPECT_NE(page.find("grid-rom=2: -5; failed: table3_margin_us</title>"), std::string::npos) << page;
    EXPECT_EQ(page.find("grid-rom=0: -5; failed"), std::string::npos);
}
