// InterruptProbe known-answer tests: a hand-assembled program on a minimal 8086 + 8259A board
// with the communication board's memory map and wait states, interrupts raised at known times,
// handlers of known instructions. Every expected time below is derived in clocks from the 8086's
// documented interrupt sequence and bus rules, not from the probe:
//   [DS]   8086 data sheet (docs/cpu8086.md "Published timing facts"): INTR is sampled at the
//          end of an instruction (the model: a boundary at clock edge c sees the level held
//          before c; HLT resumes at the first clock edge after the change); the response is two
//          back-to-back INTA cycles, the type read on the second; IF is cleared by the entry;
//          bus cycles are T1 T2 T3 [Tw] T4; STI delays recognition by one instruction.
//   [TAB]  8086 clock tables: NOP 3, CLI 2, STI 2 (instruction already in the queue).
//   [BIU]  the bus-interface rules measured on a P80C86A-2 (docs/cpu8086.md "Core design"):
//          a word is prefetched when two queue bytes are free, decided in T2 of the cycle on
//          the bus; room on an idle bus (queue read or flush) starts a prefetch in the third
//          clock after it, room that appears in T3/T4 four clocks after that T4; an EU request
//          on an idle bus gets T1 three clocks later (a prefetch about to start waits); one
//          made during a prefetch's T1/T2 follows its T4 directly, one made in T3/T4 starts
//          three clocks after T4; a second EU cycle of the same transfer follows T4 directly;
//          the last write of an instruction overlaps the next opcode read with its T3.
//   [INT]  the interrupt entry (docs/cpu8086.md; INT n measured on the P80C86A-2): for INTR
//          one clock, INTA, INTA, one clock; then SUSP, two clocks, read IP, one clock, read CS,
//          two clocks, push FLAGS, four clocks, push CS, three clocks, flush to the handler,
//          three clocks, push IP. The single clocks around the INTA pair are the core's model
//          (no Intel text gives them; docs/cpu8086.md lists hardware INTA timing as a gap).
//   [BRD]  wait states of the board (CommBoardConfig): ROM 1, RAM 0, I/O 1; the INTA cycles go
//          to the 8259A directly (no chip-select wait state) and the 8259A adds none.
// The probe's definitions (scenarios/board/interrupt_probe.h): first_isr = end of T4 of the first code
// fetch at the handler; iret_done = T1 of the first code fetch at the return address;
// eoi = T1 of the OUT that writes the EOI; latency = first_isr - ir_rise.
#include "comm_cpu/comm_board.h"
#include "comm_cpu/cpu8086.h"
#include "models/router.h"
#include "pic8259/pic8259.h"
#include "scenarios/board/interrupt_probe.h"
#include "tests/support/sc_test.h"

#include <tlm_utils/simple_target_socket.h>

#include <cstdint>
#include <initializer_list>
#include <vector>

using namespace rcsim;
using namespace sc_core;

