// The X-Y plotter end to end: scenarios/xy_plotter_st.yaml (the ST program st/xy_plotter.st)
// draws the same circle as the built-in scenarios/xy_plotter_circle.yaml. CTest's fixture
// st.plotter_runs runs both with the rcsim executable first; this compares their trajectory.csv
// sample by sample from the cycle each run commanded the circle, within 1 pulse on both axes,
// commanded and actual positions.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Sample {
    std::array<long long, 2> cmd{}, act{};
};
using Trajectory = std::map<long long, Sample>; // microseconds -> axes 0 and 1

Trajectory read_csv(const std::string& file) {
    Trajectory t;
    std::ifstream in(file);
    EXPECT_TRUE(in) << file;
    std::string line;
    std::getline(in, line); // t_s,axis,cmd_pulses,act_pulses
    while (std::getline(in, line)) {
        std::stringstream s(line);
        double ts = 0;
        int axis = 0;
        long long cmd = 0, act = 0;
        char c = 0;
        s >> ts >> c >> axis >> c >> cmd >> c >> act;
        if (axis > 1) continue;
        Sample& x = t[std::llround(ts * 1e6)];
        x.cmd[static_cast<std::size_t>(axis)] = cmd;
        x.act[static_cast<std::size_t>(axis)] = act;
    }
    return t;
}

nlohmann::json read_json(const std::string& file) {
    std::ifstream in(file);
    EXPECT_TRUE(in) << file;
    return nlohmann::json::parse(in);
}

const std::string out = RCSIM_PLOTTER_OUT;

/// The largest difference of the two runs over `length_us` from their circle starts, `shift_us`
/// added to the ST run's start (0 for the real comparison).
long long worst_difference(long long length_us, long long shift_us) {
    const Trajectory builtin = read_csv(out + "/builtin/trajectory.csv");
    const Trajectory st = read_csv(out + "/st/trajectory.csv");
    const nlohmann::json b = read_json(out + "/builtin/report.json"), s = read_json(out + "/st/report.json");
    // The built-in run gave MC_CircleCenterMove Execute at its command's at_ms; the program
    // records the cycle it raised Execute in t_circle ("T#<ms>ms").
    const long long b0 = std::llround(b["motion"]["commands"][1]["at_ms"].get<double>() * 1000);
    const std::string tc = s["motion"]["program"]["variables"]["t_circle"].get<std::string>();
    const long long s0 = std::llround(std::stod(tc.substr(2)) * 1000) + shift_us;
    long long worst = 0;
    int compared = 0;
    for (long long t = 0; t <= length_us; t += 1000) {
        const auto x = builtin.find(b0 + t), y = st.find(s0 + t);
        if (x == builtin.end() || y == st.end()) break;
        for (std::size_t a = 0; a < 2; ++a) {
            worst = std::max(worst, std::llabs(x->second.cmd[a] - y->second.cmd[a]));
            worst = std::max(worst, std::llabs(x->second.act[a] - y->second.act[a]));
        }
        ++compared;
    }
    EXPECT_GE(compared * 1000LL, length_us) << "a trajectory ends before the circle does";
    return worst;
}

// The circle: 2 pi 5000 = 31416 pulses at 20000 pulses/s plus 0.1 s ramps, about 1.67 s; the
// comparison covers 2 s (the pen at rest after it).
constexpr long long circle_us = 2'000'000;

TEST(StPlotter, TheStProgramDrawsTheBuiltInCircleWithinOnePulse) {
    EXPECT_LE(worst_difference(circle_us, 0), 1);
}

TEST(StPlotter, TheComparisonSeesAOneCycleShift) {
    // The same comparison one cycle off: at 20000 pulses/s the pen moves 20 pulses per 1 ms cycle,
    // so a trajectory late by one cycle differs by far more than 1 pulse.
    EXPECT_GT(worst_difference(circle_us - 1000, 1000), 10);
}

TEST(StPlotter, TheProgramRanEveryStepAndSpStoppedIt) {
    const nlohmann::json s = read_json(out + "/st/report.json");
    const nlohmann::json& p = s["motion"]["program"];
    EXPECT_EQ(p["program"], "XY_Plotter");
    EXPECT_EQ(p["error"], "");
    EXPECT_EQ(p["state"], "STOPPED");            // SP at 3450 ms
    EXPECT_EQ(p["variables"]["state"], 6);        // the state machine reached "done"
    EXPECT_EQ(p["variables"]["corner"], 4);       // four sides of the square
    const nlohmann::json& cmds = s["motion"]["commands"];
    ASSERT_EQ(cmds.size(), 4u);
    EXPECT_EQ(cmds[0]["token"], "RN");
    EXPECT_EQ(cmds[0]["bch"], 0);
    // ST: robot state, program state, name, then the encoder positions: the pen back where it
    // started after homing (0, 0), within the 1 pulse the encoder may sit off the command.
    auto fields = [](const std::string& r) {
        std::vector<std::string> f(1);
        for (char c : r) {
            if (c == ',') f.emplace_back();
            else f.back().push_back(c);
        }
        return f;
    };
    const auto running = fields(cmds[1]["reply"]), stopped = fields(cmds[3]["reply"]);
    ASSERT_EQ(running.size(), 7u);
    EXPECT_EQ(running[0] + "," + running[1] + "," + running[2], "STANDSTILL,RUNNING,XY_PLOTTER");
    EXPECT_LE(std::abs(std::stoll(running[3])), 1);
    EXPECT_LE(std::abs(std::stoll(running[4])), 1);
    EXPECT_EQ(cmds[2]["bch"], 0); // SP
    ASSERT_EQ(stopped.size(), 7u);
    EXPECT_EQ(stopped[1], "IDLE");
}

} // namespace
