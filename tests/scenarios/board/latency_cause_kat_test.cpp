// Latency causes (scenarios/board/latency_cause.h) known-answer tests: nasm ROMs (tests/scenarios/board/kat/)
// on an 8086 + 8259A (+ IDT7130) board with the communication board's map and wait states, the
// 8259A watched by the probe, IR lines raised at known times. Each phase of a latency and each
// cause's figure is derived below in clocks, not taken from the probe:
//   [TAB]  8086 clock tables (instruction already in the queue, boundary to boundary): NOP 3,
//          CLI 2, STI 2; DIV r16 144-162, the fastest when every trial subtraction of the
//          division fails (a zero quotient; the microcode's CORD loop, docs/cpu8086.md).
//   [DS]   INTR is sampled at instruction boundaries (a boundary at clock edge c sees the level
//          held before c); no recognition after STI when IF was 0 until the next instruction
//          has run; an interrupt is not taken inside an instruction.
//   [KAT]  the derivations of probe_known_answer_test.cpp for this layout (kat/latency_kat.inc):
//          (E) entry: first_isr = B + 57 from a boundary B with the bus idle, INTA1 at B + 4;
//          (H) the MOV/OUT/IRET handler entered at B: h = B + 52, EOI at h + 24, the return fetch
//              at h + 57 = B + 109 (so a HLT woken at B resumes with its return fetch T1 at B + 109);
//          (T) the same tail resumed by an IRET whose return fetch is at r0: OUT read r0 + 10,
//              EOI T1 r0 + 20, IRET read r0 + 23;
//          (C) after a return fetch at r (even, ROM 1 Tw): the first opcode read at r + 5 and its
//              boundary at r + 6; each instruction's next read at its read + its clocks [TAB]
//              while the queue keeps up (one byte per NOP, two per fetch of 5 clocks).
//   [BRD]  ROM 1 wait state, RAM 0, I/O 1; the DP-RAM none but BUSY.
//   [IDT]  IDT7130 55 ns grade: the loser's read completes tBDA + tBDD = 30 + 45 ns after the
//          winner's cycle ends, its Tw states end at the first clock edge at or after that.
// The phases partition [IR rise, first ISR instruction]; the cause is the kind with the most time.
#include "comm_cpu/comm_board.h"
#include "comm_cpu/cpu8086.h"
#include "dpram/idt7130.h"
#include "models/router.h"
#include "pic8259/pic8259.h"
#include "scenarios/board/interrupt_probe.h"
#include "scenarios/debug/symbols.h"
#include "scenarios/run/cause_symbols.h"
#include "scenarios/verdict/latency_causes.h"
#include "tests/support/sc_test.h"
#include "tests/support/files.h"

#include <tlm_utils/simple_initiator_socket.h>
#include <tlm_utils/simple_target_socket.h>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using namespace rcsim;
using namespace sc_core;
using Kind = LatencyPhase::Kind;

namespace {

constexpr std::uint64_t kClockPs = 125'000; // 8 MHz
sc_time at_clock(std::uint64_t c) { return ps(c * kClockPs); }
sc_time mid_clock(std::uint64_t c) { return ps(c * kClockPs + kClockPs / 2); }

constexpr unsigned kToInta1 = 4, kToFirstIsr = 57; // (E)
constexpr unsigned kWakeToReturn = 109;            // (H): a HLT woken at B resumes at B + 109
constexpr unsigned kHandlerEoi = 52 + 24;          // (E)+(H): the EOI's T1 from the boundary
constexpr unsigned kTailOutRead = 10, kTailEoi = 20, kTailIretRead = 23; // (T)

std::string kat(const std::string& file) { return std::string(RCSIM_LATENCY_KAT) + "/" + file; }

struct IrStep {
    sc_time at;
    unsigned level;
    bool value;
};

// Cpu8086 + 8259A + IDT7130 (left port at D0000) with the board's map and wait states; the ROM
// and its symbols from nasm; vector 20h + n -> the ROM's isrN. A right-port read of the DP-RAM's
// byte 010h at `right_at` (if set) holds it for `right_clocks` clocks.
struct CpuPicDpram : sc_module {
    CommBoardConfig cfg;
    std::vector<std::uint8_t> ram = std::vector<std::uint8_t>(cfg.ram_size, 0);
    std::vector<std::uint8_t> rom;
    debug::SymbolTable symbols;
    Cpu8086 cpu{"cpu"};
    Router io{"io", true};
    Router mem{"mem"};
    Pic8259 pic{"pic"};
    Idt7130 dpram{"dpram"};
    tlm_utils::simple_initiator_socket<CpuPicDpram> right{"right"};
    IrqLine intr{"intr"}, nmi{"nmi"}, int_l{"int_l"}, int_r{"int_r"};
    sc_vector<IrqLine> ir{"ir", 8};
    std::vector<IrStep> script;
    sc_time right_at = SC_ZERO_TIME;
    unsigned right_clocks = 100;
    InterruptProbe probe;
    std::vector<Idt7130::BusyEvent> busy;
    std::vector<i8086::BusRecord> dpram_cycles; // the CPU's DP-RAM cycles

