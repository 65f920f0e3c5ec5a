// Tests of the token dispatcher (docs/system.md §7), without a kernel.
#include "main_cpu/dispatcher.h"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

using namespace rcsim;

namespace {

/// Records every command and answers with a scripted reply.
class FakeMotion : public MotionInterface {
public:
    MotionReply reply;
    std::vector<std::pair<std::string, std::string>> commands;
    std::vector<sc_core::sc_time> cycles;

    MotionReply command(const std::string& token, const std::string& data) override {
        commands.emplace_back(token, data);
        return reply;
    }
    void control_cycle(const sc_core::sc_time& now) override { cycles.push_back(now); }
    std::vector<std::int64_t> positions() const override { return {100, -5, 0, 7}; }
    std::string state() const override { return "STANDSTILL"; }
};

} // namespace

TEST(Dispatcher, EchoReturnsTheData) {
    Dispatcher d;
    const Outcome o = d.execute("EC", "hello, world");
    EXPECT_EQ(o.bch, bch::ok);
    EXPECT_EQ(o.data, "hello, world");
}

TEST(Dispatcher, UnknownTokenIs01) {
    Dispatcher d;
    const Outcome o = d.execute("ZZ", "");
    EXPECT_EQ(o.bch, bch::unknown_token);
    EXPECT_NE(o.note.find("ZZ"), std::string::npos);
    EXPECT_EQ(d.execute("ec", "x").bch, bch::unknown_token); // tokens are case sensitive
}

TEST(Dispatcher, ParameterWriteThenRead) {
    Dispatcher d;
    EXPECT_EQ(d.execute("PW", "17,-250").bch, bch::ok);
    const Outcome o = d.execute("PR", "17");
    EXPECT_EQ(o.bch, bch::ok);
    EXPECT_EQ(o.data, "-250");
    EXPECT_EQ(d.execute("PW", "17,9").bch, bch::ok);
    EXPECT_EQ(d.execute("PR", "17").data, "9");
}

TEST(Dispatcher, ParameterBadDataIs02) {
    Dispatcher d;
    EXPECT_EQ(d.execute("PR", "5").bch, bch::bad_data); // never written
    EXPECT_EQ(d.execute("PR", "x").bch, bch::bad_data);
    EXPECT_EQ(d.execute("PR", "65536").bch, bch::bad_data);
    EXPECT_EQ(d.execute("PW", "5").bch, bch::bad_data);
    EXPECT_EQ(d.execute("PW", "5,1.5").bch, bch::bad_data);
    EXPECT_EQ(d.execute("PW", "5,1,2").bch, bch::bad_data);
    const Outcome o = d.execute("PW", "-1,3");
    EXPECT_NE(o.note.find("-1"), std::string::npos) << o.note;
    EXPECT_TRUE(d.parameters().empty());
}

TEST(Dispatcher, ProgramUploadKeepsCommasAndDownloadReturnsIt) {
    Dispatcher d;
    const std::string text = "MOVE P1, P2; WAIT 10; " + std::string(3000, 'x');
    EXPECT_EQ(d.execute("PU", "weld_1," + text).bch, bch::ok);
    const Outcome o = d.execute("PD", "weld_1");
    EXPECT_EQ(o.bch, bch::ok);
    EXPECT_EQ(o.data, text);
    EXPECT_EQ(d.execute("PD", "nope").bch, bch::bad_data);
    EXPECT_EQ(d.execute("PU", "no comma").bch, bch::bad_data);
    EXPECT_EQ(d.execute("PU", "bad name,x").bch, bch::bad_data);
    EXPECT_EQ(d.execute("PU", std::string(17, 'a') + ",x").bch, bch::bad_data);
}

