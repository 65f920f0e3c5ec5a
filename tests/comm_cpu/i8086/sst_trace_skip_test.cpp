// Without a trace the core takes runs of clocks in which only the BIU counts down in one step
// (Cpu::clks, to_t4, to_last_transfer, wait_queue, an EU bus cycle's T1-T4); with one, every
// clock is simulated and recorded (the path SingleStepTests level 3 checks against the
// hardware). The two must not differ in timing: every test of every shared vector file marked
// normal takes the same clocks and makes the same bus cycles (kind, address, data, width, wait
// states, T1 clock) both ways, with the captures' zero wait states and with 0-3 wait states a
// fixed function of each cycle's address (the Tw arithmetic, which no capture reaches).
// Skipped when the vectors are absent, like the other SingleStepTests checks.
#include "comm_cpu/i8086/sst.h"
#include "tests/support/sc_test.h"

#include <nlohmann/json.hpp>

using namespace rcsim::i8086::sst;
using rcsim::i8086::BusRecord;

namespace {

bool same(const BusRecord& a, const BusRecord& b) {
    return a.kind == b.kind && a.address == b.address && a.data == b.data && a.width == b.width &&
           a.wait_states == b.wait_states && a.start == b.start;
}

// How a test's run without the trace (`off`) differs from the run with it, "" if it does not.
std::string difference(const Runner::Timing& off, const Runner::Timing& on) {
    if (off.cycles != on.cycles)
        return std::to_string(off.cycles) + " clocks without the trace, " + std::to_string(on.cycles) + " with it";
    if (off.bus.size() != on.bus.size())
        return std::to_string(off.bus.size()) + " bus cycles without the trace, " + std::to_string(on.bus.size()) +
               " with it";
    for (std::size_t k = 0; k < off.bus.size(); ++k)
        if (!same(off.bus[k], on.bus[k]))
            return "bus cycle " + std::to_string(k) + " differs (T1 at " + std::to_string(off.bus[k].start) +
                   " without the trace, " + std::to_string(on.bus[k].start) + " with it)";
    return "";
}

// Runs every normal test both ways with `max_waits`; the counts of files and tests seen.
void compare_both_ways(unsigned max_waits, std::size_t& files, std::size_t& tests) {
    const std::string dir = rcsim::test::sst_dir();
    const Metadata meta = Metadata::load(dir + "/metadata.json");
    Runner off, on;
    for (const std::string& path : collect({dir})) {
        const OpcodeInfo info = meta.lookup_file(path);
        if (!info.has("normal")) continue;
        // (a file with a status per ModR/M reg value, 8F, C6, C7: its normal tests)
        const std::vector<rcsim::i8086::sst::Test> list =
            tests_of_status(Runner::convert(nlohmann::json::parse(read_text(path)), path), info, "normal");
        const std::vector<Runner::Timing> a = off.timing_per_test(list, false, max_waits);
        const std::vector<Runner::Timing> b = on.timing_per_test(list, true, max_waits);
        ASSERT_EQ(a.size(), b.size()) << path;
        // (the first difference of a file is reported, not every test after it)
        for (std::size_t i = 0; i < a.size(); ++i) {
            const std::string why = difference(a[i], b[i]);
            if (why.empty()) continue;
            ADD_FAILURE() << path << " test " << i << " (" << list[i].name << "), max_waits " << max_waits << ": "
                          << why;
            break;
        }
        ++files;
        tests += list.size();
    }
}

void expect_both_ways_agree(unsigned max_waits) {
    std::size_t files = 0, tests = 0;
    compare_both_ways(max_waits, files, tests);
    // metadata.json marks 274 files normal, 100 tests each, and /0 of 8F, C6 and C7, whose
    // files hold 13, 4 and 8 such tests (docs/cpu8086.md, "Exactness").
    EXPECT_EQ(files, 277u);
    EXPECT_EQ(tests, 27425u);
}

} // namespace

TEST(SstTraceSkip, TraceOffAndOnGiveTheSameCyclesAndBusCyclesOnEveryNormalFile) {
    if (rcsim::test::sst_dir().empty()) GTEST_SKIP() << "SingleStepTests 8086 vectors not present (set RCSIM_SST_DIR)";
    expect_both_ways_agree(0);
}

TEST(SstTraceSkip, TraceOffAndOnAgreeWithWaitStates) {
    if (rcsim::test::sst_dir().empty()) GTEST_SKIP() << "SingleStepTests 8086 vectors not present (set RCSIM_SST_DIR)";
    expect_both_ways_agree(3);
}