    SC_HAS_PROCESS(CpuPicDpram);
    CpuPicDpram(sc_module_name name, const std::string& rom_name, std::vector<IrStep> steps)
        : sc_module(name), rom(test::slurp_bytes(kat(rom_name + ".bin"))),
          symbols(debug::SymbolTable::load_nasm_map(kat(rom_name + ".map"))), script(std::move(steps)),
          probe("probe", cpu, lines(), cfg.pic_io_base, cfg.dpram_base, Idt7130::kSize) {
        EXPECT_EQ(rom.size(), cfg.rom_size) << rom_name;
        rom.resize(cfg.rom_size, 0xFF);
        cpu.map_memory({"ram", cfg.ram_base, cfg.ram_size, ram.data(), cfg.ram_wait, true});
        cpu.map_memory({"rom", cfg.rom_base, cfg.rom_size, rom.data(), cfg.rom_wait, false});
        cpu.io.bind(io.in);
        cpu.mem.bind(mem.in);
        cpu.inta.bind(pic.inta);
        cpu.intr(intr);
        cpu.nmi(nmi);
        pic.intr(intr);
        io.out.bind(pic.bus);
        io.map(cfg.pic_io_base, 4, 0, "pic", cfg.io_wait);
        mem.out.bind(dpram.left);
        mem.map(cfg.dpram_base, Idt7130::kSize, 0, "dpram", cfg.dpram_wait);
        right.bind(dpram.right);
        dpram.int_l(int_l);
        dpram.int_r(int_r);
        dpram.on_busy = [this](const Idt7130::BusyEvent& e) { busy.push_back(e); };
        for (unsigned n = 0; n < 8; ++n) pic.ir[n](ir[n]);
        probe.watch_pic(pic);
        cpu.set_debug_bus_observer(
            [](void* self, const i8086::BusRecord& r) {
                auto* b = static_cast<CpuPicDpram*>(self);
                if (r.address - b->cfg.dpram_base < Idt7130::kSize && r.kind != i8086::Bus::io_read &&
                    r.kind != i8086::Bus::io_write && r.kind != i8086::Bus::int_ack)
                    b->dpram_cycles.push_back(r);
            },
            this);
        for (unsigned n = 0; n < 8; ++n) {
            const debug::Symbol* s = symbols.find("isr" + std::to_string(n));
            EXPECT_NE(s, nullptr) << "isr" << n;
            const std::uint32_t ip = s ? s->address - cfg.rom_base : 0;
            std::uint8_t* v = &ram[4 * (0x20 + n)];
            v[0] = ip & 0xFF;
            v[1] = std::uint8_t(ip >> 8);
            v[2] = 0x00;
            v[3] = 0xF0;
        }
        test::spawn_checked([this] { drive(); }, "drive");
        test::spawn_checked([this] { drive_right(); }, "drive_right");
    }
    std::vector<IrqLine*> lines() {
        std::vector<IrqLine*> v;
        for (auto& line : ir) v.push_back(&line);
        return v;
    }
    void drive() {
        for (const IrStep& s : script) {
            wait(s.at - sc_time_stamp());
            ir[s.level].write(s.value);
        }
    }
    void drive_right() {
        if (right_at == SC_ZERO_TIME) return;
        dpram.ports[Idt7130::right_port].cycle_clocks = right_clocks;
        wait(right_at - sc_time_stamp());
        std::uint8_t data[2] = {0, 0};
        bus_access(right, BusCycle::mem_read, 0x010, data, 1, sc_time_stamp());
    }
    const InterruptRecord& record_of(unsigned level, unsigned nth = 0) const {
        for (const InterruptRecord& r : probe.records())
            if (r.level == level && nth-- == 0) return r;
        static const InterruptRecord none;
        ADD_FAILURE() << "no record " << nth << " of level " << level;
        return none;
    }
};

struct Want {
    Kind kind;
    int level;
    sc_time from, to;
};

// The phases are `want`, and they partition [ir_rise, first_isr].
void expect_phases(const InterruptRecord& r, const std::vector<Want>& want) {
    const LatencyCause& c = r.cause;
    ASSERT_TRUE(c.known);
    ASSERT_EQ(c.phases, want.size());
    for (unsigned k = 0; k < c.phases; ++k) {
        SCOPED_TRACE(testing::Message() << "phase " << k << " " << to_string(c.phase[k].kind));
        EXPECT_EQ(c.phase[k].kind, want[k].kind);
        EXPECT_EQ(c.phase[k].level, want[k].level);
        EXPECT_EQ(c.phase[k].from, want[k].from);
        EXPECT_EQ(c.phase[k].to, want[k].to);
    }
    EXPECT_EQ(c.phase[0].from, r.ir_rise);
    EXPECT_EQ(c.phase[c.phases - 1].to, r.first_isr);
    for (unsigned k = 1; k < c.phases; ++k) EXPECT_EQ(c.phase[k].from, c.phase[k - 1].to);
    EXPECT_FALSE(c.truncated);
}

// The first level-3 record is the wake-up of main from HLT at boundary b (the CPU was halted:
// its INTA1 is (E)'s).
void expect_wake(const CpuPicDpram& b, std::uint64_t wake) {
    const InterruptRecord& w = b.record_of(3);
    EXPECT_EQ(w.inta1, at_clock(wake + kToInta1));
    EXPECT_EQ(w.iret_done, at_clock(wake + kWakeToReturn));
}

SymbolOf symbols_of(const std::string& rom) { return cause_symbols(debug::SymbolTable::load(kat(rom + ".map"))); }

} // namespace

