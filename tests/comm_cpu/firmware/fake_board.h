// rcsim — a fake board that runs the communication firmware ROM on the plain 8086 core
// (rcsim_cpu8086_core, no SystemC kernel) with small behavioural fakes of the board:
//
// - Uart: an 82510 channel as far as the firmware uses it (docs/firmware.md "82510 register
//   contract"): banks, GIR priorities (timer > Tx machine > Rx machine > Rx FIFO > Tx FIFO), RX
//   FIFO with per-character error flags and its level in FLR, RST error/BREAK bits cleared by
//   reading, TXD capture, the transmitter-idle source, ICM.INTA (INT falls and rises again: a
//   fresh edge while a source is pending), periodic BRGB timer.
// - Pic: an 8259A in single, edge-triggered 8086 mode with rotate-on-non-specific-EOI.
// - DP-RAM left port at D0000 with the IDT7130 mailbox rules; the test plays the main CPU.
//
// Every I/O write is logged (port, value, bank at the time) for the set-up sequence tests.
//
// Why fakes and not the real models (uart82510/, pic8259/, dpram/ on comm_cpu/'s CommBoard):
// - These tests check the firmware against its documented contract (docs/firmware.md), not the
//   chips: a fake that does what the contract says, and no more, makes a firmware that leans on
//   anything else fail here. The real board runs the same ROM in tests/system/ (and the chips
//   have their own tests), so a contract and a model that drift apart fail one of the two.
// - They look where the chips do not: the bank at each write, at INTA and at the EOI; every
//   mailbox word with its time; the RX FIFO's high-water mark; a transmitter that takes no time
//   unless a test gives it one, so a test controls each character's arrival to the cycle.
// - Plain C++ on the core, without a SystemC kernel: each test boots its own board (CTest runs
//   every TEST in a process of its own) and 100 ms of firmware time run in a few ms of wall time.
// The register map and its bits are the model's (uart82510/uart82510.h i82510::, from the
// sources its README lists) and docs/system.md's (the board's map, models/dpram_layout.h).
#pragma once

#include "comm_cpu/i8086/cpu.h"
#include "comm_fw_symbols.h"
#include "models/dpram_layout.h"
#include "models/frame_codec.h"
#include "tests/support/files.h"
#include "uart82510/uart82510.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <deque>
#include <stdexcept>
#include <string>
#include <vector>

