// The cycle profiler's known-answer test (scenarios/trace/profiler.h): profile_kat.asm on the bare
// 8086 core, named by its nasm map through the symbol table (scenarios/debug/symbols.h).
//
// Expected clocks, from the 8086 instruction timing tables (Intel 8086 Family User's Manual):
//   NOP                 3 clocks. A run of NOPs keeps the queue full (1 byte per 3 clocks used,
//                       2 bytes per 4-clock fetch supplied), so each NOP is exactly 3 clocks.
//   REP STOSB          9 + 10 per byte (CX bytes).
// The clocks a call costs besides its body (the CALL's refetch at the target is the caller's, the
// RET and its refetch at the return address the callee's) are the same for every call made in the
// same bus-interface state, which CALLQ guarantees (full queue, even targets and return
// addresses). So, per call:
//   leaf_b - leaf_a      = (50 - 20) NOPs x 3          =  90 clocks
//   fill(30) - fill(10)  = (30 - 10) bytes x 10        = 200 clocks
// and the identities of the definitions: inclusive = self + the callees' inclusive; an ISR's
// clocks are not the interrupted function's; every clock from the first instruction to the end
// is exactly one function's self clock.
#include "scenarios/debug/symbols.h"
#include "scenarios/trace/flame_graph.h"
#include "scenarios/trace/profiler.h"
#include "tests/comm_cpu/i8086/cpu_board.h"
#include "tests/support/files.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

using namespace rcsim;
using i8086::test::Board;
using Row = trace::CycleProfiler::Row;

namespace {

constexpr std::uint32_t kLoad = 0x10000; // 1000:0000, where Board runs code

struct Kat {
    Board b;
    debug::SymbolTable symbols = debug::SymbolTable::load_nasm_map(RCSIM_TRACE_KAT "/profile_kat.map", kLoad);
    trace::CycleProfiler profile{[this](std::uint32_t a) {
        const debug::Symbol* s = symbols.containing(a);
        return s ? s->name : std::string("?");
    }};
    i8086::cycles_t first = 0;
    bool seen_first = false;
    std::vector<std::pair<std::uint32_t, i8086::cycles_t>> boundaries; // (pc, cycle), independent of the profiler
    std::vector<i8086::cycles_t> inta_t1;                              // T1 of every INTA cycle

