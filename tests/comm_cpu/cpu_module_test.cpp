// The SystemC 8086 module: TLM I/O after sync, INTA through the inta socket, HLT wake-up, and
// lookahead exactness: instruction boundaries with interrupts at known times are identical to a
// cycle-by-cycle reference run of the bare core, with lookahead on and with a one-clock quantum.
#include "comm_cpu/cpu8086.h"
#include "models/bus.h"
#include "tests/support/sc_test.h"

#include <tlm_utils/simple_target_socket.h>

#include <cstring>
#include <memory>
#include <vector>

using namespace rcsim;
using namespace sc_core;

namespace {

// Program at 1000:0000: STI; loop: INC AX; OUT 10h,AL; IN AL,12h; JMP loop
// ISR (vector 20h) at 0000:0500: INC BX; IRET
void load_program(std::uint8_t* ram) {
    std::memset(ram, 0x90, 1 << 20);
    const std::uint8_t code[] = {0xFB, 0x40, 0xE6, 0x10, 0xE4, 0x12, 0xEB, 0xF9};
    std::memcpy(ram + 0x10000, code, sizeof code);
    ram[0x20 * 4] = 0x00;
    ram[0x20 * 4 + 1] = 0x05;
    ram[0x20 * 4 + 2] = 0;
    ram[0x20 * 4 + 3] = 0;
    ram[0x500] = 0x43;
    ram[0x501] = 0xCF;
}

void start_regs(i8086::Cpu& cpu) {
    i8086::Registers r;
    r.s[i8086::CS] = 0x1000;
    r.s[i8086::SS] = 0x2000;
    r.r[i8086::SP] = 0x100;
    cpu.load_state(r, nullptr, 0);
}

constexpr unsigned kIoWaits = 1;
// INTR rises at these times (ps); the PIC-like target drops it on the second INTA.
const std::uint64_t kRaise[] = {20'000'000, 47'123'457, 75'000'000 /* on a clock edge */, 190'062'500, 300'000'001};
constexpr std::uint64_t kEnd = 400'000'000;

struct Peripherals : sc_module {
    tlm_utils::simple_target_socket<Peripherals> io{"io"};
    tlm_utils::simple_target_socket<Peripherals> inta{"inta"};
    tlm_utils::simple_target_socket<Peripherals> mem{"mem"};
    sc_signal<bool, SC_MANY_WRITERS> intr{"intr"};
    sc_signal<bool> nmi{"nmi"};
    std::vector<sc_time> io_times;
    std::vector<sc_time> io_starts;
    std::vector<sc_time> inta_times;
    unsigned inta_count = 0;
    sc_event_queue raises{"raises"}; // one notification at each kRaise time