namespace fakeboard {

namespace fw = rcsim::comm_fw;
namespace dl = rcsim::dpram_layout;
namespace u = rcsim::i82510;
using rcsim::i8086::Bus;
using rcsim::i8086::cycles_t;

// ---- the communication board (docs/system.md §2, comm_cpu/comm_board.h) --------------------
constexpr cycles_t clk_hz = 8'000'000; // the 8086-2's clock
constexpr cycles_t cycles_per_us = clk_hz / 1'000'000;
constexpr unsigned kPorts = dl::ports;               // 82510 #0..#2 on IR0..IR2
constexpr unsigned kDpramIr = 3;                     // the IDT7130's INT_L on IR3
constexpr std::uint16_t kUartIoBase = 0x80;          // 82510 #n register r at 0x80 + 0x10n + 2r
constexpr std::uint16_t kUartIoStride = 0x10;
constexpr std::uint16_t kUartIoEnd = kUartIoBase + kPorts * kUartIoStride;
constexpr std::uint16_t kPicA0 = 0xC0, kPicA1 = 0xC2; // the 8259A with A0 = 0 and A0 = 1
constexpr std::uint32_t kRamBase = 0x00000, kRamSize = 0x10000;
constexpr std::uint32_t kRomBase = 0xF0000, kRomSize = 0x10000;
constexpr unsigned kRamWaits = 0, kRomWaits = 1, kIoWaits = 1; // wait states per bus cycle
constexpr std::uint32_t kDpramBase = 0xD0000, kDpramSize = 0x400; // IDT7130: 1 KB
/// One 9600 8E1 character (1145.8 us, tests/support/serial_times.h), to the next whole us.
constexpr double kCharUs9600 = 1146.0;

// ---- the 82510 (uart82510/README.md) ---------------------------------------------------------
constexpr std::uint64_t kUartClockHz = 18'432'000;
constexpr unsigned kTimerPrescale = 2;   // clocks per timer count (Uart82510::Config::timer_prescale)
constexpr std::size_t kFifoDepth = 4;    // TX and RX FIFO bytes
constexpr std::uint8_t kBankMask = 0x60; // BANK bits 6:5; GIR reads them back
constexpr std::uint8_t bank_value(unsigned bank) { return std::uint8_t(bank << 5); }
constexpr std::uint8_t kBankNas = bank_value(0), kBankWork = bank_value(1), kBankGen = bank_value(2),
                       kBankModm = bank_value(3);
constexpr std::uint8_t ger_bit(u::Source s) { return std::uint8_t(1u << s); } // GER/GSR bit n: source n
constexpr std::uint8_t kGirNone = 0x01;   // GIR.IP is active low: nothing pending
constexpr std::uint8_t kTimerB = 0x02;    // timer B's bit in TMST (expired), TMCR (STB) and TMIE
constexpr std::uint8_t kFmdTxThreshold = 0x03;
constexpr unsigned kFlrRxShift = 4;       // FLR: TX level in bits 2:0, RX level in bits 6:4

// ---- the 8259A (Intel 8259A data sheet: ICW1, OCW2) ----------------------------------------
constexpr std::uint8_t kIcw1 = 0x10;           // D4 = 1 at A0 = 0: ICW1
constexpr std::uint8_t kOcwSelect = 0x18;      // D4:D3 = 00 at A0 = 0: OCW2
constexpr std::uint8_t kEoi = 0x20;            // OCW2 non-specific EOI
constexpr std::uint8_t kRotateOnEoi = 0xA0;    // OCW2 rotate on non-specific EOI
constexpr std::uint8_t kIcw2VectorMask = 0xF8; // T7..T3; the level is bits 2:0
constexpr int kLevels = 8, kSpuriousLevel = 7; // no request left at INTA: IR7's vector

struct IoWrite {
    std::uint16_t port;
    std::uint8_t value;
    std::uint8_t bank; // 82510 bank selected before the write (0 for the PIC)
};

struct Uart {
    std::uint8_t bank = 0, lcr = 0, ger = 0, tmie = 0, rst = 0, mcr = 0;
    std::uint16_t bbl = 0, bbh = 0, bal = 0, bah = 0;
    std::deque<std::uint8_t> rx;
    std::deque<std::uint8_t> rx_flags; // RST bits (PE/FE) that come with each character
    std::vector<std::uint8_t> tx;        // bytes that left the transmitter (the host has them)
    std::vector<cycles_t> tx_at;         // when each of them was complete (never cleared)
    // Transmitter: instantaneous unless tx_char_cycles > 0; then a 4-byte FIFO and a shifter
    // that takes tx_char_cycles per character.
    cycles_t tx_char_cycles = 0;
    std::deque<std::uint8_t> tx_fifo;
    bool tx_busy = false;
    std::uint8_t tx_shift = 0;
    cycles_t tx_done_at = 0;
    unsigned tx_overflows = 0;
    std::uint8_t fmd = 0;
    bool timer_armed = false, timer_expired = false;
    cycles_t timer_due = 0;
    unsigned resets = 0, rx_flushes = 0, timer_starts = 0;

    bool dlab() const { return lcr & u::LCR_DLAB; }
    bool enabled(u::Source s) const { return ger & ger_bit(s); }
    /// GIR's bits 3:1, the highest pending enabled source (timer > Tx machine > Rx machine > Rx
    /// FIFO > Tx FIFO), or kGirNone.
    std::uint8_t vector() const {
        if (timer_expired && enabled(u::timer) && (tmie & kTimerB)) return u::vector_of(u::timer);
        if (enabled(u::tx_machine) && tx_idle()) return u::vector_of(u::tx_machine);
        if (rst && enabled(u::rx_machine)) return u::vector_of(u::rx_machine);
        if (!rx.empty() && enabled(u::rx_fifo)) return u::vector_of(u::rx_fifo);
        if (enabled(u::tx_fifo) && tx_fifo.size() <= (fmd & kFmdTxThreshold)) return u::vector_of(u::tx_fifo);
        return kGirNone;
    }
    void put_tx(std::uint8_t v, cycles_t now) {
        if (tx_char_cycles == 0) {
            tx.push_back(v);
            tx_at.push_back(now);
        } else if (tx_fifo.size() < kFifoDepth) {
            tx_fifo.push_back(v);
            tick(now);
        } else {
            ++tx_overflows;
        }
    }
    bool irq() const { return !(vector() & kGirNone); }
    /// Transmitter idle: FIFO empty and the last stop bit sent (always, when instantaneous).
    bool tx_idle() const { return tx_fifo.empty() && !tx_busy; }
    bool inta_pulse = false; // ICM.INTA written: INT low for a moment
    unsigned intas = 0;

