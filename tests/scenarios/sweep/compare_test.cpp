// compare: the change of each figure and check under the tolerances, run matching, the outputs.
#include "models/plumbing/config_error.h"
#include "scenarios/sweep/compare.h"
#include "tests/support/files.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace rcsim;
using namespace rcsim::sweep;
using json = nlohmann::json;

namespace {

RunRecord run_of(const std::string& id, const json& report) {
    RunRecord r;
    r.id = id;
    r.report = report;
    return r;
}

json report(double isr, const json& margin, bool check_passed, double wall = 0.5) {
    return {{"scenario", "s"},
            {"wall_time_s", wall},
            {"rtf", 4.0 * wall},
            {"table3", {{"rs232_isr_us", isr}, {"margin_us", margin}}},
            {"checks", json::array({{{"name", "overruns"}, {"passed", check_passed}}})},
            {"passed", check_passed}};
}

/// Compares one run; returns it.
RunDiff one(const json& base, const json& cur, const std::vector<Tolerance>& rules = default_tolerances(),
            Comparison* out = nullptr) {
    const Comparison c = compare_runs({{"r", run_of("r", base)}}, {{"r", run_of("r", cur)}}, rules, false);
    if (out) *out = c;
    return c.runs.at(0);
}

const FigureDiff& figure(const RunDiff& r, const std::string& key) {
    for (const auto& f : r.figures)
        if (f.key == key) return f;
    throw std::runtime_error("no figure " + key);
}

Tolerance rule(const std::string& figure, double abs, double rel, Tolerance::Better better = Tolerance::Better::none) {
    Tolerance t;
    t.figure = figure;
    t.abs = abs;
    t.rel = rel;
    t.better = better;
    t.origin = "test";
    return t;
}

std::vector<Tolerance> with_defaults(std::vector<Tolerance> rules) {
    for (const auto& t : default_tolerances()) rules.push_back(t);
    return rules;
}

} // namespace

TEST(Glob, StarQuestionMarkAndLiteralBrackets) {
    EXPECT_TRUE(glob_match("table3.*", "table3.margin_us"));
    EXPECT_TRUE(glob_match("*_us", "interrupts.dpram.latency_us"));
    EXPECT_TRUE(glob_match("ports[*].overruns", "ports[2].overruns"));
    EXPECT_FALSE(glob_match("ports[*].overruns", "ports[2].overruns_x"));
    EXPECT_TRUE(glob_match("a?c", "abc"));
    EXPECT_FALSE(glob_match("a?c", "ac"));
    EXPECT_TRUE(glob_match("*", ""));
    EXPECT_TRUE(glob_match("a*b*c", "axxbyyc"));
    EXPECT_FALSE(glob_match("a*b*c", "axxbyy"));
}

TEST(Compare, DefaultRuleIsExactAndIgnoresHostFigures) {
    const RunDiff r = one(report(82, 100, true, 0.5), report(82.001, 100, true, 9.0));
    EXPECT_EQ(figure(r, "table3.rs232_isr_us").change, Change::regression);
    EXPECT_NEAR(*figure(r, "table3.rs232_isr_us").delta, 0.001, 1e-9);
    EXPECT_NEAR(*figure(r, "table3.rs232_isr_us").rel, 0.001 / 82, 1e-12);
    EXPECT_EQ(figure(r, "table3.margin_us").change, Change::same);
    EXPECT_EQ(figure(r, "wall_time_s").change, Change::ignored);
    EXPECT_EQ(figure(r, "rtf").change, Change::ignored);
    EXPECT_TRUE(r.regression);
    EXPECT_FALSE(one(report(82, 100, true, 0.5), report(82, 100, true, 9.0)).regression);
}