// (1) MOV BX,1000h / XOR DX,DX / NOP / STI / HLT; IR3 wakes it at 601, its IRET returns at
// r = 710 to CLI / 100 NOPs / STI / DIV BX (AX = 0020h from the handler: quotient 0). By (C) CLI
// (F000:0120) is read at r+5 and begins at its boundary r+6 = 716; NOP j is read at r+7+3j; STI
// (F000:0185) at r+307; DIV at r+309, beginning at r+310, where STI's effect is due: IF = 1 from
// there, but the DIV, the instruction after STI, runs first [DS]: 144 clocks [TAB] (as in (3)),
// to the boundary r+454 (queue full, bus idle), where the interrupt is taken; (E) from there.
// IR3 rises again at r+20.5: IF = 0 to r+310 (289.5 clocks), the DIV 144, the entry 57: latency
// 490.5 clocks, interrupts disabled since the CLI's boundary, until STI's end.
TEST(LatencyCauseKat, InterruptsDisabledFromCliToSti) {
    constexpr std::uint64_t wake = 601, r = wake + kWakeToReturn, until = r + 310, boundary = until + 144;
    CpuPicDpram b("board", "kat_cli", {{mid_clock(600), 3, true}, {mid_clock(640), 3, false}, {mid_clock(r + 20), 3, true}});
    sc_start(us(250));
    ASSERT_EQ(b.probe.records().size(), 2u);
    expect_wake(b, wake);
    const InterruptRecord& x = b.record_of(3, 1);
    EXPECT_EQ(x.first_isr - x.ir_rise, ps(490 * kClockPs + kClockPs / 2));
    expect_phases(x, {{Kind::interrupts_disabled, -1, mid_clock(r + 20), at_clock(until)},
                      {Kind::instruction, -1, at_clock(until), at_clock(boundary)},
                      {Kind::entry, -1, at_clock(boundary), at_clock(boundary + kToFirstIsr)}});
    const LatencyCause& c = x.cause;
    EXPECT_EQ(c.cause, Kind::interrupts_disabled);
    EXPECT_EQ(c.cause_time, ps(289 * kClockPs + kClockPs / 2));
    ASSERT_TRUE(c.if_off.valid && c.if_off.has_off && c.if_off.has_on);
    EXPECT_EQ(c.if_off.since, at_clock(r + 6)); // the CLI's boundary
    EXPECT_EQ(c.if_off.off.opcode, 0xFA);
    EXPECT_EQ(c.if_off.off.cs, 0xF000);
    EXPECT_EQ(c.if_off.off.ip, 0x0120);
    EXPECT_EQ(c.if_off.on.opcode, 0xFB);
    EXPECT_EQ(c.if_off.on.ip, 0x0185);
    EXPECT_EQ(c.if_off.until, at_clock(until));
    EXPECT_TRUE(c.instruction.sti_shadow);
    EXPECT_EQ(c.instruction.ip, 0x0186); // the DIV after STI
    EXPECT_EQ(c.instruction.start, at_clock(until));
    // since 716 clocks = 89.5 us, until 1020 clocks = 127.5 us; 289.5 clocks = 36.1875 us.
    const std::string text = latency_cause_text(x, 0x20, symbols_of("kat_cli"));
    // Main-program code held it: the routine of its CLI (no call on main's stack) names it.
    EXPECT_FALSE(x.holder_service);
    EXPECT_EQ(path_names(x.holder_path.data(), x.holder_path_len, symbols_of("kat_cli")),
              std::vector<std::string>{"cli_here"});
    EXPECT_EQ(text, "interrupts disabled (IF=0) since 0.000 089 500 s (CLI at F000:0120, cli_here) until 0.000 127 500 s "
                    "(STI at F000:0185, sti_here); held by main-program code cli_here; 36.2 us of the latency")
        << text;
}