    SC_HAS_PROCESS(Peripherals);
    explicit Peripherals(sc_module_name n) : sc_module(n) {
        io.register_b_transport(this, &Peripherals::io_access);
        inta.register_b_transport(this, &Peripherals::inta_access);
        mem.register_b_transport(this, &Peripherals::io_access);
        // A method, not a thread: most tests stop before the last raise, and a stimulus has no
        // checks of its own for the completion check to guard.
        SC_METHOD(raise);
        sensitive << raises;
        dont_initialize();
        for (std::uint64_t r : kRaise) raises.notify(ps(r));
    }
    void raise() { intr.write(true); }
    void io_access(tlm::tlm_generic_payload& gp, sc_time&) {
        BusView v(gp, true);
        io_times.push_back(sc_time_stamp());
        io_starts.push_back(v->start);
        if (gp.is_read()) gp.get_data_ptr()[0] = 0x5A;
        v->wait_states = kIoWaits;
        gp.set_response_status(tlm::TLM_OK_RESPONSE);
    }
    void inta_access(tlm::tlm_generic_payload& gp, sc_time&) {
        inta_times.push_back(sc_time_stamp());
        if (++inta_count % 2 == 0) {
            gp.get_data_ptr()[0] = 0x20;
            intr.write(false);
        }
        gp.set_response_status(tlm::TLM_OK_RESPONSE);
    }
};

// The reference: the bare core stepped one instruction at a time, INTR applied with the same
// rule (a boundary at clock c sees changes made before c * period).
struct RefHandler : i8086::BusHandler {
    std::vector<std::uint64_t> drops; // ps at which INTR was dropped (second INTA)
    unsigned n = 0;
    std::uint64_t period;
    unsigned bus_access(i8086::Bus kind, std::uint32_t, std::uint16_t& data, unsigned, i8086::cycles_t start) override {
        if (kind == i8086::Bus::int_ack) {
            if (++n % 2 == 0) {
                data = 0x20;
                drops.push_back(start * period);
            }
            return 0;
        }
        if (kind == i8086::Bus::io_read) data = 0x5A;
        return kIoWaits;
    }
};

std::vector<i8086::cycles_t> reference_boundaries() {
    std::unique_ptr<std::uint8_t[]> ram(new std::uint8_t[1 << 20]);
    load_program(ram.get());
    i8086::Cpu cpu;
    RefHandler h;
    Clock clock;
    h.period = clock.period_ps();
    cpu.map_memory(MemRegion{"ram", 0, 1u << 20, ram.get(), 0, true});
    cpu.set_bus_handler(&h);
    start_regs(cpu);
    std::vector<i8086::cycles_t> out;
    auto level_before = [&](std::uint64_t t) {
        // last event strictly before t decides
        std::uint64_t last_raise = 0, last_drop = 0;
        bool any_raise = false, any_drop = false;
        for (std::uint64_t r : kRaise)
            if (r < t) { last_raise = r; any_raise = true; }
        for (std::uint64_t d : h.drops)
            if (d < t) { last_drop = d; any_drop = true; }
        if (!any_raise) return false;
        return !any_drop || last_raise > last_drop;
    };
    while (cpu.cycles() * h.period < kEnd) {
        cpu.set_intr(level_before(cpu.cycles() * h.period));
        cpu.step();
        out.push_back(cpu.cycles());
    }
    return out;
}

struct Top {
    std::unique_ptr<std::uint8_t[]> ram{new std::uint8_t[1 << 20]};
    Peripherals per{"per"};
    Cpu8086 cpu{"cpu"};
    std::vector<i8086::cycles_t> log;
    Top() {
        load_program(ram.get());
        cpu.map_memory(MemRegion{"ram", 0, 1u << 20, ram.get(), 0, true});
        cpu.io.bind(per.io);
        cpu.inta.bind(per.inta);
        cpu.mem.bind(per.mem);
        cpu.intr(per.intr);
        cpu.nmi(per.nmi);
        start_regs(cpu.core());
        cpu.set_boundary_log(&log);
    }
};

void check_against_reference(Top& top) {
    sc_start(ps(kEnd));
    const auto ref = reference_boundaries();
    std::size_t n = 0;
    while (n < top.log.size() && n < ref.size() && top.cpu.time_of(top.log[n]) <= ps(kEnd)) ++n;
    ASSERT_GT(n, 250u);
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(top.log[i], ref[i]) << "boundary " << i;
    EXPECT_EQ(top.per.inta_times.size(), 2 * std::size(kRaise));
}

// Every slice ends with a wait for kernel time to reach the core, and every I/O and INTA cycle
// waits for its T1 (the core is past the kernel's time by then: the instruction's fetch and
// decode came first). The program does not halt, and the run ends inside its last slice, the
// CPU waiting for the T1 of an access after the end: one slice wait fewer than slices, one
// access wait more than the accesses the target saw.
void expect_kernel_waits(const Top& top) {
    const std::size_t accesses = top.per.io_times.size() + top.per.inta_times.size();
    EXPECT_EQ(top.cpu.access_waits(), accesses + 1);
    EXPECT_EQ(top.cpu.kernel_waits() - top.cpu.access_waits(), top.cpu.slices() - 1);
}

} // namespace

