// The per-instruction worst clocks (comm_cpu/i8086/worst_clocks.h): no hardware-captured
// SingleStepTests vector takes more clocks than the bound of its bytes at its IP with its CX,
// and the bounds hold the iAPX 86/88 User's Manual's clock figures (Intel 231455's table),
// plus what the wait states add.
#include "comm_cpu/i8086/sst.h"
#include "comm_cpu/i8086/worst_clocks.h"
#include "tests/support/sc_test.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <iostream>
#include <string>
#include <vector>

using rcsim::i8086::WaitBounds;
using rcsim::i8086::WorstClocks;

namespace {

unsigned bound(WorstClocks& w, std::vector<std::uint8_t> b, std::uint32_t cx_max = 0xFFFF, std::uint16_t ip = 0x100) {
    return w.instruction(b.data(), static_cast<unsigned>(b.size()), ip, cx_max);
}

// The files are dealt to kShards ctest entries (file index modulo kShards) so CI's two cores
// share them.
constexpr unsigned kShards = 4;

// Whether a run of the vector read the divide error's vector (00000-00003) on our core, which
// reproduces the capture's cycles: such a run is not a time of the instruction (worst_clocks.h).
bool divide_error(const rcsim::i8086::sst::Runner::Timing& t) {
    for (const rcsim::i8086::BusRecord& r : t.bus)
        if (r.kind == rcsim::i8086::Bus::mem_read && r.address < 4) return true;
    return false;
}

class WorstClocksVectors : public ::testing::TestWithParam<unsigned> {};

} // namespace

TEST_P(WorstClocksVectors, NoVectorTakesMoreThanItsBound) {
    using namespace rcsim::i8086::sst;
    const std::string dir = rcsim::test::sst_dir();
    if (dir.empty()) GTEST_SKIP() << "SingleStepTests 8086 vectors not present (set RCSIM_SST_DIR)";
    WorstClocks worst(WaitBounds{0, 0, 0, 0});
    Runner runner;
    const std::vector<std::string> files = collect({dir});
    std::size_t checked = 0, over = 0;
    double tightest = 0;
    std::string tightest_at, first_over;
    for (std::size_t f = GetParam(); f < files.size(); f += kShards) {
        const std::string& path = files[f];
        const nlohmann::json all = nlohmann::json::parse(read_text(path));
        const std::vector<rcsim::i8086::sst::Test> tests = Runner::convert(all, path);
        // (only DIV/IDIV and AAM can divide by zero; INT 0 reads the same vector on purpose)
        const std::string stem = path.substr(path.find_last_of('/') + 1);
        const bool divides = stem.rfind("F6.6", 0) == 0 || stem.rfind("F6.7", 0) == 0 ||
                             stem.rfind("F7.6", 0) == 0 || stem.rfind("F7.7", 0) == 0 || stem.rfind("D4", 0) == 0;
        const std::vector<Runner::Timing> ours = runner.timing_per_test(tests, false);
        for (std::size_t i = 0; i < tests.size(); ++i) {
            if (divides && divide_error(ours[i])) continue;
            const std::vector<std::uint8_t> b = all[i].at("bytes").get<std::vector<std::uint8_t>>();
            const unsigned captured = static_cast<unsigned>(tests[i].cycles->size());
            const unsigned limit = bound(worst, b, tests[i].init.r[rcsim::i8086::CX], tests[i].init.ip);
            ++checked;
            const double ratio = double(captured) / limit;
            if (ratio > tightest) {
                tightest = ratio;
                tightest_at = stem + " " + tests[i].name;
            }
            if (captured > limit && over++ == 0)
                first_over = stem + " test " + std::to_string(i) + " (" + tests[i].name + "): " +
                             std::to_string(captured) + " clocks, bound " + std::to_string(limit);
        }
    }
    EXPECT_EQ(over, 0u) << "first: " << first_over << "; worst ratio " << tightest << " at " << tightest_at;
    EXPECT_GT(checked, 7500u); // ~80 files of 100 vectors each per shard (less the divide errors)
    std::cout << "shard " << GetParam() << ": " << checked << " vectors, worst ratio captured/bound " << tightest
              << " (" << tightest_at << ")\n";
}

INSTANTIATE_TEST_SUITE_P(Shards, WorstClocksVectors, ::testing::Range(0u, kShards));
