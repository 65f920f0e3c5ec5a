// The per-instruction worst clocks (comm_cpu/i8086/worst_clocks.h) against the shipped firmware
// as the board runs it: every instruction of a shortened run of the default scenario and of the
// BREAK case takes no more clocks than WorstClocks gives its bytes with the board's wait states
// and CX at its boundary, every interrupt entry no more than interrupt_entry(), and every straight
// line of 2..12 consecutive instructions (no interrupt entry inside, none a form sequence() leaves
// to instruction()) no more than sequence() gives it. The lines of 1..12 that end in a conditional
// transfer take no more than branch() gives the outcome the run took (the next boundary's
// address says which), and those that end in a return or IRET no more than sequence().
#include "comm_cpu/i8086/disasm.h"
#include "comm_cpu/i8086/worst_clocks.h"
#include "scenarios/config/scenario.h"
#include "scenarios/run/runner.h"
#include "scenarios/world/world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <deque>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

using namespace rcsim;

namespace {

/// The longest straight line checked against sequence().
constexpr std::size_t kLongestLine = 12;

/// The windows of one kind checked against their bound: how many, how many over, the tightest.
struct Tally {
    std::size_t count = 0, over = 0;
    double tightest = 0;
    std::string tightest_at, first_over;

    void add(unsigned clocks, unsigned limit, std::size_t n, std::uint16_t ip) {
        ++count;
        char where[96];
        std::snprintf(where, sizeof where, "%zu instructions from IP %04X: %u clocks, bound %u", n, ip, clocks, limit);
        const double ratio = double(clocks) / limit;
        if (ratio > tightest) {
            tightest = ratio;
            tightest_at = where;
        }
        if (clocks > limit && over++ == 0) first_over = where;
    }
};

/// One executed instruction of the current straight line.
struct Done {
    std::array<std::uint8_t, 16> bytes;
    unsigned length;
    std::uint16_t ip;
    i8086::cycles_t start, end;
};

// Measures each instruction between successive boundaries of the step hook (set without a
// SkipHook: the fast-forward is off, every boundary is seen), and each straight line of the
// last 2..kLongestLine of them.
struct Meter {
    explicit Meter(const i8086::WaitBounds& w) : worst(w) {}
    i8086::WorstClocks worst;
    i8086::StepHook chained = nullptr; // an observer the world had installed before
    void* chained_ctx = nullptr;
    bool have = false;
    i8086::cycles_t at = 0; // the previous boundary ...
    std::uint8_t bytes[16] = {};
    unsigned length = 0;
    std::uint16_t ip = 0, cx = 0;
    std::size_t checked = 0, entries = 0, over = 0;
    double tightest = 0, tightest_entry = 0;
    std::string tightest_at, first_over;
    std::deque<Done> line; // the straight line the last instruction ends
    std::size_t lines = 0, lines_over = 0;
    double tightest_line = 0;
    std::string tightest_line_at, first_line_over;
    // 8-instruction lines: their sequence() bounds and the sums of their instructions' bounds
    double eight_sequence = 0, eight_sum = 0, eight_taken = 0;
    // Lines that end in a conditional transfer, by the outcome the run took, and in a return;
    // the taken ones against the not-taken bound (the check can fail: the outcome matters).
    Tally taken, not_taken, returns;
    std::size_t taken_over_not = 0;
    // Two-instruction lines ending in a conditional transfer (CMP; Jcc): their outcome's bound
    // and the sum of the two instructions' bounds, per outcome.
    double pair_bound[2] = {}, pair_sum[2] = {};
    std::size_t pairs[2] = {};

    /// Checks every line of 1..kLongestLine instructions that ends with `last`, a conditional
    /// transfer (`outcome` 1 taken, 0 not taken) or a return (`outcome` -1).
    void check_ending(const Done& last, int outcome) {
        std::vector<i8086::Piece> pieces{i8086::Piece{last.bytes.data(), last.length, last.ip}};
        unsigned sum = worst.instruction(last.bytes.data(), last.length, last.ip);
        for (std::size_t k = line.size() + 1; k-- > 0 && pieces.size() <= kLongestLine;) {
            if (k < line.size()) {
                const Done& d = line[k];
                pieces.insert(pieces.begin(), i8086::Piece{d.bytes.data(), d.length, d.ip});
                sum += worst.instruction(d.bytes.data(), d.length, d.ip);
            }
            const Done& first = k < line.size() ? line[k] : last;
            const unsigned clocks = unsigned(last.end - first.start);
            if (outcome < 0) {
                returns.add(clocks, worst.sequence(pieces), pieces.size(), first.ip);
                continue;
            }
            const i8086::Outcomes o = worst.branch(pieces);
            (outcome ? taken : not_taken).add(clocks, outcome ? o.taken : o.not_taken, pieces.size(), first.ip);
            if (outcome && clocks > o.not_taken) ++taken_over_not;
            if (pieces.size() == 2) {
                pair_bound[outcome] += outcome ? o.taken : o.not_taken;
                pair_sum[outcome] += sum;
                ++pairs[outcome];
            }
        }
    }