TEST(Compare, AbsoluteOrRelativeToleranceAndDirection) {
    // abs 0.5: a change of 0.4 is within; rel 1 %: 82 -> 82.8 (0.98 %) is within, 83 (1.2 %) is not.
    auto rules = with_defaults({rule("table3.rs232_isr_us", 0.5, 0.01)});
    EXPECT_EQ(figure(one(report(82, 1, true), report(82.4, 1, true), rules), "table3.rs232_isr_us").change, Change::within);
    EXPECT_EQ(figure(one(report(82, 1, true), report(82.8, 1, true), rules), "table3.rs232_isr_us").change, Change::within);
    EXPECT_EQ(figure(one(report(82, 1, true), report(83, 1, true), rules), "table3.rs232_isr_us").change,
              Change::regression);
    rules = with_defaults({rule("table3.*", 0, 0, Tolerance::Better::lower)});
    EXPECT_EQ(figure(one(report(82, 1, true), report(70, 1, true), rules), "table3.rs232_isr_us").change,
              Change::improvement);
    EXPECT_EQ(figure(one(report(82, 1, true), report(90, 1, true), rules), "table3.rs232_isr_us").change,
              Change::regression);
    EXPECT_FALSE(one(report(82, 1, true), report(70, 1, true), rules).regression);
    // A rule that names a host figure replaces its default.
    rules = with_defaults({rule("wall_time_s", 0, 0.5)});
    EXPECT_EQ(figure(one(report(82, 1, true, 1.0), report(82, 1, true, 2.0), rules), "wall_time_s").change,
              Change::regression);
}

TEST(Compare, NullVersusNumberIsAChange) {
    auto rules = with_defaults({rule("table3.*", 1e9, 1e9)}); // any number change within tolerance
    EXPECT_EQ(figure(one(report(82, 100, true), report(82, nullptr, true), rules), "table3.margin_us").change,
              Change::regression);
    EXPECT_EQ(figure(one(report(82, nullptr, true), report(82, 100, true), rules), "table3.margin_us").change,
              Change::regression);
    EXPECT_EQ(figure(one(report(82, nullptr, true), report(82, nullptr, true), rules), "table3.margin_us").change,
              Change::same);
}

TEST(Compare, RemovedFigureRegressesNewFigureDoesNot) {
    json cur = report(82, 1, true);
    cur["table3"].erase("margin_us");
    cur["table3"]["new_us"] = 3;
    const RunDiff r = one(report(82, 1, true), cur);
    EXPECT_EQ(figure(r, "table3.margin_us").change, Change::regression);
    EXPECT_FALSE(figure(r, "table3.margin_us").has_current);
    EXPECT_EQ(figure(r, "table3.new_us").change, Change::added);
    json only_new = report(82, 1, true);
    only_new["table3"]["new_us"] = 3;
    EXPECT_FALSE(one(report(82, 1, true), only_new).regression);
}

TEST(Compare, CheckThatStopsPassingRegressesWhateverTheTolerances) {
    Tolerance all;
    all.figure = "*";
    all.ignore = true;
    const RunDiff r = one(report(82, 1, true), report(82, 1, false), {all});
    ASSERT_EQ(r.checks.size(), 1u);
    EXPECT_EQ(r.checks[0].change, Change::regression);
    EXPECT_TRUE(r.regression);
    EXPECT_EQ(one(report(82, 1, false), report(82, 1, true), {all}).checks[0].change, Change::improvement);
    EXPECT_EQ(one(report(82, 1, false), report(82, 1, false), {all}).checks[0].change, Change::same);
    // A new check that fails regresses, a check that is gone does too.
    json more = report(82, 1, true);
    more["checks"].push_back({{"name", "extra"}, {"passed", false}});
    EXPECT_TRUE(one(report(82, 1, true), more, {all}).regression);
    json fewer = report(82, 1, true);
    fewer["checks"] = json::array();
    EXPECT_TRUE(one(report(82, 1, true), fewer, {all}).regression);
}

