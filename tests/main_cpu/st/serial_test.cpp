// A Structured Text program in the whole board (main_cpu.program, docs/st.md): RN, SP and ST from
// a scripted serial host travel through the comm CPU's firmware and the DP-RAM to the main CPU,
// whose control cycle runs the program; a bad program is bad input naming file, line and column.
#include "models/plumbing/config_error.h"
#include "scenarios/world/world.h"
#include "scenarios/run/runner.h"
#include "scenarios/config/scenario.h"
#include "tests/support/scenario_error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace rcsim;

namespace {

const std::string cases = std::string(RCSIM_SOURCE_DIR) + "/tests/main_cpu/st/cases/";

std::string load_error(const std::string& file) { return rcsim::test::scenario_error(cases + file); }

/// The fields of an ST reply: robot state, program state, program name, four positions.
std::vector<std::string> fields(const std::string& data) {
    std::vector<std::string> out(1);
    for (char c : data)
        if (c == ',') out.emplace_back();
        else out.back() += c;
    return out;
}

// serial_program.yaml's host: RN MOVER, wait for CONTINUOUS_MOTION, ST, SP, wait for
// STANDSTILL, ST. The program (serial_mover.st) powers axis 0 and drives it at 5000 pulses/s.
TEST(StSerial, RnStartsTheLoadedProgramStReportsItSpStopsIt) {
    std::vector<FrameRecord> sent; // the main CPU's responses, as handed to the DP-RAM
    RunOptions opt;
    opt.reproducible = true;
    opt.on_world = [&sent](World& w) {
        ASSERT_TRUE(w.program);
        auto observer = w.ctl.main.on_sent; // the world's exactly-once observer: keep it
        w.ctl.main.on_sent = [observer, &sent](const FrameRecord& f) {
            if (observer) observer(f);
            sent.push_back(f);
        };
    };
    nlohmann::json report;
    // Every check holds: the script completed (RN and SP answered 00, both states reached), every
    // response reached the host exactly once, the program ran without an error.
    EXPECT_EQ(run_scenario(load_scenario(cases + "serial_program.yaml"), opt, report), 0) << report["checks"].dump(1);

    std::vector<std::vector<std::string>> st;
    std::vector<std::string> tokens;
    for (const FrameRecord& f : sent) {
        tokens.push_back(f.token);
        EXPECT_EQ(f.bch, 0) << f.token;
        if (f.token == "ST") st.push_back(fields(f.data));
    }
    ASSERT_GE(st.size(), 2u);
    // The first ST after RN that saw the axis moving (the wait_state step's last reply).
    std::size_t moving = 0;
    while (moving < st.size() && st[moving][0] != "CONTINUOUS_MOTION") ++moving;
    ASSERT_LT(moving + 1, st.size());
    const std::vector<std::string>& during = st[moving + 1]; // the script's own ST step
    ASSERT_EQ(during.size(), 7u);
    EXPECT_EQ(during[0], "CONTINUOUS_MOTION");
    EXPECT_EQ(during[1], "RUNNING");
    EXPECT_EQ(during[2], "MOVER");
    EXPECT_GT(std::stoll(during[3]), 0); // axis 0 moved in + (Direction 1)
    EXPECT_EQ(during[4], "0");           // axis 1 did not
    const std::vector<std::string>& after = st.back(); // after SP and STANDSTILL
    EXPECT_EQ(after[0], "STANDSTILL");
    EXPECT_EQ(after[1], "IDLE");
    EXPECT_EQ(after[2], "MOVER");
    EXPECT_GT(std::stoll(after[3]), std::stoll(during[3])); // it decelerated, not jumped back
    // RN first, SP after the RUNNING reply.
    ASSERT_FALSE(tokens.empty());
    EXPECT_EQ(tokens.front(), "RN");
    EXPECT_EQ(std::count(tokens.begin(), tokens.end(), "SP"), 1);

    const nlohmann::json& program = report["main_cpu"]["program"];
    EXPECT_EQ(program["state"], "STOPPED");
    EXPECT_GT(program["cycles"].get<std::uint64_t>(), 0u);
    EXPECT_GT(report["main_cpu"]["program_cost"]["statements"].get<std::uint64_t>(), 0u);
}

TEST(StSerial, AProgramWithASyntaxErrorIsBadInputNamingFileLineAndColumn) {
    EXPECT_EQ(load_error("serial_syntax.yaml"), cases + "syntax.st:4:1: expected ';', found 'END_PROGRAM'");
}

TEST(StSerial, AMissingProgramFileIsBadInputNamingTheScenarioLine) {
    EXPECT_EQ(load_error("serial_missing.yaml"),
              cases + "serial_missing.yaml:4: cannot read the Structured Text program '" + cases +
                  "no_such_file.st' (no such regular file)");
}

/// The error of a scenario with this text (written to a scratch file named `name`), without the
/// scratch folder's path.
std::string text_error(const std::string& name, const std::string& text) {
    const std::string e = rcsim::test::scenario_error_of(name, text);
    const std::string dir = rcsim::test::scratch_dir().string() + "/";
    return e.rfind(dir, 0) == 0 ? e.substr(dir.size()) : e;
}

TEST(StSerial, ProgramKeysOutOfPlaceOrRangeAreBadInput) {
    EXPECT_EQ(text_error("budget.yaml", "main_cpu:\n  statement_budget: 10\n"),
              "budget.yaml:2: 'main_cpu.statement_budget' bounds a program: it needs 'main_cpu.program'");
    const std::string e = text_error("cost.yaml", "main_cpu:\n  statement_us: 1001\n");
    EXPECT_EQ(e.rfind("cost.yaml:2:", 0), 0u) << e;
    EXPECT_NE(e.find("statement_us"), std::string::npos) << e;
    EXPECT_EQ(text_error("ok.yaml", "main_cpu:\n  statement_us: 1000\n"), "(no error)");
}

} // namespace
