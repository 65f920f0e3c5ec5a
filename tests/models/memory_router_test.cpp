#include "models/bus.h"
#include "models/memory.h"
#include "models/router.h"
#include "tests/support/sc_test.h"

#include <tlm_utils/simple_initiator_socket.h>
#include <tlm_utils/simple_target_socket.h>

#include <array>

using namespace rcsim;

TEST(MemoryMap, FindsRegionsAndRejectsOverlap) {
    std::array<std::uint8_t, 16> a{}, b{};
    MemoryMap m;
    m.add({"ram", 0x0, 16, a.data(), 0, true});
    m.add({"rom", 0xF0, 16, b.data(), 1, false});
    ASSERT_NE(m.find(0x0F), nullptr);
    EXPECT_EQ(m.find(0x0F)->name, "ram");
    EXPECT_EQ(m.find(0xFF)->name, "rom");
    EXPECT_EQ(m.find(0x10), nullptr);
    EXPECT_THROW(m.add({"bad", 0x8, 16, a.data(), 0, true}), std::invalid_argument);
    EXPECT_THROW(m.add({"empty", 0x100, 0, a.data(), 0, true}), std::invalid_argument);
}

namespace {
// A target that records the local address and kind it saw and inserts 2 wait states.
struct Recorder : sc_core::sc_module {
    tlm_utils::simple_target_socket<Recorder> socket{"socket"};
    std::uint64_t last_addr = ~0ULL;
    BusCycle last_kind = BusCycle::passive;
    explicit Recorder(sc_core::sc_module_name n) : sc_module(n) {
        socket.register_b_transport(this, &Recorder::b_transport);
    }
    void b_transport(tlm::tlm_generic_payload& gp, sc_core::sc_time&) {
        BusView bus(gp, true);
        last_addr = gp.get_address();
        last_kind = bus->kind;
        bus->wait_states = 2;
        gp.get_data_ptr()[0] = 0x5A;
        gp.set_response_status(tlm::TLM_OK_RESPONSE);
    }
};
struct Cpu : sc_core::sc_module {
    tlm_utils::simple_initiator_socket<Cpu> socket{"socket"};
    explicit Cpu(sc_core::sc_module_name n) : sc_module(n) {}
};
} // namespace

TEST(Router, RebasesAddressAndReturnsWaitStates) {
    Cpu cpu("cpu");
    Router io("io", true);
    Recorder uart("uart"), pic("pic");
    cpu.socket.bind(io.in);
    io.out.bind(uart.socket);
    io.out.bind(pic.socket);
    io.map(0x80, 0x10, 0, "82510 #0");
    io.map(0xC0, 0x04, 1, "8259A", 1);
    EXPECT_THROW(io.map(0x8E, 4, 1, "overlap"), std::invalid_argument);
    sc_core::sc_start(sc_core::SC_ZERO_TIME);

    std::uint8_t data = 0;
    BusResult r = bus_access(cpu.socket, BusCycle::io_read, 0x86, &data, 1, sc_core::sc_time_stamp());
    EXPECT_TRUE(r.ok());
    EXPECT_EQ(r.wait_states, 2u);
    EXPECT_EQ(uart.last_addr, 0x6u);
    EXPECT_EQ(uart.last_kind, BusCycle::io_read);
    EXPECT_EQ(data, 0x5A);

    r = bus_access(cpu.socket, BusCycle::io_write, 0xC2, &data, 1, sc_core::sc_time_stamp());
    EXPECT_EQ(r.wait_states, 3u); // the target's 2 plus the range's 1
    EXPECT_EQ(pic.last_addr, 0x2u);
    EXPECT_EQ(pic.last_kind, BusCycle::io_write);

    r = bus_access(cpu.socket, BusCycle::io_read, 0x40, &data, 1, sc_core::sc_time_stamp());
    EXPECT_EQ(r.status, tlm::TLM_ADDRESS_ERROR_RESPONSE);
    EXPECT_EQ(io.unmapped_accesses(), 1u);
}

namespace {
// A target that reports what the payload held on entry, then leaves it as a careless target
// might: wait states, an error status, DMI allowed, a byte-enable pointer of its own.
struct Dirtier : sc_core::sc_module {
    tlm_utils::simple_target_socket<Dirtier> socket{"socket"};
    unsigned entry_waits = ~0u;
    tlm::tlm_response_status entry_status = tlm::TLM_OK_RESPONSE;
    bool entry_dmi = true;
    unsigned char* entry_byte_enable = nullptr;
    bool entry_a0 = false, entry_bhe = false;
    unsigned answer_waits = 0;
    unsigned char mask[2] = {0xFF, 0xFF};
    explicit Dirtier(sc_core::sc_module_name n) : sc_module(n) {
        socket.register_b_transport(this, &Dirtier::b_transport);
    }
    void b_transport(tlm::tlm_generic_payload& gp, sc_core::sc_time&) {
        BusView bus(gp, false);
        entry_waits = bus->wait_states;
        entry_status = gp.get_response_status();
        entry_dmi = gp.is_dmi_allowed();
        entry_byte_enable = gp.get_byte_enable_ptr();
        entry_a0 = bus->a0;
        entry_bhe = bus->bhe;
        bus->wait_states = answer_waits;
        gp.set_dmi_allowed(true);
        gp.set_byte_enable_ptr(mask);
        gp.set_response_status(answer_waits ? tlm::TLM_OK_RESPONSE : tlm::TLM_GENERIC_ERROR_RESPONSE);
    }
};
} // namespace

// A kept payload (Cpu8086 and MainCpu make every access with one) starts each access as a fresh
// one would: the previous access's answer does not leak into the next.
TEST(BusPayload, EachAccessStartsFresh) {
    Cpu cpu("cpu");
    Dirtier target("target");
    cpu.socket.bind(target.socket);
    sc_core::sc_start(sc_core::SC_ZERO_TIME);

    BusPayload payload;
    std::uint8_t data[2] = {};
    target.answer_waits = 5;
    BusResult r = payload.access(cpu.socket, BusCycle::mem_read, 0x101, data, 1, sc_core::sc_time_stamp());
    EXPECT_TRUE(r.ok());
    EXPECT_EQ(r.wait_states, 5u);
    EXPECT_TRUE(target.entry_a0);
    EXPECT_TRUE(target.entry_bhe);

    target.answer_waits = 0;
    r = payload.access(cpu.socket, BusCycle::mem_write, 0x100, data, 1, sc_core::sc_time_stamp());
    EXPECT_EQ(target.entry_waits, 0u);
    EXPECT_EQ(target.entry_status, tlm::TLM_INCOMPLETE_RESPONSE);
    EXPECT_FALSE(target.entry_dmi);
    EXPECT_EQ(target.entry_byte_enable, nullptr);
    EXPECT_FALSE(target.entry_a0);
    EXPECT_FALSE(target.entry_bhe);
    EXPECT_EQ(r.status, tlm::TLM_GENERIC_ERROR_RESPONSE);
    EXPECT_EQ(r.wait_states, 0u);
}
