// The 8086 module's bus-error log (Cpu8086::bus_errors(), models/bus_error_log.h): one test per
// kind. Each runs a few instructions from RAM on a board with a ROM (direct, read-only), an I/O
// router with one device and a memory router with one device that answers with a TLM error, and
// checks the count, the record (address, cycle kind, time) against the bus cycle as the bus
// observer saw it, and what the CPU read.
#include "comm_cpu/cpu8086.h"
#include "models/bus.h"
#include "models/router.h"
#include "tests/support/sc_test.h"

#include <tlm_utils/simple_target_socket.h>

#include <cstring>
#include <memory>
#include <vector>

using namespace rcsim;
using namespace sc_core;

namespace {

constexpr std::uint32_t kRomBase = 0xF0000, kRomSize = 0x10000;
constexpr std::uint16_t kDevicePort = 0x80;     // the one I/O device
constexpr std::uint32_t kFaultyBase = 0xD0000;  // the memory device that answers with an error

/// A target that answers every access with `status` (reads give 0x5A).
struct Device : sc_module {
    tlm_utils::simple_target_socket<Device> socket{"socket"};
    tlm::tlm_response_status status;
    Device(sc_module_name n, tlm::tlm_response_status s) : sc_module(n), status(s) {
        socket.register_b_transport(this, &Device::access);
    }
    void access(tlm::tlm_generic_payload& gp, sc_time&) {
        if (gp.is_read()) std::memset(gp.get_data_ptr(), 0x5A, gp.get_data_length());
        gp.set_response_status(status);
    }
};

struct Board {
    std::unique_ptr<std::uint8_t[]> ram{new std::uint8_t[0x80000]};
    std::vector<std::uint8_t> rom = std::vector<std::uint8_t>(kRomSize, 0xA5);
    Cpu8086 cpu{"cpu"};
    Router io{"io", true}, mem{"mem"};
    Device port{"port", tlm::TLM_OK_RESPONSE};
    Device faulty{"faulty", tlm::TLM_GENERIC_ERROR_RESPONSE};
    Device pic{"pic", tlm::TLM_OK_RESPONSE};
    sc_signal<bool> intr{"intr"}, nmi{"nmi"};
    std::vector<i8086::BusRecord> cycles; // every bus cycle, from the bus observer