// (2) IR1 wakes main at 321 ((H)-like entry: its handler writes OCW3, STI, HLT at F000:0245 with
// IR1 in service). IR3, lower, rises at 400.5: the 8259A holds it for IR1 in service. IR0 rises
// at 480.5 (presented first, the CPU halted with IF = 1) and wakes the HLT at 481 [KAT]: INTA1
// at 485 (IR0 in service from there), its EOI at 481 + 76 = 557 (IR1 in service again), its
// return fetch at r0 = 481 + 109 = 590 into IR1's tail (T): IR1's EOI at r0+20 = 610 lets IR3
// in; IF = 1 (IR0's IRET restored IR1's STI), so the OUT (begun at r0+11, F000:0248) ends at
// the boundary r0+24 = 614 after the IRET's opcode read at r0+23, where IR3 is taken.
// IR1 in service 80 + 53 = 133 clocks, IR0 72: the cause is rs232_1 in service.
TEST(LatencyCauseKat, HigherPriorityHandlerInService) {
    CpuPicDpram b("board", "kat_in_service",
            {{mid_clock(320), 1, true}, {mid_clock(360), 1, false}, {mid_clock(400), 3, true}, {mid_clock(480), 0, true},
             {mid_clock(520), 0, false}});
    sc_start(us(150));
    ASSERT_EQ(b.probe.records().size(), 3u);
    constexpr std::uint64_t b0 = 481, r0 = b0 + kWakeToReturn, boundary = r0 + kTailIretRead + 1;
    const InterruptRecord& ir0 = b.record_of(0);
    EXPECT_EQ(ir0.inta1, at_clock(b0 + kToInta1));
    EXPECT_EQ(ir0.eoi, at_clock(b0 + kHandlerEoi));
    const InterruptRecord& ir1 = b.record_of(1);
    EXPECT_EQ(ir1.eoi, at_clock(r0 + kTailEoi));
    const InterruptRecord& x = b.record_of(3);
    EXPECT_EQ(x.depth, 1u); // inside IR1's handler
    EXPECT_GE(x.first_isr, at_clock(boundary + kToFirstIsr));
    expect_phases(x, {{Kind::in_service, 1, mid_clock(400), mid_clock(480)},
                      {Kind::priority, 0, mid_clock(480), at_clock(b0 + kToInta1)},
                      {Kind::in_service, 0, at_clock(b0 + kToInta1), at_clock(b0 + kHandlerEoi)},
                      {Kind::in_service, 1, at_clock(b0 + kHandlerEoi), at_clock(r0 + kTailEoi)},
                      {Kind::instruction, -1, at_clock(r0 + kTailEoi), at_clock(boundary)},
                      {Kind::entry, -1, at_clock(boundary), x.first_isr}});
    const LatencyCause& c = x.cause;
    EXPECT_EQ(c.cause, Kind::in_service);
    EXPECT_EQ(c.cause_level, 1);
    EXPECT_EQ(c.cause_time, at_clock(133));
    EXPECT_EQ(c.instruction.ip, 0x0248); // OUT 0C0h,AL
    EXPECT_EQ(c.instruction.start, at_clock(r0 + kTailOutRead + 1));
    // The holder is IR1's service (isr1, which called nothing) that had interrupted main's HLT at
    // F000:0119: its return address is the next instruction, F000:011A (main + 2).
    EXPECT_TRUE(x.holder_service);
    EXPECT_EQ(x.holder_level, 1);
    EXPECT_EQ(latency_cause_text(x, 0x20, symbols_of("kat_in_service")),
              "the rs232_1 interrupt in service in the 8259A (higher priority) for 16.6 us; held by isr1, "
              "interrupted at F000:011A (main+0x2)");
}

