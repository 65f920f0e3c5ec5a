// rcsim — a bench that runs the communication firmware ROM on the plain 8086 core
// (rcsim_cpu8086_core, no SystemC) with small behavioural fakes of the board:
//
// - Uart: an 82510 channel as far as the firmware uses it (docs/firmware.md "82510 register
//   contract"): banks, GIR priorities (timer > Tx machine > Rx machine > Rx FIFO > Tx FIFO), RX
//   FIFO with per-character error flags and its level in FLR, RST error/BREAK bits cleared by
//   reading, TXD capture, the transmitter-idle source, ICM.INTA (INT falls and rises again: a
//   fresh edge while a source is pending), periodic BRGB timer.
//   It exists to test the firmware's logic against that contract; the real model is uart82510/.
// - Pic: an 8259A in single, edge-triggered 8086 mode with rotate-on-non-specific-EOI.
// - DP-RAM left port at D0000 with the IDT7130 mailbox rules; the test plays the main CPU.
//
// Every I/O write is logged (port, value, bank at the time) for the set-up sequence tests.
#pragma once

#include "comm_cpu/i8086/cpu.h"
#include "comm_fw_symbols.h"
#include "tests/support/files.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <deque>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace fakeboard {

namespace fw = rcsim::comm_fw;
using rcsim::i8086::Bus;
using rcsim::i8086::cycles_t;

constexpr cycles_t clk_hz = 8'000'000;
constexpr cycles_t cycles_per_us = clk_hz / 1'000'000;

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

    bool dlab() const { return lcr & 0x80; }
    std::uint8_t vector() const {
        if (timer_expired && (ger & 0x20) && (tmie & 0x02)) return 0x0A;
        if ((ger & 0x10) && tx_idle()) return 0x08;
        if (rst && (ger & 0x04)) return 0x06;
        if (!rx.empty() && (ger & 0x01)) return 0x04;
        if ((ger & 0x02) && tx_fifo.size() <= (fmd & 3u)) return 0x02;
        return 0x01;
    }
    void put_tx(std::uint8_t v, cycles_t now) {
        if (tx_char_cycles == 0) {
            tx.push_back(v);
            tx_at.push_back(now);
        } else if (tx_fifo.size() < 4) {
            tx_fifo.push_back(v);
            tick(now);
        } else {
            ++tx_overflows;
        }
    }
    bool irq() const { return !(vector() & 1); }
    /// Transmitter idle: FIFO empty and the last stop bit sent (always, when instantaneous).
    bool tx_idle() const { return tx_fifo.empty() && !tx_busy; }
    bool inta_pulse = false; // ICM.INTA written: INT low for a moment
    unsigned intas = 0;

    std::size_t rx_high = 0; // RX FIFO high-water mark (a real 82510 holds 4)
    void receive(std::uint8_t c, std::uint8_t err = 0) {
        rx.push_back(c);
        rx_high = std::max(rx_high, rx.size());
        rx_flags.push_back(err);
        if (rx.size() == 1) rst |= err;
    }
    void soft_reset() {
        bank = 0;
        tx_fifo.clear();
        fmd = 0;
        lcr = ger = tmie = rst = 0;
        rx.clear();
        rx_flags.clear();
        timer_armed = timer_expired = false;
        ++resets;
    }

    std::uint8_t read(unsigned r) {
        if (r == 2) return std::uint8_t(vector() | bank);
        switch (bank) {
        case 0x00:
            if (r == 5) return std::uint8_t((rx.empty() ? 0 : 1) | rst | 0x60);
            if (r == 3) return lcr;
            return 0;
        case 0x20:
            if (r == 0) { // RXD
                if (rx.empty()) return 0;
                const std::uint8_t c = rx.front();
                rx.pop_front();
                rx_flags.pop_front();
                if (!rx_flags.empty()) rst |= rx_flags.front();
                return c;
            }
            if (r == 3) { // TMST
                const std::uint8_t v = timer_expired ? 0x02 : 0x00;
                timer_expired = false;
                return v;
            }
            if (r == 4) return std::uint8_t(tx_fifo.size() | (std::min<std::size_t>(rx.size(), 4) << 4)); // FLR
            if (r == 5) {         // RST: read clears
                const std::uint8_t v = std::uint8_t(rst | (rx.empty() ? 0 : 1));
                rst = 0;
                return v;
            }
            return 0;
        default:
            return 0;
        }
    }

    void write(unsigned r, std::uint8_t v, cycles_t now) {
        if (r == 2) {
            bank = v & 0x60;
            return;
        }
        switch (bank) {
        case 0x00:
            if (r == 0) {
                if (dlab()) bal = v;
                else put_tx(v, now);
            }
            if (r == 1) {
                if (dlab()) bah = v;
                else ger = v;
            }
            if (r == 3) lcr = v;
            if (r == 4) mcr = v;
            break;
        case 0x20:
            if (r == 0) put_tx(v, now);
            if (r == 3 && (v & 0x02)) { // TMCR STB: load BRGB and start a fresh period
                timer_armed = true;
                timer_due = now + period();
                ++timer_starts;
            }
            if (r == 5 && (v & 0x10)) { // RCM FRF
                rx.clear();
                rx_flags.clear();
                ++rx_flushes;
            }
            if (r == 7 && (v & 0x10)) soft_reset();
            if (r == 7 && (v & 0x08)) {
                inta_pulse = true;
                ++intas;
            }
            break;
        case 0x40:
            if (r == 1) fmd = v;
            break;
        case 0x60:
            if (r == 0 && dlab()) bbl = v;
            if (r == 1 && dlab()) bbh = v;
            if (r == 6) tmie = v;
            break;
        default:
            break;
        }
    }

    // BRGB timer: divisor x 2 clocks of 18.432 MHz per period, auto-reload (as uart82510/)
    cycles_t period() const { return cycles_t(bbl | (bbh << 8)) * clk_hz / 9'216'000; }
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
    int init_step = 0; // 1: expect ICW2, 2: expect ICW4
    int lowest = 7;    // rotating priority: lowest + 1 is the highest
    std::array<bool, 8> prev{};
    unsigned eois = 0, spurious = 0;

    void line(int n, bool level) {
        if (level && !prev[n]) irr |= std::uint8_t(1 << n);
        prev[n] = level;
    }
    int highest(std::uint8_t set) const {
        for (int i = 1; i <= 8; ++i) {
            const int l = (lowest + i) & 7;
            if (set & (1 << l)) return l;
        }
        return -1;
    }
    int rank(int level) const { return (level - lowest - 1) & 7; }
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
            return std::uint8_t(base | 7);
        }
        irr &= std::uint8_t(~(1 << r));
        isr |= std::uint8_t(1 << r);
        return std::uint8_t(base | r);
    }
    void write(bool a0, std::uint8_t v) {
        if (!a0) {
            if (v & 0x10) { // ICW1
                init_step = 1;
                imr = 0;
                isr = irr = 0;
                lowest = 7;
                prev.fill(false);
            } else if ((v & 0x18) == 0) { // OCW2
                if (v == 0xA0 || v == 0x20) {
                    const int s = highest(isr);
                    if (s >= 0) {
                        isr &= std::uint8_t(~(1 << s));
                        if (v == 0xA0) lowest = s;
                    }
                    ++eois;
                }
            }
            return;
        }
        if (init_step == 1) {
            base = v & 0xF8;
            init_step = 2;
        } else if (init_step == 2) {
            icw4 = v;
            init_step = 0;
        } else {
            imr = v;
        }
    }
};

