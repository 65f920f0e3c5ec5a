// The set-up of the Intel 82510 tests (uart82510_test.cpp: registers and interrupts;
// uart82510_serial_test.cpp: transmit, receive, timing, two 82510s, BREAK): the CPU's register
// access over the bus, the host at the far end of the line, and one 82510 wired to both.
#pragma once

#include "uart82510/uart82510.h"

#include "models/bus.h"
#include "models/clock.h"
#include "tests/support/sc_test.h"
#include "tests/support/serial_times.h"

#include <tlm_utils/simple_initiator_socket.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace rcsim::test::uart {

using namespace rcsim::i82510;
using sc_core::sc_time;

/// Register access through the TLM socket, as the CPU does (register r at I/O offset 2r).
struct Cpu : sc_core::sc_module {
    tlm_utils::simple_initiator_socket<Cpu> sock{"sock"};
    explicit Cpu(sc_core::sc_module_name n) : sc_module(n) {}
    std::uint8_t rd(unsigned off) {
        std::uint8_t d = 0;
        const BusResult r = bus_access(sock, BusCycle::io_read, off * 2, &d, 1, sc_core::sc_time_stamp());
        EXPECT_TRUE(r.ok());
        EXPECT_EQ(r.wait_states, 0u);
        return d;
    }
    void wr(unsigned off, std::uint8_t v) {
        const BusResult r = bus_access(sock, BusCycle::io_write, off * 2, &v, 1, sc_core::sc_time_stamp());
        EXPECT_TRUE(r.ok());
    }
    void bank(unsigned b) { wr(BANK, static_cast<std::uint8_t>(b << 5)); }
    /// 9600 bps (divisor 60 at 18.432 MHz), 8 data, even parity, 1 stop: the project's format.
    void setup_9600_8e1() {
        bank(0);
        wr(LCR, LCR_DLAB);
        wr(BAL, 60);
        wr(BAH, 0);
        wr(LCR, 0x1B);
    }
    /// Timer B as a timer of ~1 us (divisor 9 x 2 clocks at 18.432 MHz is ~0.98 us; BBCF's reset
    /// value selects timer mode) with its interrupt enabled in TMIE; left in bank 3.
    void timer_b_1us() {
        bank(0);
        wr(LCR, LCR_DLAB | 0x1B); // DLAB: offsets 0 and 1 of bank 3 are BBL and BBH
        bank(3);
        wr(BBL, 9);
        wr(BBH, 0);
        bank(0);
        wr(LCR, 0x1B);
        bank(3);
        wr(TMIE, 0x02);
    }
};

/// The far end of the line: records what it receives, sends when told.
struct Host : SerialEndpoint {
    SerialFormat fmt = SerialFormat::rs232(9600);
    SerialLine& line;
    std::vector<SerialRx> got;
    std::vector<std::pair<sc_time, bool>> breaks;
    explicit Host(SerialLine& l) : line(l) { line.attach(SerialLine::b, *this); }
    SerialFormat rx_format() const override { return fmt; }
    void rx_char(const SerialRx& c) override { got.push_back(c); }
    void rx_break(bool on) override { breaks.emplace_back(sc_core::sc_time_stamp(), on); }
    /// Sends `bytes` back to back (call from a thread).
    void send(const std::string& bytes) {
        for (char c : bytes) {
            line.transmit(SerialLine::b, SerialWord::encode(static_cast<std::uint8_t>(c), fmt));
            sc_core::wait(fmt.frame_time());
        }
    }
    std::string text() const {
        std::string s;
        for (const auto& c : got) s += static_cast<char>(c.data);
        return s;
    }
};

struct UartOnLine {
    Uart82510 uart;
    Cpu cpu{"cpu"};
    IrqLine irq{"irq"};
    SerialLine line{"line"};
    Host host{line};
    explicit UartOnLine(Uart82510::Config cfg = {}) : uart("uart", cfg) {
        cpu.sock.bind(uart.bus);
        uart.int_out.bind(irq);
        uart.connect(line, SerialLine::a);
    }
};

/// Runs `body` as a thread from time 0, then simulates until nothing is left (or `limit`).
inline void run(std::function<void()> body, const sc_time& limit = sc_core::SC_ZERO_TIME) {
    test::spawn_checked(std::move(body), "body");
    if (limit == sc_core::SC_ZERO_TIME) sc_core::sc_start();
    else sc_core::sc_start(limit);
}

inline const sc_time k_char = test::char_time_9600_8e1();

/// Lets INT follow a register access: the pin is driven one delta after the change.
inline void settle() {
    sc_core::wait(sc_core::SC_ZERO_TIME);
    sc_core::wait(sc_core::SC_ZERO_TIME);
}

} // namespace rcsim::test::uart