TEST(Compare, MissingAndExtraRunsRegressUnlessAllowed) {
    const std::map<std::string, RunRecord> base{{"a", run_of("a", report(1, 1, true))}, {"b", run_of("b", report(1, 1, true))}};
    const std::map<std::string, RunRecord> cur{{"b", run_of("b", report(1, 1, true))}, {"c", run_of("c", report(1, 1, true))}};
    const Comparison c = compare_runs(base, cur, default_tolerances(), false);
    EXPECT_EQ(c.missing, 1u);
    EXPECT_EQ(c.extra, 1u);
    EXPECT_TRUE(c.regression());
    EXPECT_FALSE(compare_runs(base, cur, default_tolerances(), true).regression());
    // A run without a report regresses even with --allow-missing.
    std::map<std::string, RunRecord> broken = base;
    broken["b"].report.reset();
    EXPECT_TRUE(compare_runs(base, broken, default_tolerances(), true).regression());
}

TEST(Compare, ConsoleListsRegressionsFirstWithDeltas) {
    Comparison c;
    one(report(82, 10, true), report(90, 10, false), default_tolerances(), &c);
    std::ostringstream os;
    print_comparison(c, os);
    const std::string s = os.str();
    EXPECT_NE(s.find("regressions: 2 in 2 figures/checks"), std::string::npos) << s;
    EXPECT_LT(s.find("check overruns"), s.find("table3.rs232_isr_us")) << s; // the check first
    EXPECT_NE(s.find("+8"), std::string::npos) << s;
    EXPECT_NE(s.find("+9.76%"), std::string::npos) << s; // 8 / 82
    EXPECT_NE(s.find("REGRESSION"), std::string::npos);
}

TEST(Compare, ConsoleGroupsAFigureOverRunsAndShowsTheWorst) {
    // table3.rs232_isr_us regresses in two runs: one row, 2 runs, the worst (b: +20 %) shown.
    const std::map<std::string, RunRecord> base{{"a", run_of("a", report(100, 1, true))}, {"b", run_of("b", report(100, 1, true))}};
    const std::map<std::string, RunRecord> cur{{"a", run_of("a", report(110, 1, true))}, {"b", run_of("b", report(120, 1, true))}};
    std::ostringstream os;
    print_comparison(compare_runs(base, cur, default_tolerances(), false), os);
    const std::string s = os.str();
    EXPECT_NE(s.find("regressions: 2 in 1 figures/checks"), std::string::npos) << s;
    std::istringstream lines(s);
    std::string line;
    std::size_t rows = 0;
    while (std::getline(lines, line))
        if (line.find("table3.rs232_isr_us") != std::string::npos) {
            ++rows;
            EXPECT_NE(line.find(" 2  b "), std::string::npos) << line;
            EXPECT_NE(line.find("+20.00%"), std::string::npos) << line;
        }
    EXPECT_EQ(rows, 1u) << s;
}

TEST(Compare, JunitCountsMatchItsTestcases) {
    Comparison c;
    one(report(82, 10, true), report(90, 10, true), default_tolerances(), &c);
    const std::string x = junit_xml(c);
    auto count = [&x](const std::string& what) {
        std::size_t n = 0;
        for (auto at = x.find(what); at != std::string::npos; at = x.find(what, at + 1)) ++n;
        return n;
    };
    // run + 1 check + 3 figure families (wall_time_s and rtf ignored: skipped; table3), 1 regression.
    EXPECT_EQ(count("<testcase "), 5u);
    EXPECT_NE(x.find("<testsuites name=\"rcsim compare\" tests=\"5\" failures=\"1\" errors=\"0\" skipped=\"2\">"),
              std::string::npos) << x;
    EXPECT_NE(x.find("name=\"figures table3\"><failure type=\"regression\" message=\"1 figure regressed: "
                     "table3.rs232_isr_us 82 -&gt; 90 (+9.76%)"),
              std::string::npos) << x;
}