namespace {

constexpr std::uint64_t kClockPs = 125'000; // 8 MHz
sc_time at_clock(std::uint64_t c) { return ps(c * kClockPs); }
sc_time mid_clock(std::uint64_t c) { return ps(c * kClockPs + kClockPs / 2); } // off the clock grid
// The boundary a halted CPU wakes at: the first clock edge after the INTR change.
std::uint64_t wake_boundary(const sc_time& rise) { return to_ps(rise) / kClockPs + 1; }

// ---- Derived timing (clocks) ---------------------------------------------------------------
//
// (E) Entry from the boundary B at which INTR is recognised, the bus idle:
//   B        one clock [INT];  B+1..B+3 EU request on an idle bus [BIU]
//   B+4      INTA1 T1; 4 clocks, no Tw [BRD];  B+8 INTA2 T1 (back to back [DS][BIU]), T4 B+11
//   B+11     one clock [INT];  B+12 SUSP (one clock on an idle bus);  B+13, B+14 two clocks
//   B+18     read IP from the vector table (request B+15, idle bus; RAM, 0 Tw), T4 B+21
//   B+21     one clock;  B+25 read CS (T4 B+28);  B+28, B+29 two clocks;  B+33 push FLAGS
//   B+36..39 four clocks;  B+43 push CS (T4 B+46);  B+46..48 three clocks;  B+49 flush
//   B+52     h: first handler fetch T1, the third clock after the flush [BIU]; ROM: T1 T2 T3 Tw
//            T4 = B+52..B+56, so first_isr = B+57 (the end of that T4)
//   B+57     push IP: requested in the fetch's T1 (B+52), follows its T4 directly [BIU]
constexpr unsigned kToInta1 = 4, kToInta2 = 8, kToFirstIsr = 57;

// (H) Handler MOV AL,20h / OUT 0C0h,AL (non-specific EOI) / IRET, entered as in (E), h = B+52:
//   h+5      push IP T1; its T2 (h+6) sees 2 bytes queued: prefetch right after its T4 (h+8)
//   h+7      MOV opcode read (overlapping the push's T3);  h+8 clock;  h+9 imm8 read;  h+10 clock
//   h+9      fetch h+2 T1 (back to back), T4 h+13; T2 (h+10) sees an empty queue: next back to back
//   h+14     OUT opcode read; fetch h+4 T1;  h+15 clock;  h+16 port byte;  h+17, h+18 two clocks
//   h+19     fetch h+6 T1 (decided in T2 h+15, one byte queued); the OUT's write, requested in
//            that T1, follows its T4 (h+23):  h+24 I/O write T1 = EOI (1 Tw [BRD]); its T2 (h+25)
//            sees 4 bytes queued: prefetch after its T4
//   h+27     IRET opcode read (in the write's Tw);  h+28 clock;  h+29 fetch h+8 T1
//   h+29,30  two clocks; pop IP requested in the fetch's T3 (h+31): T1 three clocks after its T4
//            (h+33) = h+36, T4 h+39;  then three clocks;  h+45 pop CS (idle bus), T4 h+48
//   h+48     flush to the return address, two clocks;  h+53 pop FLAGS (idle bus: the prefetch
//            set up by the flush, one clock away, waits), T2 h+54 decides a prefetch after T4
//   h+57     first fetch at the return address T1 = iret_done
// Relative to first_isr = h+5: EOI +19, iret_done +52 (service 52 clocks).
constexpr unsigned kIsrEoi = 19, kIsrService = 52;

// (T) The same MOV/OUT/IRET tail resumed after an IRET's flush, first fetch T1 at r0 (even):
//   r0 fetch (T4 r0+4, next back to back);  r0+5 MOV read;  r0+7 imm8;  r0+10 OUT read (fetch
//   r0+2 T4 at r0+9);  r0+12 port byte;  r0+15 fetch T1, the write follows its T4 (r0+19):
//   r0+20 EOI T1;  r0+23 IRET read;  r0+25 fetch T1;  pop IP requested in its T3: T1 r0+32;
//   from the pop IP on as in (H) (h+36 -> h+57): iret_done = r0+53.
constexpr unsigned kTailEoi = 20, kTailIretDone = 53;

// (N) A NOP run resumed by an IRET at an even address, return fetch T1 at r:
//   fetches T1 at r, r+5, ..., r+30 back to back (each T2 sees at most 4 bytes queued); NOPs
//   [TAB] 3 clocks each: opcode reads at r+5+3k, boundaries at r+6+3k. The fetch at r+30 sees
//   5 bytes in its T2 and no more follow it; the read at r+32 (its T3) makes room, so the next
//   fetch is T1 four clocks after its T4 (r+34) = r+38. The boundary r+36 finds the bus idle.
constexpr unsigned kNopIdleBoundary = 36;

// (C) CLI, NOP, NOP, STI, NOP, NOP... resumed by an IRET at an even address, return fetch T1 r:
//   fetches r (T4 r+4), r+5 (T4 r+9), r+10 (T4 r+14), r+15 (T4 r+19): each T2 sees at most 3 bytes
//   CLI read r+5 (2 clocks [TAB]);  NOP r+7, r+10 (3 clocks);  STI r+13 (2 clocks);  NOP r+15,
//   r+18. Boundary r+16 follows STI: no recognition [DS]; boundary r+19 follows the next NOP: the
//   interrupt is taken there. The bus is in the r+15 fetch's T4 at r+19, which ends in the
//   entry's first clock, so (E) holds from B = r+19.
constexpr unsigned kAfterStiBoundary = 19;

// ---- The program -------------------------------------------------------------------------

constexpr std::uint32_t kRom = 0xF0000, kInit = 0x0100, kIsrLow = 0x0200; // offsets in F000
constexpr std::uint8_t kVectorBase = 0x20;
constexpr std::uint16_t kStackTop = 0x0800;

// A ROM image assembled by hand; every emitter names the instruction and its bytes.
struct Rom {
    std::vector<std::uint8_t> bytes = std::vector<std::uint8_t>(0x10000, 0xFF);
    std::uint16_t pc = 0;