// (3) MOV AX,5 / XOR DX,DX / MOV BX,1000h / STI / HLT; IR3 wakes it at 601, its IRET returns at
// r = 710 to DIV BX (F000:0122; AX = 0020h from the handler): read at r+5, begun at r+6 = 716;
// the quotient is 0, the fastest DIV r16: 144 clocks [TAB], so it ends at the boundary 860 (the
// queue full, the bus idle), where IR0, risen at r+56.5 = 766.5, is taken: 93.5 clocks left of
// the DIV, then (E).
TEST(LatencyCauseKat, LongDivInProgress) {
    constexpr std::uint64_t wake = 601, r = wake + kWakeToReturn, div_start = r + 6, boundary = div_start + 144;
    CpuPicDpram b("board", "kat_div",
            {{mid_clock(600), 3, true}, {mid_clock(640), 3, false}, {mid_clock(r + 56), 0, true}, {mid_clock(900), 0, false}});
    sc_start(us(150));
    ASSERT_EQ(b.probe.records().size(), 2u);
    expect_wake(b, wake);
    const InterruptRecord& x = b.record_of(0);
    EXPECT_EQ(x.inta1, at_clock(boundary + kToInta1));
    expect_phases(x, {{Kind::instruction, -1, mid_clock(r + 56), at_clock(boundary)},
                      {Kind::entry, -1, at_clock(boundary), at_clock(boundary + kToFirstIsr)}});
    const LatencyCause& c = x.cause;
    EXPECT_EQ(c.cause, Kind::instruction);
    EXPECT_EQ(c.cause_time, ps(93 * kClockPs + kClockPs / 2)); // the DIV's remaining clocks
    ASSERT_TRUE(c.instruction.valid);
    EXPECT_EQ(c.instruction.start, at_clock(div_start));
    EXPECT_EQ(c.instruction.cs, 0xF000);
    EXPECT_EQ(c.instruction.ip, 0x0122);
    ASSERT_GE(c.instruction.nbytes, 2u);
    EXPECT_EQ(c.instruction.bytes[0], 0xF7);
    EXPECT_EQ(c.instruction.bytes[1], 0xF3);
    EXPECT_FALSE(c.if_off.valid);
    // div_start 716 clocks = 89.5 us; 93.5 clocks = 11.6875 us.
    EXPECT_EQ(latency_cause_text(x, 0x20, symbols_of("kat_div")),
              "the instruction in progress, DIV at F000:0122 (div_here) begun at 0.000 089 500 s: 11.7 us to its end");
    const nlohmann::json j = latency_cause_json(x, 0x20, symbols_of("kat_div"));
    EXPECT_EQ(j["cause"], "instruction");
    EXPECT_EQ(j["detail"]["instruction"]["mnemonic"], "DIV");
    EXPECT_EQ(j["detail"]["instruction"]["bytes"].get<std::string>().substr(0, 5), "F7 F3");
    EXPECT_EQ(j["detail"]["instruction"]["symbol"], "div_here");
}

// (4) DS = D000; IR3 wakes main at 601, its IRET returns at r = 710 to MOV AL,[0010h]. The right
// port reads byte 010h at r+5 = 715 with a 100-clock cycle: the CPU's read of it, later, gets
// BUSY; its Tw states end at the first clock edge at or after 715 + 100 clocks + 75 ns [IDT]:
// 816. IR0 rises at r+40.5 = 750.5, inside them: the bus is held 65.5 clocks of the latency; then
// the rest of the MOV, then the entry.
TEST(LatencyCauseKat, DpramBusyHoldsTheBus) {
    constexpr std::uint64_t wake = 601, r = wake + kWakeToReturn, busy_end = r + 5 + 100 + 1;
    CpuPicDpram b("board", "kat_busy",
            {{mid_clock(600), 3, true}, {mid_clock(640), 3, false}, {mid_clock(r + 40), 0, true}, {mid_clock(1000), 0, false}});
    b.right_at = at_clock(r + 5);
    b.right_clocks = 100;
    sc_start(us(200));
    ASSERT_EQ(b.probe.records().size(), 2u);
    expect_wake(b, wake);
    ASSERT_EQ(b.busy.size(), 1u);
    EXPECT_EQ(b.busy[0].port, Idt7130::left_port);
    ASSERT_EQ(b.dpram_cycles.size(), 1u);
    const i8086::BusRecord& read = b.dpram_cycles[0];
    EXPECT_EQ(read.address, 0xD0010u);
    EXPECT_EQ(read.wait_states, b.busy[0].wait_states);
    EXPECT_EQ(read.start + 3 + read.wait_states, busy_end); // the Tw states end at 816
    EXPECT_LT(at_clock(read.start + 3), mid_clock(r + 40)); // ... and began before the rise
    const InterruptRecord& x = b.record_of(0);
    const LatencyCause& c = x.cause;
    ASSERT_TRUE(c.known);
    ASSERT_EQ(c.phases, 3u);
    const sc_time boundary = c.boundary;
    expect_phases(x, {{Kind::dpram_busy, -1, mid_clock(r + 40), at_clock(busy_end)},
                      {Kind::instruction, -1, at_clock(busy_end), boundary},
                      {Kind::entry, -1, boundary, x.first_isr}});
    EXPECT_LT(boundary - at_clock(busy_end), at_clock(8)); // T4 and the next opcode read
    EXPECT_EQ(c.cause, Kind::dpram_busy);
    EXPECT_EQ(c.cause_time, ps(65 * kClockPs + kClockPs / 2));
    EXPECT_EQ(c.busy.wait_states, read.wait_states);
    EXPECT_EQ(c.busy.address, 0xD0010u);
    EXPECT_EQ(c.instruction.ip, 0x0120);
    const std::string text = latency_cause_text(x, 0x20, symbols_of("kat_busy"));
    EXPECT_EQ(text, "the bus held by DP-RAM BUSY for 8.2 us (" + std::to_string(read.wait_states) +
                        " wait states at D0010)")
        << text;
}

