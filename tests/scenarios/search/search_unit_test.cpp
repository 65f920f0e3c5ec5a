// rcsim search's parts (scenarios/search): the Latin hypercube, the axes and a point as a scenario,
// the search section, the figure paths, the influence of an axis, and the optimiser on functions
// whose best is known.
#include "models/plumbing/config_error.h"
#include "scenarios/config/scenario.h"
#include "scenarios/search/axes.h"
#include "scenarios/search/optimiser.h"
#include "scenarios/search/search.h"
#include "scenarios/search/search_page.h"
#include "tests/support/files.h"
#include "tests/support/scenario_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>
#include <stdexcept>

using namespace rcsim;
using namespace rcsim::search;
namespace fs = std::filesystem;
using rcsim::test::config_error_of;

namespace {

// 9600 bps, 8E1: START + 8 data + parity + STOP = 11 bits a character (docs/system.md §5.1).
constexpr double kCharUs = 11 * 1e6 / 9600;

Scenario scenario_of(const std::string& text) {
    const fs::path f = rcsim::test::scratch_dir() / "s.yaml";
    std::ofstream(f) << text;
    return load_scenario(f.string());
}

const char* const kThreePorts =
    "duration_s: 0.1\nports:\n"
    "  - {host: protocol, traffic: saturate, start_ms: 50, data_size: 64, random_size: true}\n"
    "  - {host: raw, send: [{at_ms: 1, bytes: A}]}\n"
    "  - {host: protocol, traffic: fixed, rate_hz: 20, start_ms: 5, data_size: 16}\n";

const Axis* find(const std::vector<Axis>& axes, const std::string& path) {
    for (const Axis& a : axes)
        if (a.path == path) return &a;
    return nullptr;
}

} // namespace

TEST(LatinHypercube, OnePointInEachCellOfEveryAxis) {
    const auto pts = latin_hypercube(16, 3, 7);
    ASSERT_EQ(pts.size(), 16u);
    for (std::size_t d = 0; d < 3; ++d) {
        std::set<int> cells;
        for (const auto& p : pts) {
            ASSERT_GE(p[d], 0.0);
            ASSERT_LT(p[d], 1.0);
            cells.insert(static_cast<int>(p[d] * 16));
        }
        EXPECT_EQ(cells.size(), 16u) << "axis " << d;
    }
    EXPECT_EQ(latin_hypercube(16, 3, 7), pts);
    EXPECT_NE(latin_hypercube(16, 3, 8), pts);
}

TEST(SearchAxis, AWholeAxisGivesEveryValueAnEqualCell) {
    const Axis a{"seed", 1, 4, true, ""};
    EXPECT_EQ(a.at(0.0), 1);
    EXPECT_EQ(a.at(0.249), 1);
    EXPECT_EQ(a.at(0.25), 2);
    EXPECT_EQ(a.at(0.74), 3);
    EXPECT_EQ(a.at(0.99), 4);
    EXPECT_EQ(a.at(1.0), 4);
    EXPECT_EQ(a.text(3), "3");
    const Axis c{"ports[0].start_ms", 50, 51, false, ""};
    EXPECT_DOUBLE_EQ(c.at(0.5), 50.5);
    EXPECT_EQ(c.text(50.123456789012), "50.12345679");
}

TEST(SearchAxis, DefaultsAreWhatAnInstallationLeavesFree) {
    const Scenario s = scenario_of(kThreePorts);
    const auto axes = default_axes(s);
    // Port 0: saturating protocol traffic. One character time, one frame of its longest frame
    // (64 data bytes + SOH T1 T2 STX B1 B2 C1 C2 ETX, docs/system.md §5.3), the baud +-2 %.
    const Axis* phase = find(axes, "ports[0].char_phase_us");
    ASSERT_NE(phase, nullptr);
    EXPECT_NEAR(phase->hi, kCharUs, 1e-6);
    EXPECT_EQ(phase->lo, 0);
    const Axis* frame = find(axes, "ports[0].frame_phase_chars");
    ASSERT_NE(frame, nullptr);
    EXPECT_EQ(frame->hi, 64 + 9 - 1);
    EXPECT_TRUE(frame->whole);
    const Axis* baud = find(axes, "ports[0].baud");
    ASSERT_NE(baud, nullptr);
    EXPECT_EQ(baud->lo, 9408);
    EXPECT_EQ(baud->hi, 9792);
    const Axis* size = find(axes, "ports[0].data_size");
    ASSERT_NE(size, nullptr);
    EXPECT_EQ(size->hi, 64);
    EXPECT_EQ(find(axes, "ports[0].rate_hz"), nullptr); // saturate: no gaps to vary
    // Port 1 is a raw host: its schedule is the scenario's, nothing by default.
    for (const Axis& a : axes) EXPECT_EQ(a.path.rfind("ports[1].", 0), std::string::npos) << a.path;
    // Port 2: fixed traffic, its gaps by its rate +-50 %.
    const Axis* rate = find(axes, "ports[2].rate_hz");
    ASSERT_NE(rate, nullptr);
    EXPECT_DOUBLE_EQ(rate->lo, 10);
    EXPECT_DOUBLE_EQ(rate->hi, 30);
    // The main CPU's response (command_time_us 50 by default, docs/scenarios.md) and the seed.
    const Axis* cmd = find(axes, "main_cpu.command_time_us");
    ASSERT_NE(cmd, nullptr);
    EXPECT_DOUBLE_EQ(cmd->lo, 25);
    EXPECT_DOUBLE_EQ(cmd->hi, 75);
    ASSERT_NE(find(axes, "seed"), nullptr);
}

