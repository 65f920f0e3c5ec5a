// rcsim — the tests' host CPU on the CAMC-QI's bus (tests/camc_qi): a checked thread that runs a
// test body against one chip through its TLM target, the driver's command and read cycles.
#pragma once

#include "camc_qi/camc_qi.h"
#include "models/bus.h"
#include "tests/support/sc_test.h"

#include <tlm_utils/simple_initiator_socket.h>

#include <cstdint>
#include <functional>

namespace rcsim::camc_test {

using namespace rcsim::camc;

using sc_core::sc_time;
using sc_core::SC_US;

/// A host CPU on the chip's bus: a checked thread that runs the test body.
struct Host : sc_core::sc_module {
    tlm_utils::simple_initiator_socket<Host> sock{"sock"};
    CamcQi chip{"chip"};
    std::function<void(Host&)> body;
    unsigned last_wait_states = 0;

    explicit Host(sc_core::sc_module_name n) : sc_module(n) {
        sock.bind(chip.socket);
        rcsim::test::spawn_checked([this] { run(); }, "run");
    }
    void run() {
        body(*this);
        sc_core::sc_stop();
    }

    BusResult access(bool wr, unsigned addr, std::uint8_t* d, unsigned len) {
        const BusResult r = bus_access(sock, wr ? BusCycle::mem_write : BusCycle::mem_read, addr, d, len,
                                       sc_core::sc_time_stamp());
        last_wait_states = r.wait_states;
        return r;
    }
    /// Writes DATA (32-bit access) then the command byte: the driver's two bus cycles.
    void cmd(unsigned axis, std::uint8_t code, std::uint32_t data = 0) {
        std::uint8_t b[4] = {std::uint8_t(data), std::uint8_t(data >> 8), std::uint8_t(data >> 16),
                             std::uint8_t(data >> 24)};
        EXPECT_TRUE(access(true, axis * win::stride + win::data, b, 4).ok());
        EXPECT_TRUE(access(true, axis * win::stride + win::command, &code, 1).ok());
    }
    std::uint32_t read(unsigned axis, std::uint8_t code) {
        EXPECT_TRUE(access(true, axis * win::stride + win::command, &code, 1).ok());
        std::uint8_t b[4] = {};
        EXPECT_TRUE(access(false, axis * win::stride + win::data, b, 4).ok());
        return b[0] | (b[1] << 8) | (b[2] << 16) | (std::uint32_t{b[3]} << 24);
    }
    std::int32_t cnt1(unsigned axis) { return static_cast<std::int32_t>(read(axis, qi::CNT1)); }
    bool busy(unsigned axis) { return read(axis, qi::STAT2) & drvst::busy; }
    void setup(unsigned axis, std::uint32_t std_speed, std::uint32_t obj, std::uint32_t acc, std::uint32_t dec,
               std::uint32_t dcfg_value) {
        cmd(axis, qi::write | qi::STD, std_speed);
        cmd(axis, qi::write | qi::OBJ, obj);
        cmd(axis, qi::write | qi::RATE1, acc);
        cmd(axis, qi::write | qi::RATE2, dec);
        cmd(axis, qi::write | qi::DCFG, dcfg_value);
    }
    void wait_idle(unsigned axis, sc_time step = sc_time(100, SC_US)) {
        while (busy(axis)) wait(step);
    }
};

inline void run(const std::function<void(Host&)>& body) {
    Host h("host");
    h.body = body;
    sc_core::sc_start();
}

} // namespace rcsim::camc_test
