// The 8259A with a CPU: a scripted CPU (one checked thread running a test-supplied body) with the
// 8086's I/O and INTA initiator sockets, and eight IR lines the body drives directly.
#pragma once

#include "models/bus.h"
#include "models/clock.h"
#include "models/irq.h"
#include "pic8259/pic8259.h"
#include "tests/support/sc_test.h"

#include <systemc>
#include <tlm_utils/simple_initiator_socket.h>

#include <cstdint>
#include <functional>
#include <vector>

namespace rcsim::test {

class PicWithCpu : public sc_core::sc_module {
public:
    Pic8259 pic{"pic"};
    tlm_utils::simple_initiator_socket<PicWithCpu> io{"io"};
    tlm_utils::simple_initiator_socket<PicWithCpu> inta_socket{"inta_socket"};
    sc_core::sc_vector<IrqLine> ir{"ir_line", 8};
    IrqLine intr{"intr_line"};
    Clock clock{8'000'000};

    std::function<void()> body;
    std::vector<Pic8259::IntaEvent> inta_log;

    static constexpr unsigned kPortA0 = 0; // local offsets with the board's a0_shift = 1
    static constexpr unsigned kPortA1 = 2;

    explicit PicWithCpu(sc_core::sc_module_name name) : sc_module(name) {
        io.bind(pic.bus);
        inta_socket.bind(pic.inta);
        for (unsigned n = 0; n < 8; ++n) pic.ir[n].bind(ir[n]);
        pic.intr.bind(intr);
        pic.on_inta = [this](const Pic8259::IntaEvent& e) { inta_log.push_back(e); };
        spawn_checked([this] { run(); }, "run");
    }

    /// One 8086 bus cycle: 4 clocks, so everything the access triggered has settled afterwards.
    void cycle() { sc_core::wait(clock.cycles(4)); }

    BusResult out_raw(unsigned offset, std::uint8_t value, unsigned len = 1) {
        std::uint8_t data[2] = {value, 0};
        const BusResult r = bus_access(io, BusCycle::io_write, offset, data, len, sc_core::sc_time_stamp());
        cycle();
        return r;
    }
    void out(bool a0, std::uint8_t value) { out_raw(a0 ? kPortA1 : kPortA0, value); }
    std::uint8_t in(bool a0) {
        std::uint8_t data[2] = {0, 0};
        bus_access(io, BusCycle::io_read, a0 ? kPortA1 : kPortA0, data, 1, sc_core::sc_time_stamp());
        cycle();
        return data[0];
    }
    std::uint8_t inta_cycle() {
        std::uint8_t data[2] = {0, 0};
        bus_access(inta_socket, BusCycle::int_ack, 0, data, 1, sc_core::sc_time_stamp());
        cycle();
        return data[0];
    }
    /// The two INTA cycles of the 8086; returns the vector (second cycle).
    std::uint8_t inta_pair() {
        inta_cycle();
        return inta_cycle();
    }

    /// The board's initialisation: edge triggered, single, ICW4 (8086 mode), vector base 0x20.
    void init(std::uint8_t icw1 = 0x13, std::uint8_t icw2 = 0x20, std::uint8_t icw4 = 0x01,
              std::uint8_t ocw1 = 0x00) {
        out(false, icw1);
        out(true, icw2);
        out(true, icw4);
        out(true, ocw1);
    }

    void set_ir(unsigned n, bool level) {
        ir[n].write(level);
        settle();
    }
    /// Lets signal updates and the PIC's zero-time re-evaluation go through.
    void settle() { sc_core::wait(clock.cycles(1)); }

private:
    void run() {
        if (body) body();
        sc_core::sc_stop();
    }
};

} // namespace rcsim::test