/// One interrupt as the bench saw it.
struct IrqRecord {
    std::uint8_t vector;
    cycles_t inta;
    std::uint8_t bank_at_entry; // bank of the interrupting 82510 at INTA
    std::uint8_t bank_at_eoi;   // and when the ISR wrote the EOI
    bool eoi_seen = false;
};

class FakeBoard : public rcsim::i8086::BusHandler {
public:
    std::vector<std::uint8_t> rom, ram, dp;
    std::array<Uart, 3> uart;
    Pic pic;
    bool int_l = false, int_r = false;
    std::vector<std::uint8_t> posted; // words the firmware wrote to int2rbt
    std::vector<cycles_t> posted_at;  // when (all of them, never consumed)
    cycles_t int2ext_read_at = 0;     // last firmware read of int2ext
    std::vector<IoWrite> io_writes;
    std::vector<IrqRecord> irqs;
    rcsim::i8086::Cpu cpu;

    explicit FakeBoard(const std::string& rom_path = RCSIM_COMM_FW_ROM)
        : rom(rcsim::test::slurp_bytes(rom_path)), ram(0x10000, 0), dp(0x400, 0) {
        if (rom.size() != 0x10000) throw std::runtime_error("ROM image missing or not 64 KB: " + rom_path);
        cpu.map_memory(rcsim::MemRegion{"ram", 0x00000, 0x10000, ram.data(), 0, true});
        cpu.map_memory(rcsim::MemRegion{"rom", 0xF0000, 0x10000, rom.data(), 1, false});
        cpu.set_bus_handler(this);
        cpu.reset();
    }

