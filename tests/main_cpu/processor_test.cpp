// Tests of the single-processor arbitration of the main CPU's activities.
#include "main_cpu/processor.h"
#include "models/clock.h"
#include "tests/support/sc_test.h"

#include <string>
#include <vector>

using namespace rcsim;
using sc_core::sc_time;

namespace {

/// Activities sharing one processor: each asks for it at `at`, notes when it got it, holds it for
/// `hold` and releases it.
struct Activities : sc_core::sc_module {
    Processor cpu{"cpu"};
    std::vector<std::pair<std::string, sc_time>> starts;

    using sc_module::sc_module;
    void run(Processor::Priority p, const char* who, sc_time at, sc_time hold) {
        wait(at);
        cpu.acquire(p);
        starts.emplace_back(who, sc_core::sc_time_stamp());
        wait(hold);
        cpu.release();
    }
};

/// Three activities: "a" holds the processor 0..10 us; "low" and "high" ask for it at 2 us and
/// 3 us; the high-priority one must get it first although it asked later.
struct Contenders : Activities {
    explicit Contenders(sc_core::sc_module_name n) : Activities(n) {
        test::spawn_checked([this] { holder(); }, "holder");
        test::spawn_checked([this] { low(); }, "low");
        test::spawn_checked([this] { high(); }, "high");
        test::spawn_checked([this] { low2(); }, "low2");
    }
    void holder() { run(Processor::Priority::interrupt, "holder", sc_core::SC_ZERO_TIME, us(10)); }
    void low() { run(Processor::Priority::transmit, "low", us(2), us(5)); }
    void low2() { run(Processor::Priority::transmit, "low2", us(4), us(5)); }
    void high() { run(Processor::Priority::control_cycle, "high", us(3), us(5)); }
};

} // namespace

TEST(Processor, HighestPriorityWaiterGetsItThenFirstComeAmongEquals) {
    Contenders c("c");
    sc_core::sc_start(us(100));
    ASSERT_EQ(c.starts.size(), 4u);
    EXPECT_EQ(c.starts[0], std::make_pair(std::string("holder"), us(0)));
    EXPECT_EQ(c.starts[1], std::make_pair(std::string("high"), us(10)));
    EXPECT_EQ(c.starts[2], std::make_pair(std::string("low"), us(15)));
    EXPECT_EQ(c.starts[3], std::make_pair(std::string("low2"), us(20)));
    // Busy without a gap from 0 to 25 us.
    EXPECT_EQ(c.cpu.busy_time(), us(25));
    EXPECT_FALSE(c.cpu.busy());
}

namespace {

/// The processor is released and asked for at the same instant (10 us) by two activities of
/// different priority. The kernel runs processes woken at one instant in an order of its own
/// (it follows the other events of that instant, e.g. how often the comm CPU synchronised), so the
/// contenders are spawned in either order: the control cycle must win both times.
struct SameInstant : Activities {
    SameInstant(sc_core::sc_module_name n, bool transmit_first) : Activities(n) {
        test::spawn_checked([this] { run(Processor::Priority::interrupt, "holder", us(0), us(10)); }, "holder");
        auto transmit = [this] { run(Processor::Priority::transmit, "transmit", us(10), us(5)); };
        auto cycle = [this] { run(Processor::Priority::control_cycle, "cycle", us(10), us(5)); };
        if (transmit_first) {
            test::spawn_checked(transmit, "transmit");
            test::spawn_checked(cycle, "cycle");
        } else {
            test::spawn_checked(cycle, "cycle");
            test::spawn_checked(transmit, "transmit");
        }
    }
};

void expect_cycle_first(SameInstant& c) {
    sc_core::sc_start(us(100));
    ASSERT_EQ(c.starts.size(), 3u);
    EXPECT_EQ(c.starts[0], std::make_pair(std::string("holder"), us(0)));
    EXPECT_EQ(c.starts[1], std::make_pair(std::string("cycle"), us(10)));
    EXPECT_EQ(c.starts[2], std::make_pair(std::string("transmit"), us(15)));
    EXPECT_EQ(c.cpu.busy_time(), us(20));
}

} // namespace

TEST(Processor, AtOneInstantPriorityDecidesWhateverTheKernelOrderTransmitFirst) {
    SameInstant c("c", true);
    expect_cycle_first(c);
}

TEST(Processor, AtOneInstantPriorityDecidesWhateverTheKernelOrderCycleFirst) {
    SameInstant c("c", false);
    expect_cycle_first(c);
}