TEST(SearchAxis, APointBecomesAScenario) {
    const Scenario s = scenario_of(std::string(kThreePorts) + "search: {axes: {seed: [1, 9]}}\n");
    const std::vector<Axis> axes{{"ports[0].char_phase_us", 0, kCharUs, false, ""},
                                 {"ports[0].frame_phase_chars", 0, 72, true, ""},
                                 {"ports[0].baud", 9408, 9792, true, ""},
                                 {"ports[2].data_size", 0, 16, true, ""},
                                 {"seed", 1, 9, true, ""}};
    const YAML::Node doc = apply(s.root, s, axes, {100, 3, 9792, 5, 7});
    // start_ms 50 + 3 characters + 100 us.
    EXPECT_NEAR(doc["ports"][0]["start_ms"].as<double>(), 50 + (3 * kCharUs + 100) / 1000, 1e-8);
    EXPECT_EQ(doc["ports"][0]["format"].as<std::string>(), "9792,8E1");
    EXPECT_EQ(doc["ports"][2]["data_size"].as<int>(), 5);
    EXPECT_EQ(doc["seed"].as<int>(), 7);
    EXPECT_FALSE(doc["search"]); // a run has no search section
    EXPECT_TRUE(s.root["search"]);  // the base is left as it was
}

TEST(SearchAxis, WrittenAxesAreCheckedAgainstTheScenario) {
    const Scenario s = scenario_of(kThreePorts);
    auto written = [&](const std::string& text) {
        return config_error_of([&] { written_axes({parse_axis_text(text)}, s, "--axis"); });
    };
    EXPECT_EQ(written("ports[0].char_phase_us=0..100"), "");
    EXPECT_EQ(written("ports[1].send[0].at_ms=0.5..2"), "");
    EXPECT_NE(written("ports[1].char_phase_us=0..100").find("not a protocol host"), std::string::npos);
    EXPECT_NE(written("ports[5].data_size=0..3").find("ports[5].data_size"), std::string::npos);
    EXPECT_NE(written("ports[4].baud=9000..9600").find("no port 4"), std::string::npos);
    EXPECT_NE(written("seed=9..1").find("above the high end"), std::string::npos);
    EXPECT_NE(written("seed=a..9").find("'a' is not a number"), std::string::npos);
    EXPECT_NE(written("seed=1").find("PATH=LO..HI"), std::string::npos);
    EXPECT_NE(written("ports[0].frame_phase_chars=0.5..3").find("whole numbers"), std::string::npos);
}

TEST(SearchSection, IsReadWithTheScenarioAndErrorsNameTheLine) {
    const Scenario s = scenario_of("search:\n  axes:\n    seed: [1, 50]\n  algorithm: crs2\n  starts: 2\n");
    ASSERT_TRUE(s.search);
    ASSERT_EQ(s.search->axes.size(), 1u);
    EXPECT_EQ(s.search->axes[0].path, "seed");
    EXPECT_TRUE(s.search->axes[0].whole);
    EXPECT_EQ(s.search->algorithm, "crs2");
    EXPECT_EQ(*s.search->starts, 2u);
    const std::string bad_alg = config_error_of([] { scenario_of("search:\n  algorithm: simplex\n"); });
    EXPECT_NE(bad_alg.find(":2:"), std::string::npos) << bad_alg;
    EXPECT_NE(bad_alg.find("subplex"), std::string::npos) << bad_alg;
    const std::string bad_range = config_error_of([] { scenario_of("search:\n  axes:\n    seed: [1]\n"); });
    EXPECT_NE(bad_range.find(":3:"), std::string::npos) << bad_range;
    EXPECT_NE(config_error_of([] { scenario_of("search:\n  axis: {}\n"); }).find("axis"), std::string::npos);
}