// (5) kat_blocking: blocking time and call paths. Each expected blocking time is, exactly, from
// the first handler instruction (first_isr) to the boundary of the instruction that set IF again
// (the core's own IF history: i8086::Cpu::if_change), the handler having sent its EOI before;
// and, from the clock tables [TAB], at least the sum of the clocks of the instructions in between
// (each in the queue), at most that with each taken LOOP's target refetched after its flush, one
// ROM word fetch (4 + 1 Tw [BRD]) each, and 200 clocks for the other fetches:
//   isr0: MOV AL 4, OUT 10, PUSH CX 11, CALL 19, PUSH BP 11, CALL 19, PUSH BP 11, MOV CX 4,
//         LOOP 1000 times (17 taken, 5 the last), POP BP 8, RET 8, POP BP 8, RET 8, POP CX 8.
//   isr1: MOV AL 4, OUT 10, then STI: IF = 1 from there, the EOI was sent before.
namespace {

constexpr std::uint64_t kLoop1000 = 999 * 17 + 5;
constexpr std::uint64_t kIsr0Clocks = 4 + 10 + 11 + 19 + 11 + 19 + 11 + 4 + kLoop1000 + 8 + 8 + 8 + 8 + 8;
constexpr std::uint64_t kSlack = 999 * 5 + 200;

// The first IF change made by `opcode` (an instruction) after `after`, from the core's history.
sc_time if_change_of(CpuPicDpram& b, std::uint8_t opcode, const sc_time& after) {
    const i8086::Cpu& core = b.cpu.core();
    sc_time found = SC_ZERO_TIME;
    for (unsigned k = 0; k < core.if_changes(); ++k) { // newest first: the last one found is the first
        const i8086::IfChange& c = core.if_change(k);
        if (c.how == i8086::IfChange::How::instruction && c.opcode == opcode && b.cpu.time_of(c.cycle) > after)
            found = b.cpu.time_of(c.cycle);
    }
    if (found == SC_ZERO_TIME) ADD_FAILURE() << "no IF change by opcode " << unsigned(opcode);
    return found;
}

std::vector<std::string> names(const InterruptRecord& r) {
    return path_names(r.path.data(), r.path_len, symbols_of("kat_blocking"));
}

} // namespace

