// Stable reads (models/bus.h StableReads, docs/architecture.md "Stable reads"): a read its target
// declares stable is made without the kernel sync when its T1 comes before the next pending
// kernel event. The same board runs twice, each run in a child process of its own (SystemC
// elaborates once per process; two boards in one kernel would bound each other's slices), with
// stable reads on and off, the program logging every value it reads: a right declaration gives
// the same log with fewer kernel waits; a wrong one (a register that follows the time declared
// stable) gives another log.
#include "comm_cpu/cpu8086.h"
#include "models/bus.h"
#include "models/router.h"
#include "tests/support/child_run.h"
#include "tests/support/sc_test.h"

#include <tlm_utils/simple_target_socket.h>

#include <cstring>
#include <memory>
#include <vector>

using namespace rcsim;
using namespace sc_core;

namespace {

constexpr std::uint32_t kLog = 0x30000; // ES:DI = 3000:0000, where the program stores what it read
sc_time run_time() { return sc_time(300, SC_US); } // (not a static: it would fix the resolution)
constexpr std::uint16_t kLatchPort = 0x10, kClockPort = 0x20;

// A register that changes only at its own events (every 7.3 us it counts up): between them a
// read gives its value whatever the kernel time. Declared stable: right.
struct Latch : sc_module, StableReads {
    tlm_utils::simple_target_socket<Latch> bus{"bus"};
    std::uint8_t value = 0;
    sc_event tick;
    SC_HAS_PROCESS(Latch);
    explicit Latch(sc_module_name n) : sc_module(n) {
        bus.register_b_transport(this, &Latch::access);
        SC_METHOD(count);
        sensitive << tick;
    }
    void count() {
        if (sc_time_stamp() > SC_ZERO_TIME) ++value;
        tick.notify(ns(7300));
    }
    void access(tlm::tlm_generic_payload& gp, sc_time&) {
        BusView v(gp, true);
        if (gp.is_read()) gp.get_data_ptr()[0] = value;
        gp.set_response_status(tlm::TLM_OK_RESPONSE);
    }
    bool read_is_stable(std::uint64_t, unsigned) const override { return true; }
};

// A free-running microsecond counter read from the kernel time, as a timer's count register
// is: its value depends on when it is read. Declaring it stable is wrong.
struct TimeCounter : sc_module, StableReads {
    tlm_utils::simple_target_socket<TimeCounter> bus{"bus"};
    bool declared_stable = false;
    explicit TimeCounter(sc_module_name n) : sc_module(n) { bus.register_b_transport(this, &TimeCounter::access); }
    void access(tlm::tlm_generic_payload& gp, sc_time&) {
        if (gp.is_read()) gp.get_data_ptr()[0] = std::uint8_t(sc_time_stamp().value() / 1'000'000);
        gp.set_response_status(tlm::TLM_OK_RESPONSE);
    }
    bool read_is_stable(std::uint64_t, unsigned) const override { return declared_stable; }
};

// The INTA and memory sockets' far ends (the program uses neither).
struct Unused : sc_module {
    tlm_utils::simple_target_socket<Unused> inta{"inta"}, mem{"mem"};
    explicit Unused(sc_module_name n) : sc_module(n) {
        inta.register_b_transport(this, &Unused::access);
        mem.register_b_transport(this, &Unused::access);
    }
    void access(tlm::tlm_generic_payload& gp, sc_time&) { gp.set_response_status(tlm::TLM_OK_RESPONSE); }
};

// loop: IN AL,10h; STOSB; IN AL,20h; STOSB; JMP loop (at 1000:0000, ES:DI = 3000:0000)
struct Board : sc_module {
    Cpu8086 cpu{"cpu"};
    Router io{"io", true};
    Latch latch{"latch"};
    TimeCounter clock{"clock"};
    Unused unused{"unused"};
    sc_signal<bool> intr{"intr"}, nmi{"nmi"};
    std::unique_ptr<std::uint8_t[]> ram{new std::uint8_t[1 << 20]};
    // The run's end is an event, as the runner's is: the CPU's last slice stops at it, so both
    // runs leave the core at the same boundary (a run cut between a read's kernel time and its
    // T1 would stand the core elsewhere).
    sc_event end;