TEST(SearchFigure, PathsAsTheSummaryNamesThem) {
    const nlohmann::json r = nlohmann::json::parse(
        R"({"interrupts": {"rs232_0": {"latency_us": {"max": 402.125, "count": 3}}, "dpram": {"latency_us": {"max": null}}},
            "ports": [{"overruns": 0}, {"overruns": 2}], "passed": true, "flag": true})");
    EXPECT_EQ(*figure_of(r, "interrupts.rs232_0.latency_us.max"), 402.125);
    EXPECT_EQ(*figure_of(r, "ports[1].overruns"), 2);
    EXPECT_FALSE(figure_of(r, "interrupts.dpram.latency_us.max"));
    const std::string missing = config_error_of([&] { figure_of(r, "interrupts.rs232_9.latency_us.max"); });
    EXPECT_NE(missing.find("under 'interrupts'"), std::string::npos) << missing;
    EXPECT_NE(missing.find("interrupts.rs232_0.latency_us.max"), std::string::npos) << missing;
    EXPECT_NE(missing.find("interrupts.dpram.latency_us.max"), std::string::npos) << missing;
    EXPECT_EQ(missing.find("ports[0]"), std::string::npos) << missing;
    EXPECT_NE(config_error_of([&] { figure_of(r, "flag"); }).find("not a number"), std::string::npos);
}

TEST(SearchInfluence, TheAxisThatDecidesTheFigureExplainsItsVariance) {
    SearchResult r;
    r.axes = {{"a", 0, 1, false, ""}, {"b", 0, 1, false, ""}};
    const auto pts = latin_hypercube(40, 2, 3);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        Point p;
        p.values = pts[i];
        p.figure = std::floor(pts[i][0] * 4); // constant within each of a's four cells
        r.history.push_back(p);
    }
    const auto share = influence(r);
    EXPECT_NEAR(share[0], 1.0, 1e-12);
    EXPECT_LT(share[1], 0.2);
}

namespace {

/// A smooth bowl with its top at (0.3, 0.7): the streams must climb it.
struct Bowl {
    std::vector<std::vector<double>> asked;
    double best = -1e9;
    bool operator()(const std::vector<Ask>& asks, std::vector<Answer>& out) {
        for (std::size_t i = 0; i < asks.size(); ++i) {
            const auto& u = asks[i].u;
            asked.push_back(u);
            const double f = -((u[0] - 0.3) * (u[0] - 0.3) + (u[1] - 0.7) * (u[1] - 0.7));
            best = std::max(best, f);
            out[i].figure = f;
        }
        return true;
    }
};

} // namespace

TEST(SearchOptimiser, EveryAlgorithmClimbsASmoothTopWithinItsBudget) {
    for (const std::string& alg : search_algorithms()) {
        Bowl bowl;
        const Plan plan{alg, 2, 80, 2, 1, Direction::maximize, {}};
        ASSERT_TRUE(optimise(plan, [&](const auto& a, auto& o) { return bowl(a, o); })) << alg;
        EXPECT_LE(bowl.asked.size(), 80u) << alg;
        // Within 0.03 of the top for the local ones; 0.1 for CRS2, a population spread over the box.
        const double within = alg == "crs2" ? 0.1 : 0.03;
        EXPECT_GT(bowl.best, -within * within) << alg << ": the top is 0 at (0.3, 0.7)";
    }
}

TEST(SearchOptimiser, TheSameSeedAsksTheSamePoints) {
    for (const std::string& alg : {std::string("subplex"), std::string("crs2")}) {
        Bowl a, b, c;
        const Plan plan{alg, 3, 40, 3, 5, Direction::minimize, {}};
        optimise(plan, [&](const auto& x, auto& o) { return a(x, o); });
        optimise(plan, [&](const auto& x, auto& o) { return b(x, o); });
        EXPECT_EQ(a.asked, b.asked) << alg;
        Plan other = plan;
        other.seed = 6;
        optimise(other, [&](const auto& x, auto& o) { return c(x, o); });
        EXPECT_NE(a.asked, c.asked) << alg;
    }
}

