// The slice chain (docs/architecture.md "Slice chain"): where a slice ends before the next
// pending kernel event with nothing left at the current time, the core begins the next slice
// itself, the one Cpu8086::run would compute after a sync that only moves kernel time. The same
// board runs with the chain on and off, each run in a child process of its own (SystemC
// elaborates once per process): interrupts raised at irregular times, the handler logging the
// clock it reads from a time port and the main loop's counter. On and off must give the same
// log and cycle count, the chain with fewer kernel waits. A run whose slices ignore the pending
// event (lookahead off: what a chain past the event would be) gives another log, so the
// comparison sees a chain that crosses an event.
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

sc_time run_time() { return sc_time(3, SC_MS); } // (not a static: it would fix the resolution)
constexpr std::uint16_t kTimePort = 0x20;
constexpr std::uint8_t kVector = 0x40;
constexpr std::uint32_t kCounter = 0x30000, kLog = 0x40000; // DS:0 and ES:DI at the start

// The kernel time in clocks (125 ns) as a word: its value depends on when it is read.
struct TimePort : sc_module {
    tlm_utils::simple_target_socket<TimePort> bus{"bus"};
    explicit TimePort(sc_module_name n) : sc_module(n) { bus.register_b_transport(this, &TimePort::access); }
    void access(tlm::tlm_generic_payload& gp, sc_time&) {
        const std::uint64_t clocks = sc_time_stamp().value() / 125'000;
        if (gp.is_read()) {
            gp.get_data_ptr()[0] = std::uint8_t(clocks);
            if (gp.get_data_length() > 1) gp.get_data_ptr()[1] = std::uint8_t(clocks >> 8);
        }
        gp.set_response_status(tlm::TLM_OK_RESPONSE);
    }
};

// INTR raised at irregular times and held until the second INTA cycle, which gives the vector
// (an 8259A's edge request as the CPU sees it); the memory socket's far end (unused).
struct Interrupter : sc_module {
    tlm_utils::simple_target_socket<Interrupter> inta{"inta"}, mem{"mem"};
    sc_signal<bool> intr{"intr"};
    sc_event acknowledged;
    bool second = false;
    explicit Interrupter(sc_module_name n) : sc_module(n) {
        inta.register_b_transport(this, &Interrupter::acknowledge);
        mem.register_b_transport(this, &Interrupter::unused);
        test::spawn_checked([this] { raise(); }, "raise");
    }
    void raise() {
        const unsigned gaps_us[] = {137, 411, 95, 733, 260, 181, 502, 77, 349};
        for (unsigned gap : gaps_us) {
            wait(sc_time(gap, SC_US));
            intr.write(true);
            wait(acknowledged);
            intr.write(false);
        }
    }
    void acknowledge(tlm::tlm_generic_payload& gp, sc_time&) {
        gp.get_data_ptr()[0] = second ? kVector : 0xFF;
        if (second) acknowledged.notify(SC_ZERO_TIME);
        second = !second;
        gp.set_response_status(tlm::TLM_OK_RESPONSE);
    }
    void unused(tlm::tlm_generic_payload& gp, sc_time&) { gp.set_response_status(tlm::TLM_OK_RESPONSE); }
};

struct Options {
    bool chain = true;
    bool lookahead = true;
    bool idle_loop = false; // NOP NOP in the main loop (it repeats: the fast-forward takes it)
};

// start: STI; loop: INC WORD [BX] (or NOP NOP); JMP loop
// isr:   IN AX,20h; STOSW; MOV AX,[BX]; STOSW; IRET
struct Board : sc_module {
    Cpu8086 cpu{"cpu"};
    Router io{"io", true};
    TimePort time{"time"};
    Interrupter pic{"pic"};
    sc_signal<bool> nmi{"nmi"};
    std::unique_ptr<std::uint8_t[]> ram{new std::uint8_t[1 << 20]};
    sc_event end; // the run's end, an event as the runner's is (Cpu8086::end_slices_at)

    Board(sc_module_name n, const Options& o) : sc_module(n) {
        std::memset(ram.get(), 0, 1 << 20);
        const std::uint8_t body0 = o.idle_loop ? 0x90 : 0xFF, body1 = o.idle_loop ? 0x90 : 0x07;
        const std::uint8_t code[] = {0xFB, body0, body1, 0xEB, 0xFC, 0xE5, kTimePort, 0xAB, 0x8B, 0x07, 0xAB, 0xCF};
        std::memcpy(ram.get() + 0x10000, code, sizeof code);
        const std::uint8_t vector[] = {0x05, 0x00, 0x00, 0x10}; // 1000:0005
        std::memcpy(ram.get() + kVector * 4, vector, sizeof vector);
        cpu.map_memory(MemRegion{"ram", 0, 1u << 20, ram.get(), 0, true});
        cpu.io.bind(io.in);
        cpu.mem.bind(pic.mem);
        cpu.inta.bind(pic.inta);
        cpu.intr(pic.intr);
        cpu.nmi(nmi);
        io.out.bind(time.bus);
        io.map(kTimePort, 2, 0, "time");
        cpu.set_slice_chain(o.chain);
        cpu.set_lookahead(o.lookahead);
        cpu.set_fast_forward(true);
        i8086::Registers r;
        r.s[i8086::CS] = 0x1000;
        r.s[i8086::DS] = kCounter >> 4;
        r.s[i8086::ES] = kLog >> 4;
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
    std::uint64_t cycles = 0, kernel_waits = 0, slices = 0;
};

// The run in a child process (tests/support/child_run.h).
BoardRun run_board(const Options& o) {
    const test::ChildResult c = test::run_in_child([&o] {
        Board b("board", o);
        sc_start(run_time());
        return test::ChildResult{{b.cpu.cycles(), b.cpu.kernel_waits(), b.cpu.slices()}, b.log()};
    });
    BoardRun r;
    r.log = c.log;
    if (c.counts.size() == 3) {
        r.cycles = c.counts[0];
        r.kernel_waits = c.counts[1];
        r.slices = c.counts[2];
    }
    return r;
}

// Nine interrupts, each logging two words.
constexpr std::size_t kLogBytes = 9 * 4;

} // namespace

TEST(CpuSliceChain, ChainedSlicesGiveTheSameRunWithFewerKernelWaits) {
    const BoardRun on = run_board({true, true, false}), off = run_board({false, true, false});
    ASSERT_EQ(on.log.size(), kLogBytes);
    EXPECT_EQ(on.log, off.log);
    EXPECT_EQ(on.cycles, off.cycles);
    EXPECT_EQ(on.slices, off.slices) << "a chained slice is still a slice, with the same limit";
    EXPECT_LT(on.kernel_waits, off.kernel_waits);
}

TEST(CpuSliceChain, TheFastForwardCrossesChainedSlicesAlike) {
    const BoardRun on = run_board({true, true, true}), off = run_board({false, true, true});
    ASSERT_EQ(on.log.size(), kLogBytes);
    EXPECT_EQ(on.log, off.log);
    EXPECT_EQ(on.cycles, off.cycles);
    EXPECT_LT(on.kernel_waits, off.kernel_waits);
}

TEST(CpuSliceChain, SlicesThatRunPastThePendingEventChangeTheRun) {
    const BoardRun on = run_board({true, true, false}), past = run_board({false, false, false});
    ASSERT_FALSE(past.log.empty());
    EXPECT_NE(on.log, past.log) << "interrupts taken at the end of a quantum instead of at their time";
}