// IR0 interrupts main's loop at 600.5: isr0 blocks from its first instruction to its IRET (EOI at once, IF = 0
// all along) through isr0 > routine_a > routine_b. IR2 rises during routine_b's loop: IF = 0 holds
// it until isr0's IRET; the cause names isr0's path and where isr0 had interrupted (main's loop).
TEST(BlockingKat, HandlerThroughTwoRoutinesWithInterruptsDisabled) {
    CpuPicDpram b("board", "kat_blocking",
                  {{mid_clock(600), 0, true}, {mid_clock(640), 0, false}, {mid_clock(2000), 2, true},
                   {mid_clock(30000), 2, false}}); // IR2 high until its INTA [DS]
    b.cpu.set_debug_bus_observer(nullptr, nullptr); // (it sees every cycle: the probe's kinds below)
    std::vector<std::pair<unsigned, sc_time>> asked; // the RX FIFO levels asked for: level, when
    b.probe.fifo_level = [&asked](unsigned level) {
        asked.emplace_back(level, sc_time_stamp());
        return 3u;
    };
    sc_start(us(4500));
    ASSERT_EQ(b.probe.records().size(), 2u);
    const InterruptRecord& x = b.record_of(0);
    const sc_time iret = if_change_of(b, 0xCF, x.first_isr);
    EXPECT_EQ(x.blocking, iret - x.first_isr);
    EXPECT_GE(x.blocking, at_clock(kIsr0Clocks));
    EXPECT_LE(x.blocking, at_clock(kIsr0Clocks + kSlack));
    EXPECT_LT(x.blocking, x.iret_done - x.first_isr); // the IRET itself blocks no more
    EXPECT_EQ(names(x), (std::vector<std::string>{"isr0", "routine_a", "routine_b"}));
    EXPECT_EQ(x.path[0], 0xF0200u); // the handler's entry
    EXPECT_EQ(b.probe.blocking_us(0).count(), 1u);
    ASSERT_NE(b.probe.longest_blocking(0), nullptr);
    EXPECT_EQ(b.probe.longest_blocking(0)->blocking, x.blocking);
    EXPECT_EQ(b.probe.longest_blocking(1), nullptr);
    // The RX FIFO level is read once per RS-232 service, when its handler begins (the kernel's
    // time at most a slice behind first_isr), and kept with the record.
    ASSERT_EQ(asked.size(), 2u);
    EXPECT_EQ(asked[0].first, 0u);
    EXPECT_EQ(asked[1].first, 2u);
    EXPECT_LE(asked[0].second, x.first_isr);
    EXPECT_EQ(x.rx_fifo_level, 3u);
    // Back in main's loop the probe watches only INTA and memory writes, as before: the paths
    // cost the main program nothing (its fetches and reads keep the core's direct path).
    EXPECT_EQ(b.cpu.core().bus_hook_kinds(),
              i8086::bus_kind_bit(i8086::Bus::int_ack) | i8086::bus_kind_bit(i8086::Bus::mem_write));

    const InterruptRecord& y = b.record_of(2);
    EXPECT_EQ(y.cause.cause, Kind::interrupts_disabled);
    ASSERT_TRUE(y.cause.if_off.has_on);
    EXPECT_EQ(y.cause.if_off.on.opcode, 0xCF); // isr0's IRET set IF again
    EXPECT_GE(y.cause.if_off.until, iret);     // ... at its end, where IR2 was taken
    EXPECT_EQ(y.cause.if_off.until, y.cause.boundary);
    EXPECT_TRUE(y.holder_service);
    EXPECT_EQ(y.holder_level, 0);
    EXPECT_EQ(path_names(y.holder_path.data(), y.holder_path_len, symbols_of("kat_blocking")),
              (std::vector<std::string>{"isr0", "routine_a", "routine_b"}));
    const std::string text = latency_cause_text(y, 0x20, symbols_of("kat_blocking"));
    EXPECT_NE(text.find("(entry of the rs232_0 interrupt) until "), std::string::npos) << text;
    EXPECT_NE(text.find("; held by isr0 > routine_a > routine_b, interrupted at F000:0119 (spin)"), std::string::npos)
        << text;
    const nlohmann::json j = latency_cause_json(y, 0x20, symbols_of("kat_blocking"));
    EXPECT_EQ(j["holder"], (std::vector<std::string>{"isr0", "routine_a", "routine_b"}));
    EXPECT_EQ(j["holder_source"], "rs232_0");
    EXPECT_EQ(j["interrupted_at"], "F000:0119");
    EXPECT_EQ(j["if_on_us"].get<double>(), to_us(y.cause.if_off.until));
}

// IR1 interrupts main at 600.5: isr1 sends its EOI and enables interrupts at once, then loops 1000 times
// with IF = 1. It blocks only up to its STI; its service is the whole loop.
TEST(BlockingKat, EarlyEoiAndStiBlockOnlyTheShortPart) {
    CpuPicDpram b("board", "kat_blocking", {{mid_clock(600), 1, true}, {mid_clock(640), 1, false}});
    sc_start(us(3000));
    ASSERT_EQ(b.probe.records().size(), 1u);
    const InterruptRecord& x = b.record_of(1);
    ASSERT_TRUE(x.has_eoi);
    EXPECT_LT(x.eoi, if_change_of(b, 0xFB, x.first_isr));
    EXPECT_EQ(x.blocking, if_change_of(b, 0xFB, x.first_isr) - x.first_isr);
    EXPECT_GE(x.blocking, at_clock(4 + 10));
    EXPECT_LE(x.blocking, at_clock(4 + 10 + 20));
    EXPECT_GE(x.iret_done - x.first_isr, at_clock(kLoop1000));
    EXPECT_EQ(names(x), std::vector<std::string>{"isr1"});
}