    Rom& org(std::uint16_t at) { pc = at; return *this; }
    Rom& db(std::initializer_list<std::uint8_t> b) {
        for (std::uint8_t v : b) bytes[pc++] = v;
        return *this;
    }
    Rom& nop(unsigned n = 1) { for (unsigned i = 0; i < n; ++i) db({0x90}); return *this; }
    Rom& cli() { return db({0xFA}); }
    Rom& sti() { return db({0xFB}); }
    Rom& hlt() { return db({0xF4}); }
    Rom& iret() { return db({0xCF}); }
    Rom& mov_al(std::uint8_t v) { return db({0xB0, v}); }
    Rom& out_al(std::uint8_t port) { return db({0xE6, port}); }
    Rom& jmp_short(std::uint16_t to) { return db({0xEB, std::uint8_t(to - (pc + 2))}); }
    // The handler of level n: MOV AL,20h; OUT 0C0h,AL (OCW2 non-specific EOI); IRET.
    Rom& eoi_iret() { return mov_al(0x20).out_al(0xC0).iret(); }
};

std::uint16_t isr_offset(unsigned level) { return std::uint16_t(kIsrLow + 0x40 * level); }

// Reset FFFF:0 -> F000:0100: CLI; SS=0, SP=0800h; 8259A: ICW1 13h (edge, single, ICW4),
// ICW2 20h (types 20h-27h), ICW4 01h (8086, normal EOI), OCW1 = imr. Then `main` (at F000:0118).
Rom program(std::uint8_t imr) {
    Rom rom;
    rom.org(0xFFF0).db({0xEA, std::uint8_t(kInit), kInit >> 8, 0x00, 0xF0}); // JMP F000:0100
    rom.org(kInit).cli().db({0x31, 0xC0, 0x8E, 0xD0, 0xBC, kStackTop & 0xFF, kStackTop >> 8});
    rom.mov_al(0x13).out_al(0xC0).mov_al(kVectorBase).out_al(0xC2).mov_al(0x01).out_al(0xC2);
    rom.mov_al(imr).out_al(0xC2);
    for (unsigned level = 0; level < 8; ++level) {
        const std::uint16_t pc = rom.pc;
        rom.org(isr_offset(level)).eoi_iret().org(pc);
    }
    return rom;
}

// ---- The board ----------------------------------------------------------------------------

struct IrStep {
    sc_time at;
    unsigned level;
    bool value;
};

// Cpu8086 + 8259A with the board's map and wait states; memory outside RAM/ROM is open bus.
struct CpuPic : sc_module {
    CommBoardConfig cfg;
    std::vector<std::uint8_t> ram = std::vector<std::uint8_t>(cfg.ram_size, 0);
    std::vector<std::uint8_t> rom;
    Cpu8086 cpu{"cpu"};
    Router io{"io", true};
    Pic8259 pic{"pic"};
    tlm_utils::simple_target_socket<CpuPic> open_bus{"open_bus"};
    IrqLine intr{"intr"}, nmi{"nmi"};
    sc_vector<IrqLine> ir{"ir", 8};
    std::vector<IrStep> script;
    InterruptProbe probe;

