// RN, SP, HT and ST with a loaded Structured Text program (docs/system.md §7.2, docs/st.md): the
// dispatcher's answers, and over DP-RAM the main CPU running the program once per control cycle.
#include "main_cpu/dispatcher.h"
#include "main_cpu/main_cpu.h"
#include "tests/main_cpu/comm_side.h"
#include "tests/main_cpu/st/st_test.h"
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

// ---- the program's cost in the control cycle (docs/st.md "Cost in the control cycle") ----------

/// PROGRAM T: a FOR loop of n iterations of one assignment. Executed statements per cycle, as the
/// budget counts them (docs/st.md): the FOR statement, each of its n iterations and each body
/// statement, 1 + 2n.
std::string loop(int n) {
    return "PROGRAM T VAR i, x : DINT; END_VAR\nFOR i := 1 TO " + std::to_string(n) +
           " DO x := x + 1; END_FOR;\nEND_PROGRAM";
}
std::uint64_t loop_statements(int n) { return 1 + 2 * static_cast<std::uint64_t>(n); }

/// A main CPU on a DP-RAM nobody writes: only its control cycle runs.
struct CycleRig {
    test::FakeDpram ram;
    MainCpu cpu;
    std::unique_ptr<StProgram> program;
    CycleRig(const std::string& name, const MainCpuConfig& cfg, const std::string& text)
        : ram((name + "_ram").c_str()), cpu(name.c_str(), cfg) {
        cpu.dpram.bind(ram.right);
        cpu.int_r(ram.int_r);
        if (text.empty()) return;
        program = std::make_unique<StProgram>(text, name + ".st", std::vector<motion::McAxis*>{});
        EXPECT_EQ(program->start("T"), ""); // running from the first cycle, as after an RN
        cpu.set_program(program.get());
    }
    double max_us() const { return cpu.cycle_duration_us().summary().max; }
    double min_us() const { return cpu.cycle_duration_us().summary().min; }
};

TEST(StCost, EachExecutedStatementAddsStatementTimeToTheControlCycle) {
    constexpr int n = 50;
    MainCpuConfig cfg; // cycle_time 100 us, period 1 ms
    cfg.statement_time = sc_core::sc_time(2, sc_core::SC_US);
    MainCpuConfig free = cfg;
    free.statement_time = sc_core::SC_ZERO_TIME;
    CycleRig none("none", cfg, ""), empty("empty", cfg, loop(0)), busy("busy", cfg, loop(n)),
        zero("zero", free, loop(n));
    sc_core::sc_start(sc_core::sc_time(10, sc_core::SC_MS));

    const double t = 2.0, base = 100.0; // statement_time, cycle_time (us)
    // Every cycle runs the same statements, so min = max = cycle_time + statements x statement_time.
    EXPECT_DOUBLE_EQ(busy.min_us(), base + double(loop_statements(n)) * t);
    EXPECT_DOUBLE_EQ(busy.max_us(), base + double(loop_statements(n)) * t);
    EXPECT_DOUBLE_EQ(empty.max_us(), base + double(loop_statements(0)) * t);
    // n iterations more: 2n statements more (iteration and assignment).
    EXPECT_DOUBLE_EQ(busy.max_us() - empty.max_us(), 2.0 * n * t);
    // Cost 0: the figures of a main CPU without a program.
    EXPECT_DOUBLE_EQ(zero.max_us(), none.max_us());
    EXPECT_DOUBLE_EQ(zero.min_us(), base);
    EXPECT_DOUBLE_EQ(none.max_us(), base);
    EXPECT_EQ(zero.cpu.cycle_jitter_us().summary().max, none.cpu.cycle_jitter_us().summary().max);
    // The totals: one execution per control cycle.
    EXPECT_EQ(busy.program->cycles(), busy.cpu.control_cycles());
    EXPECT_EQ(busy.cpu.program_statements(), busy.cpu.control_cycles() * loop_statements(n));
    EXPECT_DOUBLE_EQ(to_us(busy.cpu.program_time()), double(busy.cpu.program_statements()) * t);
    EXPECT_EQ(busy.cpu.report()["program_cost"]["statements"], busy.cpu.program_statements());
    EXPECT_EQ(busy.cpu.report()["cycle_duration_us"]["max"], busy.max_us());
}

// The charge holds the processor: a program that makes the cycle's work longer than its period
// makes the next cycle start late (jitter) and skips periods (overruns).
TEST(StCost, AProgramLongerThanThePeriodDelaysTheNextCycles) {
    MainCpuConfig cfg;
    cfg.statement_time = sc_core::sc_time(2, sc_core::SC_US);
    // 1 + 2 x 500 = 1001 statements = 2002 us, plus 100 us: 2.1 ms of work in a 1 ms period.
    CycleRig slow("slow", cfg, loop(500));
    sc_core::sc_start(sc_core::sc_time(10, sc_core::SC_MS));
    EXPECT_DOUBLE_EQ(slow.max_us(), 100.0 + 1001 * 2.0);
    // Each cycle holds the processor for 2.102 ms, so cycle k (k >= 1) starts when cycle k-1
    // ends, at k x 2.102 ms, against the ideal start (2k - 1) ms (main_cpu.cpp cycle_thread: the
    // ideal advances one period per cycle, then past the start with one overrun per skipped
    // period): jitter 1 + 0.102 k ms. In 10 ms: starts 0, 2.102, 4.204, 6.306, 8.408 ms, the last
    // 1.408 ms late; cycles 1-3 ended after the next ideal start: 3 overruns (cycle 4 ends after 10 ms).
    EXPECT_EQ(slow.cpu.control_cycles(), 5u);
    EXPECT_EQ(slow.cpu.cycle_overruns(), 3u);
    EXPECT_NEAR(slow.cpu.cycle_jitter_us().summary().max, 1408.0, 1e-6);
}

/// A program that reports motion block calls: the main CPU charges fb_call for each.
struct BlockCaller : ProgramInterface {
    bool has_program(const std::string&) const override { return true; }
    std::string start(const std::string&) override { return ""; }
    void stop() override {}
    bool running() const override { return true; }
    const std::string& error() const override { return none; }
    ProgramWork cycle(const sc_core::sc_time&) override { return ProgramWork{4, 3}; }
    std::string none;
};

TEST(StCost, EachMotionBlockCallAddsFbCall) {
    MainCpuConfig cfg; // fb_call 5 us
    cfg.statement_time = sc_core::sc_time(2, sc_core::SC_US);
    test::FakeDpram ram{"ram"};
    MainCpu cpu("cpu", cfg);
    cpu.dpram.bind(ram.right);
    cpu.int_r(ram.int_r);
    BlockCaller p;
    cpu.set_program(&p);
    sc_core::sc_start(sc_core::sc_time(3, sc_core::SC_MS));
    // 4 statements x 2 us + 3 calls x 5 us + cycle_time 100 us.
    EXPECT_DOUBLE_EQ(cpu.cycle_duration_us().summary().max, 100.0 + 4 * 2.0 + 3 * 5.0);
    EXPECT_EQ(cpu.program_motion_calls(), 3 * cpu.control_cycles());
}

} // namespace