TEST(SearchOptimiser, AStopEndsTheSearchAndAnErrorComesUp) {
    std::size_t batches = 0;
    const Plan plan{"subplex", 2, 40, 4, 1, Direction::maximize, {}};
    const bool finished = optimise(plan, [&](const std::vector<Ask>& asks, std::vector<Answer>& out) {
        for (auto& o : out) o.figure = 1.0;
        (void)asks;
        return ++batches < 3; // the third batch is the last
    });
    EXPECT_FALSE(finished);
    EXPECT_EQ(batches, 3u);
    std::size_t calls = 0;
    EXPECT_THROW(optimise(plan,
                          [&](const std::vector<Ask>&, std::vector<Answer>& out) -> bool {
                              for (auto& o : out) o.figure = std::nullopt; // no figure: the worst to NLopt
                              if (++calls == 2) throw std::runtime_error("a run the loader refused");
                              return true;
                          }),
                 std::runtime_error);
}

TEST(SearchOptimiser, TheBudgetCountsRunsAndAConvergedStreamGoesOnFromTheNextStart) {
    // A figure that is one value everywhere: a stream converges at once (its points all ran
    // before, 16 cells in all), gives way to the next sample point it was dealt, and answers from
    // earlier runs cost nothing: never more runs than the budget.
    std::set<std::vector<double>> ran;
    std::vector<std::vector<double>> sample;
    std::set<std::size_t> starts_used;
    std::size_t runs = 0;
    const Plan plan{"subplex", 2, 40, 1, 3, Direction::maximize, {}};
    optimise(plan, [&](const std::vector<Ask>& asks, std::vector<Answer>& out) {
        for (std::size_t i = 0; i < asks.size(); ++i) {
            const auto& u = asks[i].u;
            if (asks[i].stage == "sample") sample.push_back(u);
            else { // the sample point this one is nearest to: the start it came from
                std::size_t nearest = 0;
                auto d2 = [&](std::size_t k) { return std::pow(u[0] - sample[k][0], 2) + std::pow(u[1] - sample[k][1], 2); };
                for (std::size_t k = 1; k < sample.size(); ++k)
                    if (d2(k) < d2(nearest)) nearest = k;
                starts_used.insert(nearest);
            }
            out[i].ran = ran.insert({std::floor(u[0] * 4), std::floor(u[1] * 4)}).second;
            runs += out[i].ran ? 1 : 0;
            out[i].figure = 1.0;
        }
        return true;
    });
    EXPECT_LE(runs, 40u);
    EXPECT_EQ(starts_used.size(), sample.size()) << "one stream went on from every sample point";
}

TEST(SearchOptimiser, WithTheSeedAloneTheSampleIsTheWholeSearch) {
    std::size_t asked = 0;
    const Plan plan{"subplex", 1, 30, 4, 1, Direction::maximize, {true}};
    optimise(plan, [&](const std::vector<Ask>& asks, std::vector<Answer>& out) {
        for (std::size_t i = 0; i < asks.size(); ++i) {
            EXPECT_EQ(asks[i].stage, "sample");
            out[i].figure = asks[i].u[0];
        }
        asked += asks.size();
        return true;
    });
    EXPECT_EQ(asked, 30u);
}

TEST(SearchCause, TheWitnessSaysWhatHeldItsFigure) {
    const nlohmann::json r = nlohmann::json::parse(R"({
        "interrupts": {"rs232_0": {"latency_us": {"max": 418.125},
                                   "worst": [{"text": "the rs232_1 interrupt in service for 203.9 us"}]}},
        "table3": {"budget_us": 381.9444, "rs232_isr_us": 62.5, "rs232_isr_max_us": 218.375, "dpram_byte_us": 40.5,
                   "margin_us": 278.9, "worst_margin_us": 123.0694},
        "checks": [{"name": "overruns", "passed": true}, {"name": "frames_failed", "passed": false, "why": "port 1 gave up"}],
        "verdict_reason": "a check failed"})");
    EXPECT_EQ(witness_cause(r, "interrupts.rs232_0.latency_us.max"),
              "rs232_0's worst latency: the rs232_1 interrupt in service for 203.9 us");
    const std::string t3 = witness_cause(r, "table3.worst_margin_us");
    EXPECT_NE(t3.find("longest 218.375 us"), std::string::npos) << t3;
    EXPECT_NE(t3.find("worst margin 123.069 us"), std::string::npos) << t3;
    EXPECT_EQ(witness_cause(r, "ports[0].overruns"), "frames_failed: port 1 gave up");
    nlohmann::json passed = r;
    passed["checks"] = nlohmann::json::array();
    EXPECT_EQ(witness_cause(passed, "ports[0].overruns"), "a check failed");
}