    std::size_t rx_high = 0; // RX FIFO high-water mark (a real 82510 holds kFifoDepth)
    void receive(std::uint8_t c, std::uint8_t err = 0) {
        rx.push_back(c);
        rx_high = std::max(rx_high, rx.size());
        rx_flags.push_back(err);
        if (rx.size() == 1) rst |= err;
    }
    void soft_reset() {
        bank = kBankNas;
        tx_fifo.clear();
        fmd = 0;
        lcr = ger = tmie = rst = 0;
        rx.clear();
        rx_flags.clear();
        timer_armed = timer_expired = false;
        ++resets;
    }
    std::uint8_t rx_ready() const { return rx.empty() ? 0 : u::RST_RFIR; } // LSR.DR, RST.RFIR

    std::uint8_t read(unsigned r) {
        if (r == u::GIR) return std::uint8_t(vector() | bank);
        switch (bank) {
        case kBankNas:
            // LSR: 8250 layout, its error bits where RST has them; the transmitter always empty
            if (r == u::LSR) return std::uint8_t(rx_ready() | rst | u::LSR_TFST | u::LSR_TXST);
            if (r == u::LCR) return lcr;
            return 0;
        case kBankWork:
            if (r == u::RXD) {
                if (rx.empty()) return 0;
                const std::uint8_t c = rx.front();
                rx.pop_front();
                rx_flags.pop_front();
                if (!rx_flags.empty()) rst |= rx_flags.front();
                return c;
            }
            if (r == u::TMST) { // read clears the expired bit
                const std::uint8_t v = timer_expired ? kTimerB : 0x00;
                timer_expired = false;
                return v;
            }
            if (r == u::FLR)
                return std::uint8_t(tx_fifo.size() | (std::min<std::size_t>(rx.size(), kFifoDepth) << kFlrRxShift));
            if (r == u::RST) { // read clears
                const std::uint8_t v = std::uint8_t(rst | rx_ready());
                rst = 0;
                return v;
            }
            return 0;
        default:
            return 0;
        }
    }

    void write(unsigned r, std::uint8_t v, cycles_t now) {
        if (r == u::BANK) {
            bank = v & kBankMask;
            return;
        }
        switch (bank) {
        case kBankNas:
            if (r == u::TXD) {
                if (dlab()) bal = v;
                else put_tx(v, now);
            }
            if (r == u::GER) {
                if (dlab()) bah = v;
                else ger = v;
            }
            if (r == u::LCR) lcr = v;
            if (r == u::MCR) mcr = v;
            break;
        case kBankWork:
            if (r == u::TXD) put_tx(v, now);
            if (r == u::TMCR && (v & kTimerB)) { // STB: load BRGB and start a fresh period
                timer_armed = true;
                timer_due = now + period();
                ++timer_starts;
            }
            if (r == u::RCM && (v & u::RCM_FRF)) {
                rx.clear();
                rx_flags.clear();
                ++rx_flushes;
            }
            if (r == u::ICM && (v & u::ICM_RESET)) soft_reset();
            if (r == u::ICM && (v & u::ICM_INTA)) {
                inta_pulse = true;
                ++intas;
            }
            break;
        case kBankGen:
            if (r == u::FMD) fmd = v;
            break;
        case kBankModm:
            if (r == u::BBL && dlab()) bbl = v;
            if (r == u::BBH && dlab()) bbh = v;
            if (r == u::TMIE) tmie = v;
            break;
        default:
            break;
        }
    }