    Board(sc_module_name n, bool stable_reads, bool clock_declared_stable) : sc_module(n) {
        std::memset(ram.get(), 0, 1 << 20);
        const std::uint8_t code[] = {0xE4, kLatchPort, 0xAA, 0xE4, kClockPort, 0xAA, 0xEB, 0xF8};
        std::memcpy(ram.get() + 0x10000, code, sizeof code);
        cpu.map_memory(MemRegion{"ram", 0, 1u << 20, ram.get(), 0, true});
        cpu.io.bind(io.in);
        cpu.mem.bind(unused.mem);
        cpu.inta.bind(unused.inta);
        cpu.intr(intr);
        cpu.nmi(nmi);
        io.out.bind(latch.bus);
        io.out.bind(clock.bus);
        io.map(kLatchPort, 1, 0, "latch");
        io.map(kClockPort, 1, 1, "clock");
        io.declare_stable(kLatchPort, &latch);
        io.declare_stable(kClockPort, &clock);
        clock.declared_stable = clock_declared_stable;
        cpu.set_stable_reads(&io, nullptr);
        cpu.set_stable_reads_enabled(stable_reads);
        i8086::Registers r;
        r.s[i8086::CS] = 0x1000;
        r.s[i8086::ES] = 0x3000;
        r.s[i8086::SS] = 0x2000;
        r.r[i8086::SP] = 0x100;
        cpu.core().load_state(r, nullptr, 0);
        end.notify(run_time());
    }
    std::vector<std::uint8_t> log() {
        const std::uint16_t di = cpu.core().regs().r[i8086::DI];
        return std::vector<std::uint8_t>(ram.get() + kLog, ram.get() + kLog + di);
    }
};

struct BoardRun {
    std::vector<std::uint8_t> log;
    std::uint64_t cycles = 0, stable_reads = 0, access_waits = 0;
};

// 300 us of the board in a child process (tests/support/child_run.h).
BoardRun run_board(bool stable_reads, bool clock_declared_stable) {
    const test::ChildResult c = test::run_in_child([&] {
        Board b("board", stable_reads, clock_declared_stable);
        sc_start(run_time());
        return test::ChildResult{{b.cpu.cycles(), b.cpu.stable_reads(), b.cpu.access_waits()}, b.log()};
    });
    BoardRun r;
    r.log = c.log;
    if (c.counts.size() == 3) {
        r.cycles = c.counts[0];
        r.stable_reads = c.counts[1];
        r.access_waits = c.counts[2];
    }
    return r;
}

} // namespace

TEST(CpuStableReads, DeclaredStableReadsGiveTheSameRunWithoutTheirSyncs) {
    const BoardRun on = run_board(true, false), off = run_board(false, false);
    ASSERT_GT(on.log.size(), 60u);
    EXPECT_EQ(on.log, off.log);
    EXPECT_EQ(on.cycles, off.cycles);
    // Every latch read is declared stable; the clock reads are not and still sync.
    EXPECT_GT(on.stable_reads, 0u);
    EXPECT_EQ(off.stable_reads, 0u);
    EXPECT_LT(on.access_waits, off.access_waits);
    EXPECT_GT(on.access_waits, 0u);
}

TEST(CpuStableReads, AReadThatFollowsTheTimeDeclaredStableChangesTheRun) {
    const BoardRun on = run_board(true, true), off = run_board(false, true);
    ASSERT_GT(on.log.size(), 60u);
    EXPECT_NE(on.log, off.log) << "the clock read ahead of its T1 gives an earlier time";
    EXPECT_LT(on.access_waits, off.access_waits);
}

TEST(CpuStableReads, RouterForwardsTheDeclarationOfTheMappedTarget) {
    Board b("b", true, false);
    EXPECT_TRUE(b.io.read_is_stable(kLatchPort, 1));
    EXPECT_FALSE(b.io.read_is_stable(kClockPort, 1)) << "the clock declares nothing stable";
    EXPECT_FALSE(b.io.read_is_stable(kLatchPort, 2)) << "a word read runs past the latch's one-byte range";
    EXPECT_FALSE(b.io.read_is_stable(0x30, 1)) << "unmapped";
    EXPECT_THROW(b.io.declare_stable(0x30, &b.latch), std::invalid_argument);
}