TEST(Compare, FiguresGroupIntoFamiliesBySourcePortOrFirstName) {
    EXPECT_EQ(figure_family("interrupts.rs232_0.latency_us.max"), "interrupts.rs232_0");
    EXPECT_EQ(figure_family("interrupts.dpram.count"), "interrupts.dpram");
    EXPECT_EQ(figure_family("ports[2].commands.matched"), "ports[2]");
    EXPECT_EQ(figure_family("table3.margin_us"), "table3");
    EXPECT_EQ(figure_family("comm_cpu.cycles"), "comm_cpu");
    EXPECT_EQ(figure_family("rtf"), "rtf");
}

TEST(Compare, RanksFollowWhatAFirmwareTeamAsksFirst) {
    EXPECT_EQ(rank_of("table3.worst_margin_us"), Rank::budget);
    EXPECT_EQ(rank_of("interrupts.rs232_1.latency_us.p99"), Rank::latency);
    EXPECT_EQ(rank_of("interrupts.dpram.service_us.mean"), Rank::latency);
    EXPECT_EQ(rank_of("interrupts.dpram.latency_us.min"), Rank::other);
    EXPECT_EQ(rank_of("ports[0].frames_delivered"), Rank::delivery);
    EXPECT_EQ(rank_of("ports[1].responses.matched"), Rank::delivery);
    EXPECT_EQ(rank_of("comm_cpu.cycles"), Rank::other);
}

namespace {
/// A run where one change (a slower ISR) moved a check, the budget, a latency, a delivery count,
/// and 300 other figures by a hair: what a CI log shows after a firmware change.
json slowed(bool slow) {
    json r = report(slow ? 127 : 82, slow ? -10.0 : 35.0, !slow);
    r["interrupts"]["rs232_0"]["latency_us"]["max"] = slow ? 420.0 : 380.0;
    r["ports"] = json::array({{{"frames_delivered", slow ? 99 : 100}}});
    for (int i = 0; i < 300; ++i) r["comm_cpu"]["counter_" + std::to_string(i)] = slow ? 1000001 + i : 1000000 + i;
    return r;
}
} // namespace

TEST(Compare, TheFirstScreenLeadsWithWhatFlippedAndCollapsesTheRestByFamily) {
    std::map<std::string, RunRecord> base, cur;
    for (const char* id : {"a", "b"}) base.emplace(id, run_of(id, slowed(false))), cur.emplace(id, run_of(id, slowed(true)));
    const Comparison c = compare_runs(base, cur, default_tolerances(), false);
    std::ostringstream os;
    print_comparison(c, os);
    const std::string s = os.str();
    auto line_of = [&s](const std::string& what) {
        const auto at = s.find(what);
        return at == std::string::npos ? std::string::npos : std::size_t(std::count(s.begin(), s.begin() + at, '\n'));
    };
    const std::size_t check = line_of("check overruns"), budget = line_of("table3.rs232_isr_us"),
                      latency = line_of("interrupts.rs232_0.latency_us.max"),
                      delivery = line_of("ports[0].frames_delivered"), family = line_of("\n  comm_cpu ");
    ASSERT_NE(check, std::string::npos) << s;
    EXPECT_LT(check, budget) << s;
    EXPECT_LT(budget, latency) << s;
    EXPECT_LT(latency, delivery) << s;
    EXPECT_LT(delivery, family) << s;
    // The 300 counters are one line: their family, its count, the largest change and its run.
    EXPECT_NE(s.find("other figures: 300 in 1 families"), std::string::npos) << s;
    EXPECT_EQ(s.find("comm_cpu.counter_1 "), std::string::npos) << "a counter listed alone:\n" << s;
    EXPECT_LT(std::count(s.begin(), s.end(), '\n'), 30) << s;
    // Still exact: every changed figure is counted (per run the two of table3, the latency, the
    // delivery count and the 300 counters).
    EXPECT_NE(s.find("figures: 608 regressions"), std::string::npos) << s;
}