    // BRGB timer: divisor x kTimerPrescale clocks of 18.432 MHz per period, auto-reload (as uart82510/)
    cycles_t period() const { return cycles_t(bbl | (bbh << 8)) * kTimerPrescale * clk_hz / kUartClockHz; }
    void tick(cycles_t now) {
        if (timer_armed && now >= timer_due) {
            timer_due += period();
            timer_expired = true;
        }
        for (;;) {
            cycles_t start = now;
            if (tx_busy) {
                if (now < tx_done_at) break;
                tx.push_back(tx_shift);
                tx_at.push_back(tx_done_at);
                tx_busy = false;
                start = tx_done_at; // the next character follows back to back
            }
            if (tx_fifo.empty()) break;
            tx_shift = tx_fifo.front();
            tx_fifo.pop_front();
            tx_busy = true;
            tx_done_at = start + tx_char_cycles;
        }
    }
};

struct Pic {
    std::uint8_t irr = 0, isr = 0, imr = 0xFF, base = 0, icw4 = 0;
    int init_step = 0;                  // 1: expect ICW2, 2: expect ICW4
    int lowest = kLevels - 1;           // rotating priority: lowest + 1 is the highest
    std::array<bool, kLevels> prev{};
    unsigned eois = 0, spurious = 0;

    void line(int n, bool level) {
        if (level && !prev[n]) irr |= std::uint8_t(1 << n);
        prev[n] = level;
    }
    int highest(std::uint8_t set) const {
        for (int i = 1; i <= kLevels; ++i) {
            const int l = (lowest + i) % kLevels;
            if (set & (1 << l)) return l;
        }
        return -1;
    }
    int rank(int level) const { return (level - lowest - 1 + kLevels) % kLevels; }
    bool intr() const {
        const int r = highest(std::uint8_t(irr & ~imr));
        if (r < 0) return false;
        const int s = highest(isr);
        return s < 0 || rank(r) < rank(s);
    }
    std::uint8_t acknowledge() { // both INTA cycles at once
        const int r = highest(std::uint8_t(irr & ~imr));
        if (r < 0) {
            ++spurious;
            return std::uint8_t(base | kSpuriousLevel);
        }
        irr &= std::uint8_t(~(1 << r));
        isr |= std::uint8_t(1 << r);
        return std::uint8_t(base | r);
    }
    void write(bool a0, std::uint8_t v) {
        if (!a0) {
            if (v & kIcw1) {
                init_step = 1;
                imr = 0;
                isr = irr = 0;
                lowest = kLevels - 1;
                prev.fill(false);
            } else if ((v & kOcwSelect) == 0) { // OCW2
                if (v == kRotateOnEoi || v == kEoi) {
                    const int s = highest(isr);
                    if (s >= 0) {
                        isr &= std::uint8_t(~(1 << s));
                        if (v == kRotateOnEoi) lowest = s;
                    }
                    ++eois;
                }
            }
            return;
        }
        if (init_step == 1) {
            base = v & kIcw2VectorMask;
            init_step = 2;
        } else if (init_step == 2) {
            icw4 = v;
            init_step = 0;
        } else {
            imr = v;
        }
    }
};

/// One interrupt as the fake board saw it.
struct IrqRecord {
    std::uint8_t vector;
    cycles_t inta;
    std::uint8_t bank_at_entry; // bank of the interrupting 82510 at INTA
    std::uint8_t bank_at_eoi;   // and when the ISR wrote the EOI
    bool eoi_seen = false;
    cycles_t eoi_at = 0;        // when the ISR wrote the EOI
};

class FakeBoard : public rcsim::i8086::BusHandler {
public:
    std::vector<std::uint8_t> rom, ram, dp;
    std::array<Uart, kPorts> uart;
    Pic pic;
    bool int_l = false, int_r = false;
    std::vector<std::uint8_t> posted; // words the firmware wrote to int2rbt
    std::vector<cycles_t> posted_at;  // when (all of them, never consumed)
    cycles_t int2ext_read_at = 0;     // last firmware read of int2ext
    std::vector<IoWrite> io_writes;
    std::vector<IrqRecord> irqs;
    rcsim::i8086::Cpu cpu;

    explicit FakeBoard(const std::string& rom_path = RCSIM_COMM_FW_ROM)
        : rom(rcsim::test::slurp_bytes(rom_path)), ram(kRamSize, 0), dp(kDpramSize, 0) {
        if (rom.size() != kRomSize) throw std::runtime_error("ROM image missing or not 64 KB: " + rom_path);
        cpu.map_memory(rcsim::MemRegion{"ram", kRamBase, kRamSize, ram.data(), kRamWaits, true});
        cpu.map_memory(rcsim::MemRegion{"rom", kRomBase, kRomSize, rom.data(), kRomWaits, false});
        cpu.set_bus_handler(this);
        cpu.reset();
    }