    SC_HAS_PROCESS(CpuPic);
    CpuPic(sc_module_name name, const Rom& image, std::vector<IrStep> steps)
        : sc_module(name), rom(image.bytes), script(std::move(steps)),
          probe("probe", cpu, lines(), cfg.pic_io_base, cfg.dpram_base, 0) {
        cpu.map_memory({"ram", cfg.ram_base, cfg.ram_size, ram.data(), cfg.ram_wait, true});
        cpu.map_memory({"rom", cfg.rom_base, cfg.rom_size, rom.data(), cfg.rom_wait, false});
        cpu.io.bind(io.in);
        cpu.mem.bind(open_bus);
        cpu.inta.bind(pic.inta);
        cpu.intr(intr);
        cpu.nmi(nmi);
        pic.intr(intr);
        io.out.bind(pic.bus);
        io.map(cfg.pic_io_base, 4, 0, "pic", cfg.io_wait);
        for (unsigned n = 0; n < 8; ++n) pic.ir[n](ir[n]);
        open_bus.register_b_transport(this, &CpuPic::unmapped);
        // Vector table: type 20h+n -> F000:isr_offset(n).
        for (unsigned n = 0; n < 8; ++n) {
            std::uint8_t* v = &ram[4 * (kVectorBase + n)];
            v[0] = isr_offset(n) & 0xFF;
            v[1] = isr_offset(n) >> 8;
            v[2] = 0x00;
            v[3] = 0xF0;
        }
        test::spawn_checked([this] { drive(); }, "drive");
    }
    std::vector<IrqLine*> lines() {
        std::vector<IrqLine*> v;
        for (auto& line : ir) v.push_back(&line);
        return v;
    }
    void unmapped(tlm::tlm_generic_payload& gp, sc_time&) {
        gp.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
    }
    void drive() {
        for (const IrStep& s : script) {
            wait(s.at - sc_time_stamp());
            ir[s.level].write(s.value);
        }
    }
    const InterruptRecord& record(std::size_t n) const { return probe.records().at(n); }
};

// A record of `level` entered at boundary `b` (bus idle), running the MOV/OUT/IRET handler (H).
void expect_plain_entry(const InterruptRecord& r, unsigned level, unsigned depth, std::uint64_t b,
                        const sc_time& rise) {
    EXPECT_EQ(r.level, level);
    EXPECT_EQ(r.vector, kVectorBase + level);
    EXPECT_EQ(r.handler, kRom + isr_offset(level));
    EXPECT_EQ(r.depth, depth);
    EXPECT_TRUE(r.has_rise);
    EXPECT_TRUE(r.done);
    EXPECT_EQ(r.ir_rise, rise);
    EXPECT_EQ(r.inta1, at_clock(b + kToInta1));
    EXPECT_EQ(r.inta2, at_clock(b + kToInta2));
    EXPECT_EQ(r.first_isr, at_clock(b + kToFirstIsr));
}

void expect_plain_service(const InterruptRecord& r) {
    EXPECT_TRUE(r.has_eoi);
    EXPECT_EQ(r.eoi, r.first_isr + at_clock(kIsrEoi));
    EXPECT_EQ(r.iret_done - r.first_isr, at_clock(kIsrService));
}

constexpr std::uint8_t kOnlyIr3 = 0xF7;

// Wake-up interrupt shared by the cases that run code after an IRET: IR3 rises at t1 while main
// halts (STI; HLT), falls after its INTA. Its IRET resumes main after the HLT at F000:011A (even).
sc_time t1() { return mid_clock(320); }
sc_time t1_fall() { return mid_clock(360); }
constexpr std::uint64_t kB1 = 321; // wake_boundary(t1())
// Return fetch of that IRET: h = B+52, iret_done = h+57.
constexpr std::uint64_t kResume = kB1 + 52 + 57;

Rom main_halt_then(std::initializer_list<std::uint8_t> code, std::uint8_t imr = kOnlyIr3) {
    Rom rom = program(imr);
    const std::uint16_t main = rom.pc;
    rom.sti().hlt().db(code).jmp_short(std::uint16_t(main + 1));
    return rom;
}

} // namespace

// IR3 rises while the CPU halts with IF=1: the wake boundary is the first clock edge after the
// rise (docs/cpu8086.md "HLT"), then (E) and (H).
TEST(ProbeKnownAnswer, InterruptIntoHlt) {
    ASSERT_EQ(wake_boundary(t1()), kB1);
    CpuPic b("board", main_halt_then({0x90}), {{t1(), 3, true}, {t1_fall(), 3, false}});
    sc_start(us(100));
    ASSERT_EQ(b.probe.records().size(), 1u);
    const InterruptRecord& r = b.record(0);
    expect_plain_entry(r, 3, 0, kB1, t1());
    expect_plain_service(r);
    // Latency 321 + 57 - 320.5 = 57.5 clocks; service 52 clocks; resume at 430.
    EXPECT_EQ(r.first_isr - r.ir_rise, ps(57 * kClockPs + kClockPs / 2));
    EXPECT_EQ(r.iret_done, at_clock(kResume));
    EXPECT_EQ(r.service_us(), 52 * 0.125);
}