    /// Checks every line of 2..kLongestLine instructions that ends with the one just done.
    void check_lines() {
        std::vector<i8086::Piece> pieces;
        unsigned sum = 0;
        for (std::size_t k = line.size(); k-- > 0;) { // (from the last back: lines of 1, 2, ...)
            const Done& d = line[k];
            pieces.insert(pieces.begin(), i8086::Piece{d.bytes.data(), d.length, d.ip});
            sum += worst.instruction(d.bytes.data(), d.length, d.ip);
            if (pieces.size() < 2) continue;
            const unsigned clocks = unsigned(line.back().end - d.start), limit = worst.sequence(pieces);
            ++lines;
            if (pieces.size() == 8) {
                eight_sequence += limit;
                eight_sum += sum;
                eight_taken += clocks;
            }
            const double ratio = double(clocks) / limit;
            if (ratio > tightest_line) {
                tightest_line = ratio;
                char where[64];
                std::snprintf(where, sizeof where, "%zu instructions from IP %04X", pieces.size(), d.ip);
                tightest_line_at = where;
            }
            if (clocks > limit && lines_over++ == 0) {
                char where[96];
                std::snprintf(where, sizeof where, "%zu instructions from IP %04X: %u clocks, bound %u", pieces.size(),
                              d.ip, clocks, limit);
                first_line_over = where;
            }
        }
    }

    void check(unsigned clocks, unsigned limit, const std::string& what) {
        const double ratio = double(clocks) / limit;
        if (ratio > tightest) {
            tightest = ratio;
            tightest_at = what;
        }
        if (clocks > limit && over++ == 0)
            first_over = what + ": " + std::to_string(clocks) + " clocks, bound " + std::to_string(limit);
    }

    void boundary(const i8086::Cpu& cpu) {
        const i8086::cycles_t now = cpu.cycles();
        bool entry_followed = false;
        if (have && !(length && bytes[0] == 0xF4) && !cpu.interrupt_from_halt()) { // (HLT waits)
            i8086::cycles_t end = now;
            if (cpu.interrupt_boundary() > at) { // an interrupt entry followed the instruction
                entry_followed = true;
                end = cpu.interrupt_boundary();
                const unsigned entry = unsigned(now - end), limit = worst.interrupt_entry();
                ++entries;
                tightest_entry = std::max(tightest_entry, double(entry) / limit);
                if (entry > limit && over++ == 0)
                    first_over = "interrupt entry: " + std::to_string(entry) + " clocks, bound " + std::to_string(limit);
            }
            ++checked;
            char where[48];
            std::snprintf(where, sizeof where, "IP %04X bytes %02X %02X %02X CX %u", ip, bytes[0], bytes[1], bytes[2], cx);
            check(unsigned(end - at), worst.instruction(bytes, length, ip, cx), where);
            Done d{{}, length, ip, at, end};
            std::copy(bytes, bytes + length, d.bytes.begin());
            const i8086::Decoded dec = i8086::decode(bytes, length);
            if (i8086::WorstClocks::sequenceable(bytes, length, ip)) {
                line.push_back(d);
                if (line.size() > kLongestLine) line.pop_front();
                check_lines();
            } else {
                if (dec.flow == i8086::Flow::branch && !entry_followed) {
                    // (the outcome from where the run went: the boundary's IP is the next instruction's)
                    const std::uint16_t target = i8086::direct_target(bytes, dec, ip)->ip;
                    if (target != std::uint16_t(ip + dec.length)) check_ending(d, cpu.regs().ip == target ? 1 : 0);
                } else if (dec.flow == i8086::Flow::ret_near || dec.flow == i8086::Flow::ret_far ||
                           dec.flow == i8086::Flow::iret) {
                    check_ending(d, -1);
                }
                line.clear();
            }
        } else {
            line.clear();
        }
        if (entry_followed) line.clear(); // (the next instruction is the handler's)
        // The next instruction: its bytes from the memory it runs from (the ROM).
        have = false;
        const std::uint32_t pc = cpu.pc();
        const MemRegion* r = cpu.memory().find(pc);
        if (!r) return;
        length = 0;
        while (length < sizeof bytes && r->contains(pc + length)) {
            bytes[length] = r->data[pc + length - r->base];
            ++length;
        }
        unsigned n = 0; // (prefixes, then the longest instruction)
        while (n < length && (bytes[n] & 0xE7) == 0x26) ++n;
        while (n < length && (bytes[n] == 0xF0 || bytes[n] == 0xF1 || bytes[n] == 0xF2 || bytes[n] == 0xF3)) ++n;
        length = std::min<unsigned>(length, n + 6);
        ip = cpu.regs().ip;
        cx = cpu.regs().r[i8086::CX];
        at = now;
        have = true;
    }