    // ---- time -------------------------------------------------------------------------
    /// The core runs this many clocks (5 us) between two looks of the fakes at the time: a timer
    /// expiry or a character's end is seen at most that late.
    static constexpr cycles_t kSliceCycles = 40;
    /// run_until() checks its condition this often (25 us).
    static constexpr cycles_t kPollCycles = 200;
    cycles_t now() const { return cpu.cycles(); }
    void run_cycles(cycles_t n) {
        const cycles_t end = cpu.cycles() + n;
        while (cpu.cycles() < end) {
            for (auto& chip : uart) chip.tick(cpu.cycles());
            update_lines();
            cpu.run_until(std::min(end, cpu.cycles() + kSliceCycles));
        }
    }
    void run_us(double us) { run_cycles(cycles_t(us * cycles_per_us)); }
    void run_ms(double ms) { run_us(ms * 1000.0); }
    /// Runs until `pred` holds or `ms` pass; returns whether it held.
    template <typename Pred> bool run_until(Pred pred, double ms) {
        const cycles_t end = cpu.cycles() + cycles_t(ms * 1000.0 * cycles_per_us);
        while (cpu.cycles() < end) {
            if (pred()) return true;
            run_cycles(kPollCycles);
        }
        return pred();
    }

    // ---- the firmware's variables ------------------------------------------------------
    std::uint8_t var8(std::uint32_t linear, unsigned index = 0) const { return ram.at(linear + index); }
    std::uint16_t var16(std::uint32_t linear, unsigned index = 0) const {
        return std::uint16_t(ram.at(linear + 2 * index) | (ram.at(linear + 2 * index + 1) << 8));
    }
    std::uint8_t step(unsigned port) const { return var8(fw::data::step, port); }

    // ---- the host side -----------------------------------------------------------------
    /// One character arriving at 82510 #port (with RST error bits, e.g. RST_PE).
    void host_byte(unsigned port, std::uint8_t c, std::uint8_t err = 0) {
        uart[port].receive(c, err);
        update_lines();
    }
    /// Characters one per `char_us` (by default one 9600 bps 8E1 character).
    void host_send(unsigned port, const std::string& bytes, double char_us = kCharUs9600) {
        for (unsigned char c : bytes) {
            host_byte(port, c);
            run_us(char_us);
        }
    }
    void host_break(unsigned port) {
        uart[port].rst |= u::RST_BKD;
        update_lines();
    }
    /// Bytes the firmware sent to the host on `port` since the last call.
    std::string host_take(unsigned port) {
        std::string s(uart[port].tx.begin(), uart[port].tx.end());
        uart[port].tx.clear();
        return s;
    }

    // ---- the main CPU side -------------------------------------------------------------
    static constexpr unsigned area = dl::area_size, chunk = dl::chunk_size;
    std::uint8_t pflag(unsigned p) const { return dp[dl::pflag_addr(p)]; }
    /// The main CPU writes a mailbox word (raises INT_L).
    void main_word(std::uint8_t w) {
        dp[dl::int2ext] = w;
        int_l = true;
        update_lines();
    }
    /// Takes the oldest posted word, if any (as the main CPU's INT_R handler would), and
    /// empties int2rbt as docs/firmware.md recommends (unless main_clears_int2rbt is false).
    bool main_clears_int2rbt = true;
    bool main_take_word(std::uint8_t& w) {
        if (posted.empty()) return false;
        w = posted.front();
        posted.erase(posted.begin());
        int_r = false;
        if (main_clears_int2rbt) dp[dl::int2rbt] = 0;
        return true;
    }
    /// Copies chunk p out of DP-RAM the way the main CPU does (up to ETX or a whole chunk).
    std::string main_read_chunk(unsigned p) const {
        std::string s;
        for (unsigned i = 0; i < chunk; ++i) {
            s += char(dp[dl::data_addr(p) + i]);
            if (dp[dl::data_addr(p) + i] == rcsim::proto::ETX) break;
        }
        return s;
    }
    /// Writes one chunk of a frame for the host into data[p] and sends 0x1p.
    void main_write_chunk(unsigned p, const std::string& bytes, bool first) {
        if (first) dp[dl::pflag_addr(p)] = dl::pflag_rbt_use;
        for (std::size_t i = 0; i < bytes.size(); ++i) dp[dl::data_addr(p) + i] = std::uint8_t(bytes[i]);
        main_word(dl::word(dl::kind_chunk, p));
    }