TEST(Compare, JunitHasOneTestcasePerRunPerCheckAndPerFigureFamily) {
    std::map<std::string, RunRecord> base, cur;
    for (const char* id : {"a", "b"}) base.emplace(id, run_of(id, slowed(false))), cur.emplace(id, run_of(id, slowed(true)));
    const std::string x = junit_xml(compare_runs(base, cur, default_tolerances(), false));
    auto count = [&x](const std::string& what) {
        std::size_t n = 0;
        for (auto at = x.find(what); at != std::string::npos; at = x.find(what, at + 1)) ++n;
        return n;
    };
    // Per run: run, check overruns, and the families wall_time_s, rtf, table3, interrupts.rs232_0,
    // ports[0], comm_cpu; all but run and the two ignored fail.
    EXPECT_EQ(count("<testcase "), 2u * 8u) << x;
    EXPECT_EQ(count("<failure "), 2u * 5u) << x;
    EXPECT_NE(x.find("name=\"figures comm_cpu\"><failure type=\"regression\" message=\"300 figures regressed: "),
              std::string::npos) << x;
    EXPECT_NE(x.find("; and 295 more"), std::string::npos) << x;
}

TEST(Compare, HtmlHasTheRegressionTableAndOverlaidHistogram) {
    Comparison c;
    one(report(82, 10, true), report(90, 10, true), default_tolerances(), &c);
    const std::string h = compare_html(c);
    EXPECT_NE(h.find("<h2>Regressions (1)</h2>"), std::string::npos);
    EXPECT_NE(h.find("<tr class=\"reg\"><td class=\"k\">r</td><td class=\"k\">table3.rs232_isr_us</td>"), std::string::npos);
    EXPECT_NE(h.find("fill-opacity=\"0.55\""), std::string::npos); // baseline and current bars overlaid
    EXPECT_EQ(h.find("src=\"http"), std::string::npos);             // self-contained
}

// Issue #51 item 3: which way a figure is better comes from the check that limits it or the time
// it measures (scenarios/verdict/checks.cpp: table3_margin_us >=, frames_delivered >=, overruns <=).
TEST(Compare, AFiguresDirectionComesFromItsCheckOrWhatItMeasures) {
    using B = Tolerance::Better;
    EXPECT_EQ(figure_direction("table3.margin_us"), B::higher);
    EXPECT_EQ(figure_direction("table3.worst_margin_us"), B::higher);
    EXPECT_EQ(figure_direction("table3.rs232_isr_us"), B::lower);
    EXPECT_EQ(figure_direction("table3.budget_us"), B::none);
    EXPECT_EQ(figure_direction("interrupts.rs232_0.latency_us.max"), B::lower);
    EXPECT_EQ(figure_direction("interrupts.rs232_0.latency_us.count"), B::none);
    EXPECT_EQ(figure_direction("ports[1].frames_delivered"), B::higher);
    EXPECT_EQ(figure_direction("ports[1].overruns"), B::lower);
    EXPECT_EQ(figure_direction("comm_cpu.instructions"), B::none);
    // A tolerance's `better` overrides it.
    const RunDiff r = one(report(82, 10, true), report(82, 5, true),
                          with_defaults({rule("table3.margin_us", 0, 0, Tolerance::Better::lower)}));
    EXPECT_EQ(figure(r, "table3.margin_us").better, B::lower);
    EXPECT_EQ(figure(one(report(82, 10, true), report(82, 5, true)), "table3.margin_us").better, B::higher);
}

