// The idle-clock skip (Cpu::clks jumps over idle clocks when no trace is recorded) must not change
// timing: every test of every shared vector file marked normal takes the same number of cycles
// with the per-cycle trace off (skip taken) and on (every clock simulated). Skipped when the
// vectors are absent, like the other SingleStepTests checks.
#include "comm_cpu/sst.h"
#include "tests/support/sc_test.h"

#include <nlohmann/json.hpp>


using namespace rcsim::i8086::sst;

TEST(SstTraceSkip, TraceOffAndOnGiveTheSameCyclesOnEveryNormalFile) {
    const std::string dir = rcsim::test::sst_dir();
    if (dir.empty()) GTEST_SKIP() << "SingleStepTests 8086 vectors not present (set RCSIM_SST_DIR)";
    const Metadata meta = Metadata::load(dir + "/metadata.json");
    Runner off, on;
    std::size_t files = 0, tests = 0;
    for (const std::string& path : collect({dir})) {
        const OpcodeInfo info = meta.lookup_file(path);
        if (!info.has("normal")) continue;
        // (a file with a status per ModR/M reg value, 8F, C6, C7: its normal tests)
        const std::vector<rcsim::i8086::sst::Test> list =
            tests_of_status(Runner::convert(nlohmann::json::parse(read_text(path)), path), info, "normal");
        const std::vector<std::uint64_t> a = off.cycles_per_test(list, false);
        const std::vector<std::uint64_t> b = on.cycles_per_test(list, true);
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t i = 0; i < a.size(); ++i)
            EXPECT_EQ(a[i], b[i]) << path << " test " << i << " (" << list[i].name << ")";
        ++files;
        tests += list.size();
    }
    // metadata.json marks 274 files normal, 100 tests each, and /0 of 8F, C6 and C7, whose
    // files hold 13, 4 and 8 such tests (docs/cpu8086.md, "Exactness").
    EXPECT_EQ(files, 277u);
    EXPECT_EQ(tests, 27425u);
}