    static bool hook(void* self, const i8086::Cpu& cpu) {
        auto* m = static_cast<Meter*>(self);
        m->boundary(cpu);
        return m->chained ? m->chained(m->chained_ctx, cpu) : false;
    }
};

/// Runs `file` shortened to `duration_s` with a Meter whose bounds take the board's wait states
/// (or `waits` when given) and returns it.
std::unique_ptr<Meter> measured(const std::string& file, double duration_s, const i8086::WaitBounds* given = nullptr) {
    Scenario s = load_scenario(std::string(RCSIM_SOURCE_DIR) + "/" + file);
    s.duration_s = duration_s;
    s.drain_s = 0.01;
    const CommBoardConfig& c = s.board.comm;
    // Data: the worst region a memory cycle can reach (ROM, RAM, DP-RAM; BUSY adds none at the
    // defaults); INTA: the 8259A inserts none.
    const i8086::WaitBounds waits{c.rom_wait, std::max({c.ram_wait, c.rom_wait, c.dpram_wait}), c.io_wait, 0};
    auto meter = std::make_unique<Meter>(given ? *given : waits);
    RunOptions opt;
    opt.reproducible = true;
    opt.on_world = [&meter](World& w) {
        auto [hook, ctx] = w.ctl.comm.cpu.step_observer();
        meter->chained = hook;
        meter->chained_ctx = ctx;
        w.ctl.comm.cpu.set_step_observer(&Meter::hook, meter.get());
    };
    nlohmann::json report;
    run_scenario(s, opt, report);
    return meter;
}

void expect_within_bounds(const std::string& file, double duration_s) {
    const std::unique_ptr<Meter> meter = measured(file, duration_s);
    EXPECT_EQ(meter->over, 0u) << file << ": first " << meter->first_over;
    EXPECT_GT(meter->checked, 100000u) << file;
    EXPECT_GT(meter->entries, 100u) << file;
    EXPECT_EQ(meter->lines_over, 0u) << file << ": first " << meter->first_line_over;
    EXPECT_GT(meter->lines, 100000u) << file;
    const std::pair<const char*, const Tally*> endings[] = {
        {"taken", &meter->taken}, {"not taken", &meter->not_taken}, {"return", &meter->returns}};
    for (const auto& [what, t] : endings) {
        EXPECT_EQ(t->over, 0u) << file << ": lines ending " << what << ", first " << t->first_over;
        EXPECT_GT(t->count, 10000u) << file << ": lines ending " << what;
        std::cout << file << ": " << t->count << " lines of 1.." << kLongestLine << " ending " << what << ", tightest "
                  << t->tightest << " (" << t->tightest_at << ")\n";
    }
    // The outcome matters: lines whose branch was taken exceed the bound of not taking it.
    EXPECT_GT(meter->taken_over_not, 1000u) << file;
    for (int o : {1, 0})
        std::cout << file << ": " << meter->pairs[o] << " two-instruction lines ending " << (o ? "taken" : "not taken")
                  << ": their bound is " << meter->pair_bound[o] / meter->pair_sum[o]
                  << " of their instructions' bounds summed\n";
    std::cout << file << ": " << meter->checked << " instructions, tightest " << meter->tightest << " ("
              << meter->tightest_at << "); " << meter->entries << " interrupt entries, tightest "
              << meter->tightest_entry << "; " << meter->lines << " straight lines of 2.." << kLongestLine
              << ", tightest " << meter->tightest_line << " (" << meter->tightest_line_at
              << "); 8-instruction lines take " << meter->eight_taken / meter->eight_sequence
              << " of their bound, bounded at " << meter->eight_sequence / meter->eight_sum
              << " of their instructions' bounds summed\n";
}

} // namespace

TEST(InstructionBound, NoInstructionOfTheDefaultScenarioExceedsItsBound) {
    expect_within_bounds("scenarios/three_ports_9600.yaml", 0.3);
}

TEST(InstructionBound, NoInstructionOfTheBreakCaseExceedsItsBound) {
    // (to 0.52 s: the BREAK comes at 500 ms, and the port's reset after it)
    expect_within_bounds("tests/comm_cpu/firmware/cases/break.yaml", 0.52);
}

TEST(InstructionBound, BoundsWithoutTheBoardsWaitStatesAreExceeded) {
    // The check can fail: bounds measured with no wait state are below what the board's ROM and
    // I/O wait states make the same instructions take.
    const i8086::WaitBounds none{0, 0, 0, 0};
    const std::unique_ptr<Meter> meter = measured("scenarios/three_ports_9600.yaml", 0.1, &none);
    EXPECT_GT(meter->over, 1000u);
    EXPECT_GT(meter->tightest, 1.1);
    EXPECT_GT(meter->lines_over, 1000u);
    EXPECT_GT(meter->tightest_line, 1.1);
    for (const Tally* t : {&meter->taken, &meter->not_taken, &meter->returns}) {
        EXPECT_GT(t->over, 100u);
        std::cout << "without wait states: " << t->over << " of " << t->count << " lines over, tightest " << t->tightest
                  << "\n";
    }
}
