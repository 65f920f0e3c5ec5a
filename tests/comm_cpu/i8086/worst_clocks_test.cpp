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

// Known answers: the iAPX 86/88 User's Manual's clock table gives each form's clocks without
// wait states (a range where the time depends on the operands: the bound is at least its top);
// every wait state of a bus cycle the form must run adds one clock.
TEST(WorstClocks, AtLeastTheDatasheetFigures) {
    WorstClocks w(WaitBounds{0, 0, 0, 0});
    EXPECT_GE(bound(w, {0x8A, 0xC3}), 2u);             // MOV AL,BL: 2
    EXPECT_GE(bound(w, {0xF7, 0xE3}), 133u);           // MUL BX: 118-133
    EXPECT_GE(bound(w, {0xF6, 0xE3}), 77u);            // MUL BL: 70-77
    EXPECT_GE(bound(w, {0xF7, 0xEB}), 154u);           // IMUL BX: 128-154
    EXPECT_GE(bound(w, {0xF7, 0xF3}), 162u);           // DIV BX: 144-162
    EXPECT_GE(bound(w, {0xF6, 0xF3}), 90u);            // DIV BL: 80-90
    EXPECT_GE(bound(w, {0xF7, 0xFB}), 184u);           // IDIV BX: 165-184
    EXPECT_GE(bound(w, {0xD4, 0x0A}), 83u);            // AAM: 83
    EXPECT_GE(bound(w, {0xE4, 0x60}), 10u);            // IN AL,60h: 10
    EXPECT_GE(bound(w, {0xD3, 0xE0}, 10), 8u + 4 * 10); // SHL AX,CL: 8 + 4/bit, CL up to 10
    EXPECT_GE(bound(w, {0xE2, 0xFE}), 17u);            // LOOP: 17 taken, 5 not
    EXPECT_GE(bound(w, {0x74, 0x10}), 16u);            // JZ: 16 taken, 4 not
    EXPECT_GE(bound(w, {0xCD, 0x21}), 51u);            // INT 21h: 51
    EXPECT_GE(bound(w, {0xF3, 0xA5}, 100), 9u + 17 * 100); // REP MOVSW: 9 + 17/rep, CX up to 100
    EXPECT_GE(w.interrupt_entry(), 61u);               // INTR: 61 (two INTA cycles and the entry)
}

TEST(WorstClocks, TheCountsAndShiftsGrowWithCxMax) {
    WorstClocks w(WaitBounds{0, 0, 0, 0});
    // 17 clocks per MOVSW element, 4 per bit shifted: more CX, more time by at least those.
    EXPECT_GE(bound(w, {0xF3, 0xA5}, 200), bound(w, {0xF3, 0xA5}, 100) + 17 * 100);
    EXPECT_GE(bound(w, {0xD3, 0xE0}, 20), bound(w, {0xD3, 0xE0}, 10) + 4 * 10);
    // A shift counts CL alone: a CX above 255 allows CL = 255 and no more.
    EXPECT_EQ(bound(w, {0xD3, 0xE0}, 0x1234), bound(w, {0xD3, 0xE0}, 255));
    // Without REP the count is not CX's.
    EXPECT_EQ(bound(w, {0xA5}, 0), bound(w, {0xA5}, 0xFFFF));
}

TEST(WorstClocks, EachWaitStateRaisesTheBoundOfTheCyclesItHolds) {
    WorstClocks none(WaitBounds{0, 0, 0, 0}), io(WaitBounds{0, 0, 1, 0}), data(WaitBounds{0, 1, 0, 0}),
        code(WaitBounds{1, 0, 0, 0}), inta(WaitBounds{0, 0, 0, 1});
    // IN AL,60h: one I/O read, so one clock per I/O wait state (10 + 1 with one).
    EXPECT_GE(bound(io, {0xE4, 0x60}), 11u);
    EXPECT_GE(bound(io, {0xE4, 0x60}), bound(none, {0xE4, 0x60}) + 1);
    // MOV [BX],AX: one or two data writes (odd address): one more clock at least.
    EXPECT_GE(bound(data, {0x89, 0x07}), bound(none, {0x89, 0x07}) + 1);
    // REP MOVSW with 100 words: a read and a write each, every one a wait state later.
    EXPECT_GE(bound(data, {0xF3, 0xA5}, 100), bound(none, {0xF3, 0xA5}, 100) + 2 * 100);
    // A far jump refetches its target: a code wait state shows.
    EXPECT_GT(bound(code, {0xEA, 0x00, 0x01, 0x00, 0x20}), bound(none, {0xEA, 0x00, 0x01, 0x00, 0x20}));
    // The entry: two INTA cycles, so two clocks at least.
    EXPECT_GE(inta.interrupt_entry(), none.interrupt_entry() + 2);
    EXPECT_GE(data.interrupt_entry(), none.interrupt_entry() + 5); // 3 pushes, 2 vector reads
}

TEST(WorstClocks, OperandValuesAlignmentAndFlagsAreTakenAtTheirWorst) {
    WorstClocks w(WaitBounds{0, 0, 0, 0});
    // CWD takes a clock more for a negative AX (the vectors show 5 and 6).
    EXPECT_GE(bound(w, {0x99}), 6u);
    // A word at an odd address takes two bus cycles: MOV AX,[BX] and PUSH are bounded as if odd,
    // so at least a bus cycle (4 clocks) above a byte access of the same form.
    EXPECT_GE(bound(w, {0x8B, 0x07}), bound(w, {0x8A, 0x07}) + 4);
    // A taken conditional jump is the worst of the two: as JMP short at the least.
    EXPECT_GE(bound(w, {0x7F, 0x10}), bound(w, {0xEB, 0x10}));
    // The cache answers by bytes, IP parity and cx_max: the same question, the same answer.
    EXPECT_EQ(bound(w, {0xEB, 0x10}, 0, 0x100), bound(w, {0xEB, 0x10}, 0, 0x200));
}

TEST(WorstClocks, ARunThatDividesByZeroIsNotTheInstructionsTime) {
    // With 10 wait states per data cycle the divide error's entry (two vector reads, three
    // pushes: 50 clocks of waits) is far longer than any DIV BL that completes (no data cycle:
    // 80-90 clocks). DIV AH always faults (AH / AH does not fit): its bound is what the fault
    // takes, the only time it has. DIV BL faults for BL = 0 but its bound leaves those runs out.
    WorstClocks w(WaitBounds{0, 10, 0, 0});
    const unsigned fault_only = bound(w, {0xF6, 0xF4});
    EXPECT_GE(fault_only, 90u + 5 * 10);
    EXPECT_LT(bound(w, {0xF6, 0xF3}), 90u + 5 * 10);
    EXPECT_GE(bound(w, {0xF6, 0xF3}), 90u);
}
