// Coverage's branch records against their definition (scenarios/coverage/counters.h): a
// conditional jump is taken when the next instruction executed is its target. Counters decides it
// from the flags and CX at the jump; here an oracle decides it from consecutive instruction
// boundaries alone, on branch_oracle.asm (every conditional jump under every combination of the
// flags it tests, no interrupts), and the two must agree at every jump.
#include "scenarios/coverage/counters.h"
#include "tests/comm_cpu/i8086/cpu_board.h"
#include "tests/support/files.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <map>

using namespace rcsim;
using i8086::test::Board;

TEST(BranchOracle, TakenIsTheNextInstructionBeingTheTarget) {
    constexpr std::uint32_t kLoad = 0x10000; // 1000:0000, where Board runs code
    const std::vector<std::uint8_t> code = test::slurp_bytes(RCSIM_COVERAGE_ORACLE_BIN);
    ASSERT_FALSE(code.empty());
    Board b;
    b.load(code, kLoad);
    struct Seen {
        coverage::Counters counters;
        std::vector<std::uint32_t> pcs;
        std::vector<bool> counted_taken; // per boundary: Counters counted a taken jump there
    } seen{coverage::Counters(kLoad, code), {}, {}};
    b.cpu.set_step_hook(
        [](void* c, const i8086::Cpu& cpu) {
            auto* s = static_cast<Seen*>(c);
            const std::uint64_t before = s->counters.taken(cpu.pc());
            s->counters.step(cpu);
            s->pcs.push_back(cpu.pc());
            s->counted_taken.push_back(s->counters.taken(cpu.pc()) > before);
            return false;
        },
        &seen);
    b.cpu.run_until(b.cpu.cycles() + 2'000'000, false);
    ASSERT_TRUE(b.cpu.halted());

    // The oracle: per jump, (taken, not taken) from the boundary after it.
    std::map<std::uint32_t, std::pair<std::uint64_t, std::uint64_t>> oracle;
    for (std::size_t i = 0; i + 1 < seen.pcs.size(); ++i) {
        const std::uint32_t at = seen.pcs[i];
        const std::uint8_t op = code[at - kLoad];
        if (!((op >= 0x70 && op <= 0x7F) || (op >= 0xE0 && op <= 0xE3))) continue;
        const std::uint32_t target = at + 2 + static_cast<std::int8_t>(code[at - kLoad + 1]);
        ASSERT_NE(target, at + 2);
        const bool taken = seen.pcs[i + 1] == target;
        if (taken) ++oracle[at].first;
        else if (seen.pcs[i + 1] == at + 2) ++oracle[at].second;
        else FAIL() << std::hex << "the instruction after the jump at " << at << " is neither way: " << seen.pcs[i + 1];
        // Each execution, not only the totals: a condition and its negation give the same totals
        // over every combination of the flags.
        ASSERT_EQ(seen.counted_taken[i], taken) << std::hex << "opcode " << int(op) << " at " << at << ", execution " << std::dec
                                                << oracle[at].first + oracle[at].second;
    }
    ASSERT_EQ(oracle.size(), 16u + 4u + 1u) << "16 Jcc, the LOOPs and JCXZ, and the program's own jb";
    for (const auto& [at, ways] : oracle) { printf("%x op %x oracle %llu/%llu counters %llu/%llu\n", at, code[at-kLoad], (unsigned long long)ways.first, (unsigned long long)ways.second, (unsigned long long)seen.counters.taken(at), (unsigned long long)seen.counters.not_taken(at));
        EXPECT_EQ(seen.counters.taken(at), ways.first) << std::hex << "at " << at;
        EXPECT_EQ(seen.counters.not_taken(at), ways.second) << std::hex << "at " << at;
        if (code[at - kLoad] != 0x72) { // the loop's jb: taken 63 times, not taken once
            EXPECT_GT(ways.first, 0u) << std::hex << "opcode " << int(code[at - kLoad]) << " never taken";
            EXPECT_GT(ways.second, 0u) << std::hex << "opcode " << int(code[at - kLoad]) << " never not taken";
        }
    }
}