    Kat() {
        b.load(test::slurp_bytes(RCSIM_TRACE_KAT "/profile_kat.bin"), kLoad);
        b.set_vector(0x20, offset_of("isr0"), 0x1000);
        b.set_vector(0x21, offset_of("isr1"), 0x1000);
        b.cpu.set_bus_hook(
            [](void* c, const i8086::BusRecord& r) {
                auto* k = static_cast<Kat*>(c);
                if (r.kind == i8086::Bus::int_ack) k->inta_t1.push_back(r.start);
                k->profile.bus(r);
            },
            this);
        b.cpu.set_step_hook(
            [](void* c, const i8086::Cpu& cpu) {
                auto* k = static_cast<Kat*>(c);
                if (!k->seen_first) k->first = cpu.cycles();
                k->seen_first = true;
                k->boundaries.emplace_back(cpu.pc(), cpu.cycles());
                k->profile.step(cpu);
                return false;
            },
            this);
        // IR0 from the start; IR1 when isr0 writes port 80h; each request drops at its INTA.
        b.on_access = [this](const i8086::BusRecord& r) {
            if (r.kind == i8086::Bus::int_ack) b.cpu.set_intr(false);
            if (r.kind == i8086::Bus::io_write && r.address == 0x80) {
                b.vector = 0x21;
                b.cpu.set_intr(true);
            }
        };
        b.cpu.set_intr(true);
        b.cpu.run_until(b.cpu.cycles() + 20000, false);
        profile.finish(b.cpu.cycles());
    }
    std::uint16_t offset_of(const char* name) const {
        return static_cast<std::uint16_t>(symbols.find(name)->address - kLoad);
    }
    Row row(const std::string& fn, const std::string& ctx) const {
        for (const Row& r : profile.rows())
            if (r.function == fn && r.context == ctx) return r;
        ADD_FAILURE() << "no row " << fn << " / " << ctx;
        return Row{};
    }
};

TEST(ProfilerKat, TheProgramRanToItsHlt) {
    Kat k;
    EXPECT_TRUE(k.b.cpu.halted());
    EXPECT_EQ(k.b.pc(), k.symbols.find("outer")->address) << "HLT is the byte before outer";
}

TEST(ProfilerKat, CallsPerFunctionAndContext) {
    Kat k;
    std::map<std::pair<std::string, std::string>, std::uint64_t> calls;
    for (const Row& r : k.profile.rows()) calls[{r.function, r.context}] = r.calls;
    using C = std::map<std::pair<std::string, std::string>, std::uint64_t>;
    EXPECT_EQ(calls, (C{{{"start", "main"}, 0}, // the root: never returns
                        {{"outer", "main"}, 1},
                        {{"leaf_a", "main"}, 2},
                        {{"fill", "main"}, 2},
                        {{"leaf_b", "main"}, 1},
                        {{"isr0", "IR0"}, 1},
                        {{"leaf_a", "IR0"}, 1},
                        {{"isr1", "IR1 nested"}, 1},
                        {{"leaf_b", "IR1 nested"}, 1}}));
}

TEST(ProfilerKat, ClocksPerCallFollowTheTimingTables) {
    Kat k;
    const Row a = k.row("leaf_a", "main"), b = k.row("leaf_b", "main"), fill = k.row("fill", "main");
    EXPECT_EQ(a.min, a.max);
    EXPECT_EQ(b.min - a.min, 30u * 3u) << "30 more NOPs";
    EXPECT_EQ(fill.max - fill.min, 20u * 10u) << "REP STOSB, 20 more bytes";
    EXPECT_DOUBLE_EQ(fill.mean, (fill.min + fill.max) / 2.0);
    // The same function costs the same in an ISR, and in a nested ISR.
    EXPECT_EQ(k.row("leaf_a", "IR0").max, a.max);
    EXPECT_EQ(k.row("leaf_b", "IR1 nested").max, b.max);
    // Leaves: inclusive = self; the root's calls are still open at the end.
    EXPECT_EQ(a.inclusive, a.self);
    EXPECT_EQ(a.inclusive, 2 * a.max);
}

TEST(ProfilerKat, InclusiveIsSelfPlusCalleesWithoutInterrupts) {
    Kat k;
    const Row outer = k.row("outer", "main"), start = k.row("start", "main");
    const Row isr0 = k.row("isr0", "IR0"), isr1 = k.row("isr1", "IR1 nested");
    // outer was interrupted (IR0 right after its CALL, IR1 nested in that): not in its clocks.
    EXPECT_EQ(outer.inclusive, outer.self + k.row("leaf_a", "main").inclusive);
    EXPECT_EQ(outer.max, outer.inclusive);
    EXPECT_EQ(isr0.inclusive, isr0.self + k.row("leaf_a", "IR0").inclusive) << "isr1 came in: not isr0's";
    EXPECT_EQ(isr1.inclusive, isr1.self + k.row("leaf_b", "IR1 nested").inclusive);
    EXPECT_EQ(start.inclusive, start.self + outer.inclusive + k.row("fill", "main").inclusive +
                                   k.row("leaf_b", "main").inclusive);
    // Every clock from the first instruction to the end is one function's self clock, and the
    // main program's and the ISRs' inclusive clocks share them out.
    std::uint64_t self = 0;
    for (const Row& r : k.profile.rows()) self += r.self;
    EXPECT_EQ(self, k.b.cpu.cycles() - k.first);
    EXPECT_EQ(k.profile.total_clocks(), self);
    EXPECT_EQ(start.inclusive + isr0.inclusive + isr1.inclusive, self);
}

TEST(ProfilerKat, AnIsrsClocksStartAtItsFirstIntaCycle) {
    Kat k;
    // isr1 runs once, from the third INTA cycle (IR1's first) on; its own instructions are those
    // from its entry up to (not into) its call of leaf_b, and its IRET.
    ASSERT_EQ(k.inta_t1.size(), 4u) << "two interrupts, two INTA cycles each";
    const std::uint32_t isr1 = k.symbols.find("isr1")->address;
    std::uint64_t own = 0;
    for (std::size_t i = 0; i + 1 < k.boundaries.size(); ++i)
        if (k.boundaries[i].first >= isr1) own += k.boundaries[i + 1].second - k.boundaries[i].second;
    auto entry = std::find_if(k.boundaries.begin(), k.boundaries.end(), [&](const auto& b) { return b.first == isr1; });
    ASSERT_NE(entry, k.boundaries.end());
    EXPECT_EQ(k.row("isr1", "IR1 nested").self, own + (entry->second - k.inta_t1[2]));
}

TEST(ProfilerKat, FoldedStacksAreTheCallPathsWithTheirSelfClocks) {
    Kat k;
    std::ostringstream os;
    k.profile.write_folded(os);
    std::map<std::string, std::uint64_t> folded;
    std::istringstream in(os.str());
    std::string line;
    std::uint64_t sum = 0;
    while (std::getline(in, line)) {
        const auto sp = line.rfind(' ');
        folded[line.substr(0, sp)] = std::stoull(line.substr(sp + 1));
        sum += std::stoull(line.substr(sp + 1));
    }
    std::map<std::string, std::uint64_t> paths;
    for (const auto& [p, n] : folded) paths[p] = 0;
    EXPECT_EQ(paths, (std::map<std::string, std::uint64_t>{{"main;start", 0}, {"main;start;outer", 0},
                                                           {"main;start;outer;leaf_a", 0}, {"main;start;fill", 0},
                                                           {"main;start;leaf_b", 0}, {"IR0;isr0", 0},
                                                           {"IR0;isr0;leaf_a", 0}, {"IR1_nested;isr1", 0},
                                                           {"IR1_nested;isr1;leaf_b", 0}}));
    EXPECT_EQ(folded["main;start;outer;leaf_a"], k.row("leaf_a", "main").self);
    EXPECT_EQ(folded["IR1_nested;isr1;leaf_b"], k.row("leaf_b", "IR1 nested").self);
    EXPECT_EQ(sum, k.profile.total_clocks());
}

TEST(ProfilerKat, TheTableIsSortedBySelfClocks) {
    Kat k;
    std::ostringstream os;
    k.profile.write_table(os, 8e6);
    const std::string t = os.str();
    const auto rows = k.profile.rows();
    for (std::size_t i = 1; i < rows.size(); ++i) EXPECT_GE(rows[i - 1].self, rows[i].self);
    // The first data row (after the 4 comment lines and the heading) is the biggest self.
    std::istringstream in(t);
    std::string line;
    for (int i = 0; i < 5; ++i) std::getline(in, line);
    std::getline(in, line);
    EXPECT_EQ(line.rfind(rows[0].function, 0), 0u) << line;
    EXPECT_NE(t.find(std::to_string(k.profile.total_clocks()) + " clocks"), std::string::npos);
}

TEST(ProfilerKat, TheFlameGraphHasABoxPerPathAsWideAsItsClocks) {
    Kat k;
    const std::string svg = trace::flame_graph_svg(k.profile, 8e6, 1100);
    // Plot width 1100 - 2 x 10 px margins over all clocks.
    const double px = 1080.0 / static_cast<double>(k.profile.total_clocks());
    const std::uint64_t fill = k.row("fill", "main").inclusive;
    const auto at = svg.find("<title>main &gt; start &gt; fill: " + std::to_string(fill) + " clocks");
    ASSERT_NE(at, std::string::npos) << svg;
    const auto rect = svg.rfind("<rect", at);
    const auto w = svg.find("width=\"", rect) + 7;
    EXPECT_NEAR(std::stod(svg.substr(w)), static_cast<double>(fill) * px, 0.05);
    for (const char* path : {"IR0 &gt; isr0 &gt; leaf_a", "IR1 nested &gt; isr1 &gt; leaf_b", "main &gt; start &gt; outer &gt; leaf_a"})
        EXPECT_NE(svg.find("<title>" + std::string(path) + ":"), std::string::npos) << path;
}

} // namespace