TEST(Dispatcher, TeachPointStoreAndRead) {
    Dispatcher d;
    EXPECT_EQ(d.execute("TP", "P1,10,-20,30,-40").bch, bch::ok);
    const Outcome o = d.execute("TR", "P1");
    EXPECT_EQ(o.bch, bch::ok);
    EXPECT_EQ(o.data, "10,-20,30,-40");
    EXPECT_EQ(d.execute("TR", "P2").bch, bch::bad_data);
    EXPECT_EQ(d.execute("TP", "P1,1,2,3").bch, bch::bad_data);
    EXPECT_EQ(d.execute("TP", "P1,1,2,3,r").bch, bch::bad_data);
}

TEST(Dispatcher, RunAndHaltFollowTheProgramState) {
    Dispatcher d;
    EXPECT_EQ(d.execute("RN", "main").bch, bch::bad_data); // no such program
    EXPECT_EQ(d.execute("HT", "").bch, bch::not_allowed);  // nothing running
    ASSERT_EQ(d.execute("PU", "main,LOOP").bch, bch::ok);
    EXPECT_EQ(d.execute("RN", "main").bch, bch::ok);
    EXPECT_EQ(d.program_state(), ProgramState::running);
    EXPECT_EQ(d.execute("RN", "main").bch, bch::busy);
    EXPECT_EQ(d.execute("PU", "main,OTHER").bch, bch::busy); // cannot replace a running program
    EXPECT_EQ(d.execute("HT", "").bch, bch::ok);
    EXPECT_EQ(d.program_state(), ProgramState::halted);
}

TEST(Dispatcher, StateWithoutMotion) {
    Dispatcher d;
    d.execute("PU", "main,LOOP");
    d.execute("RN", "main");
    const Outcome o = d.execute("ST", "");
    EXPECT_EQ(o.bch, bch::ok);
    EXPECT_EQ(o.data, "NO_MOTION,RUNNING,main");
    EXPECT_EQ(d.execute("ST", "x").bch, bch::bad_data);
}

TEST(Dispatcher, StateWithMotionListsAxisPositions) {
    Dispatcher d;
    FakeMotion m;
    d.set_motion(&m);
    EXPECT_EQ(d.execute("ST", "").data, "STANDSTILL,IDLE,,100,-5,0,7");
}

TEST(Dispatcher, MotionTokensWithoutMotionAre04WithANote) {
    Dispatcher d;
    for (const char* t : {"SV", "HM", "RS", "MA", "MR", "ML", "MC", "ES"}) {
        const Outcome o = d.execute(t, "1");
        EXPECT_EQ(o.bch, bch::not_allowed) << t;
        EXPECT_NE(o.note.find("no motion interface"), std::string::npos) << t;
    }
}

TEST(Dispatcher, MotionTokensReachTheMotionLayerAndItsReplyIsReturned) {
    Dispatcher d;
    FakeMotion m;
    m.reply = MotionReply{bch::axis_error, "axis 2 limit"};
    d.set_motion(&m);
    const Outcome o = d.execute("MA", "1,1000,50,10,10");
    EXPECT_EQ(o.bch, bch::axis_error);
    EXPECT_EQ(o.data, "axis 2 limit");
    ASSERT_EQ(m.commands.size(), 1u);
    EXPECT_EQ(m.commands[0].first, "MA");
    EXPECT_EQ(m.commands[0].second, "1,1000,50,10,10");
}

TEST(Dispatcher, EmergencyStopHaltsTheProgramEvenWithoutMotion) {
    Dispatcher d;
    d.execute("PU", "main,LOOP");
    d.execute("RN", "main");
    EXPECT_EQ(d.execute("ES", "").bch, bch::not_allowed);
    EXPECT_EQ(d.program_state(), ProgramState::halted);
    FakeMotion m;
    d.set_motion(&m);
    d.execute("RN", "main");
    EXPECT_EQ(d.execute("ES", "").bch, bch::ok);
    EXPECT_EQ(d.program_state(), ProgramState::halted);
    ASSERT_EQ(m.commands.size(), 1u);
    EXPECT_EQ(m.commands[0].first, "ES");
}