// A second IR3 rise lands in the NOP run after the first handler returned: (N) puts the
// recognising boundary at resume+36 for a rise in [resume+33, resume+36) clocks.
TEST(ProbeKnownAnswer, InterruptIntoNopRun) {
    Rom rom = program(kOnlyIr3);
    const std::uint16_t main = rom.pc;
    rom.sti().hlt().nop(60).jmp_short(std::uint16_t(main + 1));
    const sc_time t2 = mid_clock(kResume + kNopIdleBoundary - 2);
    CpuPic b("board", rom, {{t1(), 3, true}, {t1_fall(), 3, false}, {t2, 3, true}});
    sc_start(us(100));
    ASSERT_EQ(b.probe.records().size(), 2u);
    expect_plain_entry(b.record(0), 3, 0, kB1, t1());
    EXPECT_EQ(b.record(0).iret_done, at_clock(kResume));
    const std::uint64_t boundary = kResume + kNopIdleBoundary;
    const InterruptRecord& r = b.record(1);
    expect_plain_entry(r, 3, 0, boundary, t2);
    expect_plain_service(r);
    // 1.5 clocks to the boundary + 57: latency 58.5 clocks.
    EXPECT_EQ(r.first_isr - r.ir_rise, ps(58 * kClockPs + kClockPs / 2));
}

// IR3 rises between CLI and STI: it waits for the boundary after the instruction following STI
// (C), and the latency counts from the rise, masked time included.
TEST(ProbeKnownAnswer, RiseWhileInterruptsDisabledCountsFromTheRise) {
    Rom rom = program(kOnlyIr3);
    const std::uint16_t main = rom.pc;
    rom.sti().hlt().cli().nop(2).sti().nop(40).jmp_short(std::uint16_t(main + 1));
    // Rise 10.5 clocks after the return fetch: after CLI's boundary (resume+8), during the NOPs.
    const sc_time t2 = mid_clock(kResume + 10);
    CpuPic b("board", rom, {{t1(), 3, true}, {t1_fall(), 3, false}, {t2, 3, true}});
    sc_start(us(100));
    ASSERT_EQ(b.probe.records().size(), 2u);
    const std::uint64_t boundary = kResume + kAfterStiBoundary;
    const InterruptRecord& r = b.record(1);
    expect_plain_entry(r, 3, 0, boundary, t2);
    expect_plain_service(r);
    // 19 - 10.5 + 57 = 65.5 clocks, of which 8.5 before the interrupt could be recognised.
    EXPECT_EQ(r.first_isr - r.ir_rise, ps(65 * kClockPs + kClockPs / 2));
}

// IR3's handler writes OCW3 (read ISR: an OUT to 0C0h that is no EOI), re-enables interrupts and
// halts, then ends with MOV/OUT/IRET; IR0, higher priority, wakes it: IR0 is recorded at depth 1
// inside IR3's time, its handler is (H), and IR3's handler resumes after the HLT with the tail (T).
// The wake boundary does not depend on the code before the HLT.
TEST(ProbeKnownAnswer, NestedHigherPriorityInterrupt) {
    Rom rom = main_halt_then({0x90}, 0xF6); // IR0 and IR3 unmasked
    const std::uint16_t pc = rom.pc;
    // OCW3 0Bh at 02C0; HLT at 02C5: IR0 returns to 02C6 (even, as (T) assumes).
    rom.org(isr_offset(3)).mov_al(0x0B).out_al(0xC0).sti().hlt().eoi_iret().org(pc);
    const sc_time t0 = mid_clock(480), t0_fall = mid_clock(520);
    CpuPic b("board", rom, {{t1(), 3, true}, {t1_fall(), 3, false}, {t0, 0, true}, {t0_fall, 0, false}});
    sc_start(us(100));
    ASSERT_EQ(b.probe.records().size(), 2u);
    // Records are stored as they complete: the inner one first.
    const InterruptRecord& inner = b.record(0);
    const InterruptRecord& outer = b.record(1);
    const std::uint64_t b0 = wake_boundary(t0);
    expect_plain_entry(inner, 0, 1, b0, t0);
    expect_plain_service(inner);
    EXPECT_EQ(inner.first_isr - inner.ir_rise, ps(57 * kClockPs + kClockPs / 2));
    expect_plain_entry(outer, 3, 0, kB1, t1());
    // IR0's IRET returns into IR3's handler: r0 = IR0's iret_done; IR3's tail per (T).
    const std::uint64_t r0 = b0 + 52 + 57;
    EXPECT_EQ(inner.iret_done, at_clock(r0));
    EXPECT_TRUE(outer.has_eoi);
    EXPECT_EQ(outer.eoi, at_clock(r0 + kTailEoi));
    EXPECT_EQ(outer.iret_done, at_clock(r0 + kTailIretDone));
    // Outer service 481 + 109 + 53 - (321 + 57) = 265 clocks, containing the inner one.
    EXPECT_EQ(outer.iret_done - outer.first_isr, at_clock(265));
    EXPECT_LT(outer.first_isr, inner.ir_rise);
    EXPECT_LT(inner.iret_done, outer.eoi);
}