    // ---- BusHandler --------------------------------------------------------------------
    unsigned bus_access(Bus kind, std::uint32_t address, std::uint16_t& data, unsigned width,
                        cycles_t start) override {
        (void)width;
        unsigned waits = 0;
        switch (kind) {
        case Bus::io_read:
            data = io_read(std::uint16_t(address));
            waits = kIoWaits;
            break;
        case Bus::io_write:
            io_write(std::uint16_t(address), std::uint8_t(data), start);
            waits = kIoWaits;
            break;
        case Bus::mem_read:
            if (in_dpram(address)) {
                const unsigned a = address - kDpramBase;
                data = dp[a];
                if (a == dl::int2ext) {
                    int_l = false;
                    int2ext_read_at = start;
                }
            } else {
                data = 0xFFFF; // open bus
            }
            break;
        case Bus::mem_write:
            if (in_dpram(address)) {
                const unsigned a = address - kDpramBase;
                dp[a] = std::uint8_t(data);
                if (a == dl::int2rbt) {
                    int_r = true;
                    posted.push_back(std::uint8_t(data));
                    posted_at.push_back(start);
                }
            }
            break;
        case Bus::int_ack:
            // the core runs two INTA cycles; the PIC acknowledges on the first, drives on the second
            if (!inta_second_) {
                inta_vector_ = pic.acknowledge();
                irqs.push_back(IrqRecord{inta_vector_, start, uart_bank_of(inta_vector_), 0, false});
                inta_second_ = true;
                data = 0xFF; // the first INTA cycle drives nothing
            } else {
                data = inta_vector_;
                inta_second_ = false;
            }
            break;
        default:
            break;
        }
        update_lines();
        return waits;
    }

private:
    bool inta_second_ = false;
    std::uint8_t inta_vector_ = 0;

    static bool in_dpram(std::uint32_t address) { return address >= kDpramBase && address < kDpramBase + kDpramSize; }
    /// The 82510 register at I/O `port` (the odd addresses, the upper byte lane, decode nothing).
    static bool is_uart(std::uint16_t port) { return port >= kUartIoBase && port < kUartIoEnd && !(port & 1); }
    static unsigned uart_of(std::uint16_t port) { return (port - kUartIoBase) / kUartIoStride; }
    static unsigned register_of(std::uint16_t port) { return (port % kUartIoStride) >> 1; }
    /// The bank of the 82510 behind an interrupt vector's level (0 for a level that is none).
    std::uint8_t uart_bank_of(std::uint8_t vector) const {
        const unsigned level = vector & ~kIcw2VectorMask;
        return level < kPorts ? uart[level].bank : std::uint8_t(0);
    }

    void update_lines() {
        for (unsigned i = 0; i < kPorts; ++i) {
            if (uart[i].inta_pulse) {
                pic.line(int(i), false);
                uart[i].inta_pulse = false;
            }
            pic.line(int(i), uart[i].irq());
        }
        pic.line(kDpramIr, int_l);
        cpu.set_intr(pic.intr());
    }
    std::uint8_t io_read(std::uint16_t port) {
        if (is_uart(port)) return uart[uart_of(port)].read(register_of(port));
        if (port == kPicA0) return pic.irr;
        if (port == kPicA1) return pic.imr;
        return 0xFF; // open bus
    }
    void io_write(std::uint16_t port, std::uint8_t v, cycles_t now) {
        if (is_uart(port)) {
            Uart& chip = uart[uart_of(port)];
            io_writes.push_back(IoWrite{port, v, chip.bank});
            chip.write(register_of(port), v, now);
            return;
        }
        io_writes.push_back(IoWrite{port, v, 0});
        if (port == kPicA0 || port == kPicA1) {
            if (port == kPicA0 && (v == kRotateOnEoi || v == kEoi) && !irqs.empty() && !irqs.back().eoi_seen) {
                // the EOI of the most recent interrupt (RS-232 ISRs do not nest)
                IrqRecord& r = irqs.back();
                r.bank_at_eoi = uart_bank_of(r.vector);
                r.eoi_seen = true;
                r.eoi_at = now;
            }
            pic.write(port == kPicA1, v);
        }
    }
};

} // namespace fakeboard