// IR1 as above; IR0 rises in isr1's loop and nests (IF = 1, isr1's EOI sent): isr0 blocks as when
// it interrupts main; isr1's blocking stays its short part, isr0's window left out of it. IR2
// rises during isr0's loop: held by isr0, which had interrupted isr1's loop.
TEST(BlockingKat, NestedServiceLeftOutOfItsParent) {
    CpuPicDpram b("board", "kat_blocking",
                  {{mid_clock(600), 1, true}, {mid_clock(640), 1, false}, {mid_clock(3000), 0, true},
                   {mid_clock(3040), 0, false}, {mid_clock(5000), 2, true}, {mid_clock(30000), 2, false}});
    sc_start(us(7000));
    ASSERT_EQ(b.probe.records().size(), 3u);
    const InterruptRecord& outer = b.record_of(1);
    const InterruptRecord& nested = b.record_of(0);
    EXPECT_EQ(nested.depth, 1u);
    EXPECT_GE(nested.blocking, at_clock(kIsr0Clocks));
    EXPECT_LE(nested.blocking, at_clock(kIsr0Clocks + kSlack));
    EXPECT_GE(outer.blocking, at_clock(4 + 10));
    EXPECT_LE(outer.blocking, at_clock(4 + 10 + 20));
    EXPECT_GE(outer.iret_done - outer.first_isr, at_clock(kLoop1000 + kIsr0Clocks));
    EXPECT_EQ(names(nested), (std::vector<std::string>{"isr0", "routine_a", "routine_b"}));
    const InterruptRecord& y = b.record_of(2);
    EXPECT_EQ(y.cause.cause, Kind::interrupts_disabled);
    EXPECT_TRUE(y.holder_service);
    EXPECT_EQ(y.holder_level, 0);
    const std::string text = latency_cause_text(y, 0x20, symbols_of("kat_blocking"));
    EXPECT_NE(text.find("; held by isr0 > routine_a > routine_b, interrupted at F000:024"), std::string::npos) << text;
    EXPECT_NE(text.find("(isr1_loop)"), std::string::npos) << text;
}

// (6) kat_main_hold: IR3 rises at 400.5, while hold_irqs (called by main) runs with IF = 0. The
// cause is interrupts_disabled since hold_irqs's CLI, until IF came back with its STI: the end of
// the STI (2 clocks [TAB]) when the next instruction, RET, begins (at most one ROM fetch, 4 + 1 Tw
// [BRD], later), and the holder is main-program code in hold_irqs.
TEST(BlockingKat, MainProgramCliToStiNamesItsRoutine) {
    CpuPicDpram b("board", "kat_main_hold", {{mid_clock(400), 3, true}, {mid_clock(4000), 3, false}});
    sc_start(us(1000));
    ASSERT_EQ(b.probe.records().size(), 1u);
    const InterruptRecord& x = b.record_of(3);
    EXPECT_FALSE(x.startup);
    const LatencyCause& c = x.cause;
    EXPECT_EQ(c.cause, Kind::interrupts_disabled);
    ASSERT_TRUE(c.if_off.has_off && c.if_off.has_on);
    EXPECT_EQ(c.if_off.off.opcode, 0xFA);
    EXPECT_EQ(c.if_off.off.ip, 0x0800);
    EXPECT_EQ(c.if_off.on.opcode, 0xFB);
    const sc_time sti = b.cpu.time_of(c.if_off.on.cycle);
    EXPECT_GE(c.if_off.until, sti + at_clock(2));
    EXPECT_LE(c.if_off.until, sti + at_clock(2 + 5));
    EXPECT_FALSE(x.holder_service);
    EXPECT_EQ(path_names(x.holder_path.data(), x.holder_path_len, symbols_of("kat_main_hold")),
              std::vector<std::string>{"hold_irqs"});
    const std::string text = latency_cause_text(x, 0x20, symbols_of("kat_main_hold"));
    EXPECT_NE(text.find("(CLI at F000:0800, hold_irqs) until "), std::string::npos) << text;
    EXPECT_NE(text.find("(STI at F000:0806, sti_here); held by main-program code hold_irqs; "), std::string::npos)
        << text;
    const nlohmann::json j = latency_cause_json(x, 0x20, symbols_of("kat_main_hold"));
    EXPECT_EQ(j["holder_source"], "main");
    EXPECT_FALSE(j.contains("interrupted_at"));
}
