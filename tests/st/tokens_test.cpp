// RN, SP, HT and ST with a loaded Structured Text program (docs/system.md §7.2, docs/st.md): the
// dispatcher's answers, and over DP-RAM the main CPU running the program once per control cycle.
#include "main_cpu/dispatcher.h"
#include "main_cpu/main_cpu.h"
#include "tests/main_cpu/comm_side.h"
#include "tests/st/st_test.h"
#include "tests/support/sc_test.h"

using namespace rcsim;
using rcsim::st::StProgram;

namespace {

const char* counter = "PROGRAM Count VAR n : DINT; zero : DINT; crash : BOOL; END_VAR\n"
                      "n := n + 1; IF crash THEN n := n / zero; END_IF; END_PROGRAM";

StProgram loaded() { return StProgram(counter, "c.st", {}, {}); }

TEST(StTokens, RnStartsALoadedProgramAndStReportsIt) {
    StProgram p = loaded();
    Dispatcher d;
    d.set_program(&p);
    EXPECT_EQ(d.execute("RN", "Nope").bch, bch::bad_data); // neither loaded nor uploaded
    EXPECT_EQ(d.execute("ST", "").data, "NO_MOTION,IDLE,");
    EXPECT_EQ(d.execute("RN", "Count").bch, bch::ok);
    EXPECT_TRUE(p.running());
    EXPECT_EQ(d.execute("ST", "").data, "NO_MOTION,RUNNING,Count");
    const Outcome again = d.execute("RN", "Count");
    EXPECT_EQ(again.bch, bch::busy);
    EXPECT_EQ(again.note, "RN: program 'Count' is already running");
}

TEST(StTokens, SpStopsTheProgramAndRefusesWhenNothingRuns) {
    StProgram p = loaded();
    Dispatcher d;
    d.set_program(&p);
    EXPECT_EQ(d.execute("SP", "").bch, bch::not_allowed);
    ASSERT_EQ(d.execute("RN", "count").bch, bch::ok); // PROGRAM names are case-insensitive
    p.run_once(0);
    EXPECT_EQ(d.execute("SP", "x").bch, bch::bad_data);
    EXPECT_EQ(d.execute("SP", "").bch, bch::ok);
    EXPECT_FALSE(p.running());
    p.run_once(1000); // a stopped program is not executed
    EXPECT_EQ(p.value("n").i, 1);
    EXPECT_EQ(d.execute("ST", "").data, "NO_MOTION,IDLE,count");
    EXPECT_EQ(d.execute("RN", "Count").bch, bch::ok); // a new cold start
    EXPECT_EQ(p.value("n").i, 0);
    EXPECT_EQ(d.execute("HT", "").bch, bch::ok);
    EXPECT_FALSE(p.running());
    EXPECT_EQ(d.execute("ST", "").data, "NO_MOTION,HALTED,Count");
}

TEST(StTokens, ARuntimeErrorShowsAsErrorInSt) {
    StProgram p = loaded();
    Dispatcher d;
    d.set_program(&p);
    ASSERT_EQ(d.execute("RN", "Count").bch, bch::ok);
    p.set_value("crash", st::Value{1, 0});
    p.run_once(0);
    EXPECT_EQ(p.error(), "c.st:2:34: division by zero");
    EXPECT_EQ(d.execute("ST", "").data, "NO_MOTION,ERROR,Count");
    EXPECT_EQ(d.execute("SP", "").bch, bch::not_allowed); // it is not running any more
    EXPECT_EQ(d.execute("RN", "Count").bch, bch::ok);     // RN restarts it
}

TEST(StTokens, UploadedProgramsStillRunByName) {
    StProgram p = loaded();
    Dispatcher d;
    d.set_program(&p);
    ASSERT_EQ(d.execute("PU", "job1,anything").bch, bch::ok);
    EXPECT_EQ(d.execute("RN", "job1").bch, bch::ok);
    EXPECT_FALSE(p.running()); // the loaded program is not involved
    EXPECT_EQ(d.execute("ST", "").data, "NO_MOTION,RUNNING,job1");
    EXPECT_EQ(d.execute("SP", "").bch, bch::ok);
    EXPECT_EQ(d.execute("ST", "").data, "NO_MOTION,IDLE,job1");
}

// Over DP-RAM: an RN frame reaches the dispatcher, and from then on the main CPU's control cycle
// runs the program once per cycle (1 ms period).
TEST(StTokens, TheMainCpuRunsTheProgramOncePerControlCycleAfterRn) {
    test::FakeDpram ram{"ram"};
    MainCpu cpu("cpu");
    test::CommSide comm{"comm", ram};
    cpu.dpram.bind(ram.right);
    cpu.int_r(ram.int_r);
    StProgram p = loaded();
    cpu.set_program(&p);
    test::ReceivedByComm got;
    comm.script = [&](test::CommSide& c) {
        c.send_frame(0, proto::encode({"RN", 0, "Count"}));
        got = c.receive_frame(0);
    };
    sc_core::sc_start(sc_core::sc_time(20, sc_core::SC_MS) + sc_core::sc_time(1, sc_core::SC_US));
    proto::Frame f;
    ASSERT_EQ(proto::decode(got.bytes, f), "");
    EXPECT_EQ(f.token, "RN");
    EXPECT_EQ(f.bch, bch::ok);
    ASSERT_TRUE(p.running());
    // Cycles start at 0, 1, ..., 20 ms: the program ran in every cycle after the RN was dispatched,
    // so n counts the cycles from then on, one fewer at most than all 21.
    EXPECT_EQ(static_cast<std::uint64_t>(p.value("n").i), p.cycles());
    EXPECT_GE(p.cycles(), 15u);
    EXPECT_LT(p.cycles(), cpu.control_cycles());
}

} // namespace