    explicit Board(const std::vector<std::uint8_t>& code) {
        std::memset(ram.get(), 0xF4, 0x80000); // HLT
        std::memcpy(ram.get() + 0x10000, code.data(), code.size());
        cpu.map_memory(MemRegion{"ram", 0, 0x80000, ram.get(), 0, true});
        cpu.map_memory(MemRegion{"rom", kRomBase, kRomSize, rom.data(), 1, false});
        cpu.io.bind(io.in);
        io.out.bind(port.socket);
        io.map(kDevicePort, 2, 0, "port");
        cpu.mem.bind(mem.in);
        mem.out.bind(faulty.socket);
        mem.map(kFaultyBase, 0x400, 0, "faulty");
        cpu.inta.bind(pic.socket);
        cpu.intr(intr);
        cpu.nmi(nmi);
        cpu.set_bus_observer([](void* c, const i8086::BusRecord& r) { static_cast<Board*>(c)->cycles.push_back(r); },
                             this);
        i8086::Registers r;
        r.s[i8086::CS] = 0x1000;
        r.s[i8086::SS] = 0x2000;
        r.r[i8086::SP] = 0x100;
        cpu.core().load_state(r, nullptr, 0);
    }
    void run() { sc_start(us(100)); }
    /// The T1 time of the one bus cycle of `kind` at `address`, as the observer saw it.
    sc_time t1_of(i8086::Bus kind, std::uint32_t address) const {
        sc_time t = SC_ZERO_TIME;
        int n = 0;
        for (const auto& c : cycles)
            if (c.kind == kind && c.address == address) t = cpu.time_of(c.start), ++n;
        EXPECT_EQ(n, 1) << "bus cycles of that kind at that address";
        return t;
    }
    std::uint16_t ax() { return cpu.core().regs().r[i8086::AX]; }
};

// CLI; ... ; HLT (interrupts off: the CPU stays halted).
std::vector<std::uint8_t> program(std::vector<std::uint8_t> body) {
    body.insert(body.begin(), 0xFA);
    body.push_back(0xF4);
    return body;
}

TEST(Cpu8086BusErrors, RomWriteIsDroppedAndLogged) {
    // MOV AX,F000h; MOV DS,AX; MOV WORD [1234h],5555h: a word write to F1234, in the ROM.
    Board b(program({0xB8, 0x00, 0xF0, 0x8E, 0xD8, 0xC7, 0x06, 0x34, 0x12, 0x55, 0x55}));
    b.run();
    EXPECT_EQ(b.rom[0x1234], 0xA5) << "the ROM keeps its contents";
    EXPECT_EQ(b.rom[0x1235], 0xA5);
    const BusErrorLog& log = b.cpu.bus_errors();
    EXPECT_EQ(log.count(BusErrorLog::Kind::rom_write), 1u);
    EXPECT_EQ(log.total(), 1u);
    ASSERT_EQ(log.first().size(), 1u);
    const auto& r = log.first()[0];
    EXPECT_EQ(r.kind, BusErrorLog::Kind::rom_write);
    EXPECT_EQ(r.address, 0xF1234u);
    EXPECT_EQ(r.cycle, BusCycle::mem_write);
    EXPECT_EQ(r.time, b.t1_of(i8086::Bus::mem_write, 0xF1234));
}

TEST(Cpu8086BusErrors, UnmappedIoAndMemoryReadOpenBus) {
    // IN AL,40h; MOV BL,AL; OUT 40h,AL; MOV AX,E000h; MOV DS,AX; MOV AX,[0000h]; IN AL,80h
    Board b(program({0xE4, 0x40, 0x88, 0xC3, 0xE6, 0x40, 0xB8, 0x00, 0xE0, 0x8E, 0xD8, 0xA1, 0x00, 0x00}));
    b.run();
    EXPECT_EQ(b.cpu.core().regs().r[i8086::BX] & 0xFF, 0xFF) << "an unmapped port reads as an open bus";
    EXPECT_EQ(b.ax(), 0xFFFF) << "unmapped memory reads as an open bus";
    const BusErrorLog& log = b.cpu.bus_errors();
    EXPECT_EQ(log.count(BusErrorLog::Kind::unmapped), 3u);
    EXPECT_EQ(log.total(), 3u);
    ASSERT_EQ(log.first().size(), 3u);
    const BusCycle kinds[] = {BusCycle::io_read, BusCycle::io_write, BusCycle::mem_read};
    const i8086::Bus core_kinds[] = {i8086::Bus::io_read, i8086::Bus::io_write, i8086::Bus::mem_read};
    const std::uint32_t addrs[] = {0x40, 0x40, 0xE0000};
    for (int i = 0; i < 3; ++i) {
        const auto& r = log.first()[i];
        EXPECT_EQ(r.kind, BusErrorLog::Kind::unmapped) << i;
        EXPECT_EQ(r.cycle, kinds[i]) << i;
        EXPECT_EQ(r.address, addrs[i]) << i;
        EXPECT_EQ(r.time, b.t1_of(core_kinds[i], addrs[i])) << i;
    }
}

TEST(Cpu8086BusErrors, TlmErrorResponseIsLogged) {
    // MOV AX,D000h; MOV DS,AX; MOV AL,[0010h]; MOV BL,AL; IN AL,80h (a device that answers)
    Board b(program({0xB8, 0x00, 0xD0, 0x8E, 0xD8, 0xA0, 0x10, 0x00, 0x88, 0xC3, 0xE4, 0x80}));
    b.run();
    EXPECT_EQ(b.cpu.core().regs().r[i8086::BX] & 0xFF, 0xFF) << "a failed access reads as an open bus";
    EXPECT_EQ(b.ax() & 0xFF, 0x5A) << "the I/O device answered";
    const BusErrorLog& log = b.cpu.bus_errors();
    EXPECT_EQ(log.count(BusErrorLog::Kind::tlm_error), 1u);
    EXPECT_EQ(log.total(), 1u) << "the answered accesses are no errors";
    ASSERT_EQ(log.first().size(), 1u);
    EXPECT_EQ(log.first()[0].address, 0xD0010u);
    EXPECT_EQ(log.first()[0].cycle, BusCycle::mem_read);
    EXPECT_EQ(log.first()[0].time, b.t1_of(i8086::Bus::mem_read, 0xD0010));
}

TEST(Cpu8086BusErrors, CountsAllKeepsTheFirstEight) {
    // MOV CX,10; l: OUT 40h,AL; LOOP l
    Board b(program({0xB9, 0x0A, 0x00, 0xE6, 0x40, 0xE2, 0xFC}));
    b.run();
    const BusErrorLog& log = b.cpu.bus_errors();
    EXPECT_EQ(log.count(BusErrorLog::Kind::unmapped), 10u);
    ASSERT_EQ(log.first().size(), BusErrorLog::kFirst);
    for (std::size_t i = 1; i < log.first().size(); ++i) EXPECT_LT(log.first()[i - 1].time, log.first()[i].time);
    const nlohmann::json j = to_json(log);
    EXPECT_EQ(j["total"], 10);
    EXPECT_EQ(j["unmapped"], 10);
    EXPECT_EQ(j["first"].size(), 8u);
    EXPECT_EQ(j["first"][0]["address"], "0x0040");
    EXPECT_EQ(j["first"][0]["cycle"], "IOW");
    EXPECT_EQ(j["first"][0]["kind"], "unmapped");
}

} // namespace
