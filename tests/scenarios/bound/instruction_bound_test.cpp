// The per-instruction worst clocks (comm_cpu/i8086/worst_clocks.h) against the shipped firmware
// as the board runs it: every instruction of a shortened run of the default scenario and of the
// BREAK case takes no more clocks than WorstClocks gives its bytes with the board's wait states
// and CX at its boundary, and every interrupt entry no more than interrupt_entry().
#include "comm_cpu/i8086/worst_clocks.h"
#include "scenarios/config/scenario.h"
#include "scenarios/run/runner.h"
#include "scenarios/world/world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <memory>
#include <string>

using namespace rcsim;

namespace {

// Measures each instruction between successive boundaries of the step hook (set without a
// SkipHook: the fast-forward is off, every boundary is seen).
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
        if (have && !(length && bytes[0] == 0xF4) && !cpu.interrupt_from_halt()) { // (HLT waits)
            i8086::cycles_t end = now;
            if (cpu.interrupt_boundary() > at) { // an interrupt entry followed the instruction
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
        }
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
    std::cout << file << ": " << meter->checked << " instructions, tightest " << meter->tightest << " ("
              << meter->tightest_at << "); " << meter->entries << " interrupt entries, tightest "
              << meter->tightest_entry << "\n";
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
}
