// The IDT7130 between two CPUs: one scripted initiator per port (each a checked thread running a
// test-supplied body) and a log of every INT pin change with its time.
#pragma once

#include "dpram/idt7130.h"
#include "models/bus.h"
#include "models/clock.h"
#include "models/irq.h"
#include "tests/support/sc_test.h"

#include <systemc>
#include <tlm_utils/simple_initiator_socket.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace rcsim::test {

class DpramBetweenCpus : public sc_core::sc_module {
public:
    struct PinEvent {
        sc_core::sc_time time;
        std::string pin;
        bool value;
        bool operator==(const PinEvent& o) const { return time == o.time && pin == o.pin && value == o.value; }
    };

    Idt7130 ram{"ram"};
    tlm_utils::simple_initiator_socket<DpramBetweenCpus> left{"left_cpu"};
    tlm_utils::simple_initiator_socket<DpramBetweenCpus> right{"right_cpu"};
    IrqLine int_l{"int_l_line"};
    IrqLine int_r{"int_r_line"};

    std::function<void()> left_body, right_body;
    std::vector<PinEvent> pins;
    std::vector<Idt7130::BusyEvent> busy;

    explicit DpramBetweenCpus(sc_core::sc_module_name name) : sc_module(name) {
        left.bind(ram.left);
        right.bind(ram.right);
        ram.int_l.bind(int_l);
        ram.int_r.bind(int_r);
        ram.on_busy = [this](const Idt7130::BusyEvent& e) { busy.push_back(e); };
        SC_HAS_PROCESS(DpramBetweenCpus);
        spawn_checked([this] { run_left(); }, "run_left");
        spawn_checked([this] { run_right(); }, "run_right");
        SC_METHOD(log_pins);
        sensitive << int_l.value_changed_event() << int_r.value_changed_event();
        dont_initialize();
    }

    /// Waits until absolute time `at`, then runs one bus cycle on `socket` starting there.
    template <typename Socket>
    BusResult access_at(Socket& socket, const sc_core::sc_time& at, bool write, unsigned address,
                        std::uint8_t* data, unsigned len = 1) {
        if (at > sc_core::sc_time_stamp()) sc_core::wait(at - sc_core::sc_time_stamp());
        return bus_access(socket, write ? BusCycle::mem_write : BusCycle::mem_read, address, data, len,
                          sc_core::sc_time_stamp());
    }
    template <typename Socket>
    BusResult write_at(Socket& socket, const sc_core::sc_time& at, unsigned address, std::uint8_t value) {
        return access_at(socket, at, true, address, &value);
    }
    template <typename Socket>
    std::uint8_t read_at(Socket& socket, const sc_core::sc_time& at, unsigned address, BusResult* result = nullptr) {
        std::uint8_t value = 0;
        const BusResult r = access_at(socket, at, false, address, &value);
        if (result) *result = r;
        return value;
    }

    /// A read of the cycle starting at `start`, made now (kernel time may be earlier: a read
    /// the initiator makes ahead of its T1 under a stable-read declaration).
    template <typename Socket>
    std::uint8_t read_ahead(Socket& socket, const sc_core::sc_time& start, unsigned address) {
        std::uint8_t value = 0;
        bus_access(socket, BusCycle::mem_read, address, &value, 1, start);
        return value;
    }

private:
    void run_left() {
        if (left_body) left_body();
    }
    void run_right() {
        if (right_body) right_body();
    }
    void log_pins() {
        const auto now = sc_core::sc_time_stamp();
        if (int_l.event()) pins.push_back({now, "INT_L", int_l.read()});
        if (int_r.event()) pins.push_back({now, "INT_R", int_r.read()});
    }
};

inline std::ostream& operator<<(std::ostream& os, const DpramBetweenCpus::PinEvent& e) {
    return os << e.pin << "=" << e.value << "@" << e.time;
}

} // namespace rcsim::test