// The delta is coloured by the figure's direction, not its sign: a margin that shrinks (negative
// delta) and an ISR time that grows (positive) are both worse; a figure of unknown direction is
// neutral.
TEST(Compare, HtmlColoursADeltaWorseOrBetterByTheFiguresDirection) {
    auto cell_of = [](const std::string& h, const std::string& key) {
        const auto at = h.find("<td class=\"k\">" + key + "</td>", h.find("Runs side by side"));
        const auto delta = h.find("</td><td", h.find("</td><td", h.find("</td><td", at) + 1) + 1); // after baseline, current
        return h.substr(delta, h.find('>', delta + 5) - delta);
    };
    json base = report(82, 10, true), cur = report(90, 5, true);
    base["comm_cpu"] = {{"instructions", 100}};
    cur["comm_cpu"] = {{"instructions", 120}};
    Comparison c;
    one(base, cur, default_tolerances(), &c);
    const std::string h = compare_html(c);
    EXPECT_NE(cell_of(h, "table3.margin_us").find("class=\"worse\""), std::string::npos) << cell_of(h, "table3.margin_us");
    EXPECT_NE(cell_of(h, "table3.rs232_isr_us").find("class=\"worse\""), std::string::npos);
    EXPECT_EQ(cell_of(h, "comm_cpu.instructions").find("class="), std::string::npos) << cell_of(h, "comm_cpu.instructions");
    Comparison back;
    one(cur, base, default_tolerances(), &back); // the margin grows, the ISR time shrinks
    const std::string g = compare_html(back);
    EXPECT_NE(cell_of(g, "table3.margin_us").find("class=\"better\""), std::string::npos);
    EXPECT_NE(cell_of(g, "table3.rs232_isr_us").find("class=\"better\""), std::string::npos);
}

TEST(Compare, HtmlLeadsWithTheRankedReportAndCollapsesTheOtherFiguresPerFamily) {
    std::map<std::string, RunRecord> base, cur;
    for (const char* id : {"a", "b"}) base.emplace(id, run_of(id, slowed(false))), cur.emplace(id, run_of(id, slowed(true)));
    const std::string h = compare_html(compare_runs(base, cur, default_tolerances(), false));
    const auto console = h.find("-- checks that flipped"), table = h.find("<h2>Regressions (610)</h2>"),
               family = h.find("<details><summary>comm_cpu: 600 figures</summary>");
    ASSERT_NE(console, std::string::npos) << h.substr(0, 2000);
    ASSERT_NE(table, std::string::npos);
    ASSERT_NE(family, std::string::npos);
    EXPECT_LT(console, table);
    // In the table, the flipped check and the budget come before any collapsed family.
    const auto check = h.find("overruns", table), budget = h.find("table3.rs232_isr_us", table);
    EXPECT_LT(check, family);
    EXPECT_LT(budget, family);
}

TEST(Tolerances, FileRulesComeFirstAndBadFilesNameTheLine) {
    const fs::path d = rcsim::test::scratch_dir();
    std::ofstream(d / "t.yaml") << "tolerances:\n  - {figure: 'table3.*', abs: 0.5, better: lower}\n";
    const auto rules = load_tolerances((d / "t.yaml").string());
    ASSERT_EQ(rules.size(), 1 + default_tolerances().size());
    EXPECT_EQ(rules[0].abs, 0.5);
    EXPECT_EQ(rules[0].origin, (d / "t.yaml").string() + ":2");
    auto error = [&d](const std::string& text) {
        std::ofstream(d / "bad.yaml") << text;
        try {
            load_tolerances((d / "bad.yaml").string());
        } catch (const ConfigError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(error("tolerances:\n  - {figure: x, better: up}\n").find("bad.yaml:2: 'tolerances[0].better' must be"),
              std::string::npos);
    EXPECT_NE(error("tolerances:\n  - {figure: x, abs: -1}\n").find("bad.yaml:2: 'tolerances[0].abs' = -1 is out of range"),
              std::string::npos);
    EXPECT_NE(error("tolerances:\n  - {figure: x, tol: 1}\n").find("bad.yaml:2: unknown key 'tolerances[0].tol'"),
              std::string::npos);
    EXPECT_NE(error("tolerance: []\n").find("bad.yaml:1: unknown key 'tolerance'"), std::string::npos);
}