    // ---- time -------------------------------------------------------------------------
    cycles_t now() const { return cpu.cycles(); }
    void run_cycles(cycles_t n) {
        const cycles_t end = cpu.cycles() + n;
        while (cpu.cycles() < end) {
            for (auto& u : uart) u.tick(cpu.cycles());
            update_lines();
            cpu.run_until(std::min(end, cpu.cycles() + 40));
        }
    }
    void run_us(double us) { run_cycles(cycles_t(us * cycles_per_us)); }
    void run_ms(double ms) { run_us(ms * 1000.0); }
    /// Runs until `pred` holds or `ms` pass; returns whether it held.
    template <typename Pred> bool run_until(Pred pred, double ms) {
        const cycles_t end = cpu.cycles() + cycles_t(ms * 1000.0 * cycles_per_us);
        while (cpu.cycles() < end) {
            if (pred()) return true;
            run_cycles(200);
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
    /// One character arriving at 82510 #port (with RST error bits, e.g. 0x04 parity).
    void host_byte(unsigned port, std::uint8_t c, std::uint8_t err = 0) {
        uart[port].receive(c, err);
        update_lines();
    }
    /// Characters one per `char_us` (1146 us = 9600 bps 8E1).
    void host_send(unsigned port, const std::string& bytes, double char_us = 1146.0) {
        for (unsigned char c : bytes) {
            host_byte(port, c);
            run_us(char_us);
        }
    }
    void host_break(unsigned port) {
        uart[port].rst |= 0x10;
        update_lines();
    }
    /// Bytes the firmware sent to the host on `port` since the last call.
    std::string host_take(unsigned port) {
        std::string s(uart[port].tx.begin(), uart[port].tx.end());
        uart[port].tx.clear();
        return s;
    }

    // ---- the main CPU side -------------------------------------------------------------
    static constexpr unsigned area = 340, chunk = 339;
    std::uint8_t pflag(unsigned p) const { return dp[p * area + chunk]; }
    /// The main CPU writes a mailbox word (raises INT_L).
    void main_word(std::uint8_t w) {
        dp[0x3FE] = w;
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
        if (main_clears_int2rbt) dp[0x3FF] = 0;
        return true;
    }
    /// Copies chunk p out of DP-RAM the way the main CPU does (up to ETX or 339 bytes).
    std::string main_read_chunk(unsigned p) const {
        std::string s;
        for (unsigned i = 0; i < chunk; ++i) {
            s += char(dp[p * area + i]);
            if (dp[p * area + i] == 0x03) break;
        }
        return s;
    }
    /// Writes one chunk of a frame for the host into data[p] and sends 0x1p.
    void main_write_chunk(unsigned p, const std::string& bytes, bool first) {
        if (first) dp[p * area + chunk] = 2; // RBT_USE
        for (std::size_t i = 0; i < bytes.size(); ++i) dp[p * area + i] = std::uint8_t(bytes[i]);
        main_word(std::uint8_t(0x10 | p));
    }

    // ---- BusHandler --------------------------------------------------------------------
    unsigned bus_access(Bus kind, std::uint32_t address, std::uint16_t& data, unsigned width,
                        cycles_t start) override {
        (void)width;
        unsigned waits = 0;
        switch (kind) {
        case Bus::io_read:
            data = io_read(std::uint16_t(address));
            waits = 1;
            break;
        case Bus::io_write:
            io_write(std::uint16_t(address), std::uint8_t(data), start);
            waits = 1;
            break;
        case Bus::mem_read:
            if (address >= 0xD0000 && address < 0xD0400) {
                const unsigned a = address - 0xD0000;
                data = dp[a];
                if (a == 0x3FE) {
                    int_l = false;
                    int2ext_read_at = start;
                }
            } else {
                data = 0xFFFF;
            }
            break;
        case Bus::mem_write:
            if (address >= 0xD0000 && address < 0xD0400) {
                const unsigned a = address - 0xD0000;
                dp[a] = std::uint8_t(data);
                if (a == 0x3FF) {
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
                const unsigned level = inta_vector_ & 7;
                irqs.push_back(IrqRecord{inta_vector_, start, level < 3 ? uart[level].bank : std::uint8_t(0),
                                         0, false});
                inta_second_ = true;
                data = 0xFF;
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

    void update_lines() {
        for (int i = 0; i < 3; ++i) {
            if (uart[i].inta_pulse) {
                pic.line(i, false);
                uart[i].inta_pulse = false;
            }
            pic.line(i, uart[i].irq());
        }
        pic.line(3, int_l);
        cpu.set_intr(pic.intr());
    }
    std::uint8_t io_read(std::uint16_t port) {
        if (port >= 0x80 && port < 0xB0 && !(port & 1)) return uart[(port - 0x80) >> 4].read((port & 0x0F) >> 1);
        if (port == 0xC0) return pic.irr;
        if (port == 0xC2) return pic.imr;
        return 0xFF;
    }
    void io_write(std::uint16_t port, std::uint8_t v, cycles_t now) {
        if (port >= 0x80 && port < 0xB0 && !(port & 1)) {
            Uart& u = uart[(port - 0x80) >> 4];
            io_writes.push_back(IoWrite{port, v, u.bank});
            u.write((port & 0x0F) >> 1, v, now);
            return;
        }
        io_writes.push_back(IoWrite{port, v, 0});
        if (port == 0xC0 || port == 0xC2) {
            if (port == 0xC0 && (v == 0xA0 || v == 0x20) && !irqs.empty() && !irqs.back().eoi_seen) {
                // the EOI of the most recent interrupt (RS-232 ISRs do not nest)
                IrqRecord& r = irqs.back();
                const unsigned level = r.vector & 7;
                r.bank_at_eoi = level < 3 ? uart[level].bank : 0;
                r.eoi_seen = true;
            }
            pic.write(port == 0xC2, v);
        }
    }
};

} // namespace fakeboard