TEST(Cpu8086Module, LookaheadMatchesCycleByCycleReference) {
    Top top;
    top.cpu.set_quantum(us(50));
    check_against_reference(top);
    EXPECT_LT(top.cpu.slices(), top.log.size()) << "lookahead should run several instructions per slice";
}

// Fast sync off: every TLM access ends its slice (the reference behaviour) and the boundaries
// are the same.
TEST(Cpu8086Module, FastSyncOffMatchesReference) {
    Top top;
    top.cpu.set_quantum(us(50));
    top.cpu.set_fast_sync(false);
    check_against_reference(top);
    // Each of the program's I/O accesses ended a slice.
    EXPECT_GE(top.cpu.slices(), top.per.io_times.size());
    expect_kernel_waits(top);
}

// Fast sync on: an I/O access that leaves no kernel activity (this target only answers) does
// not end the slice, so the program's accesses (an OUT and an IN per loop of 4 instructions)
// share slices; the boundaries stay those of the reference. What still ends slices: the five INTR
// raises (timed events), the INTA pairs (the second writes INTR: activity at the current time)
// and the 50 us quantum over 400 us, about 5 x 3 + 8, far fewer than the accesses (over 100).
TEST(Cpu8086Module, FastSyncKeepsTheSliceAcrossQuietAccesses) {
    Top top;
    top.cpu.set_quantum(us(50));
    check_against_reference(top);
    ASSERT_GT(top.per.io_times.size(), 100u);
    EXPECT_LT(top.cpu.slices() * 4, top.per.io_times.size());
    expect_kernel_waits(top);
}

TEST(Cpu8086Module, OneClockQuantumMatchesReference) {
    Top top;
    top.cpu.set_lookahead(false);
    top.cpu.set_quantum(top.cpu.clock().period());
    check_against_reference(top);
}

TEST(Cpu8086Module, IoTargetSeesTimeOfT1) {
    Top top;
    sc_start(us(5));
    ASSERT_FALSE(top.per.io_times.empty());
    for (std::size_t i = 0; i < top.per.io_times.size(); ++i) {
        EXPECT_EQ(top.per.io_times[i], top.per.io_starts[i]);
        EXPECT_EQ(to_ps(top.per.io_times[i]) % 125000, 0u) << "on a clock edge";
    }
}

TEST(Cpu8086Module, QuantumShorterThanAClockIsAnError) {
    Top top;
    EXPECT_THROW(top.cpu.set_quantum(ps(1000)), sc_report);
}

namespace {
// HLT then wake by INTR raised at 30 us.
struct HaltTop : Top {
    HaltTop() {
        const std::uint8_t code[] = {0xFB, 0xF4, 0x90, 0xF4};
        std::memcpy(ram.get() + 0x10000, code, sizeof code);
    }
};
} // namespace

TEST(Cpu8086Module, HltSleepsUntilIntr) {
    HaltTop top;
    // A quantum shorter than the 20 us sleep: a thread that woke once per quantum would show.
    top.cpu.set_quantum(us(10));
    sc_start(us(19));
    EXPECT_TRUE(top.cpu.core().halted());
    const auto instr = top.cpu.instructions();
    // The slice that ran STI and HLT ended with a wait for kernel time to reach the core, then
    // the thread sleeps in one wait until INTR rises (20 us), not one per quantum.
    const auto waits = top.cpu.kernel_waits();
    EXPECT_EQ(waits, top.cpu.slices() + 1);
    sc_start(ns(900));
    EXPECT_EQ(top.cpu.kernel_waits(), waits);
    EXPECT_TRUE(top.cpu.core().halted());
    sc_start(ns(11100)); // 31 us: the first INTR (20 us) has been taken and the ISR has run
    EXPECT_GT(top.cpu.instructions(), instr);
    ASSERT_EQ(top.per.inta_times.size(), 2u);
    EXPECT_GE(top.per.inta_times[0], us(20));
    EXPECT_LT(top.per.inta_times[0], us(20) + ns(125 * 8));
}
