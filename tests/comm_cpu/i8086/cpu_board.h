// A board for the bare 8086 core in tests: 1 MB of RAM (optionally with wait states), or RAM
// below 0x80000 and a "device" window above it served by the handler with its own wait states;
// the handler answers I/O and INTA (vector on the second INTA) and records every call; the bus
// hook records every bus cycle.
#pragma once

#include "comm_cpu/i8086/cpu.h"

#include <cstring>
#include <functional>
#include <memory>
#include <vector>

namespace rcsim::i8086::test {

constexpr std::uint32_t kStack = 0x20000; // SS = 0x2000, SP = 0x0100
constexpr std::uint32_t kWindow = 0x80000; // first address of the device window

struct Board : BusHandler {
    std::unique_ptr<std::uint8_t[]> ram{new std::uint8_t[1 << 20]};
    Cpu cpu;
    std::uint8_t vector = 0x20;
    unsigned io_waits = 0, inta_waits = 0, window_waits = 0;
    unsigned intas = 0;              // INTA cycles so far (the vector goes out on every second one)
    std::vector<BusRecord> calls;    // handler calls
    std::vector<BusRecord> cycles;   // every bus cycle (hook)
    std::uint16_t io_value = 0x1234;
    std::function<void(const BusRecord&)> on_access; // runs inside a handler call (e.g. raise INTR)

    explicit Board(unsigned ram_waits = 0, bool device_window = false) {
        std::memset(ram.get(), 0xF4, 1 << 20); // HLT everywhere by default
        cpu.map_memory(MemRegion{"ram", 0, device_window ? kWindow : 1u << 20, ram.get(), ram_waits, true});
        cpu.set_bus_handler(this);
        cpu.set_bus_hook([](void* c, const BusRecord& r) { static_cast<Board*>(c)->cycles.push_back(r); }, this);
        Registers regs;
        regs.s[CS] = 0x1000;
        regs.s[SS] = 0x2000;
        regs.s[DS] = 0x3000;
        regs.s[ES] = 0x4000;
        regs.r[SP] = 0x0100;
        regs.ip = 0;
        cpu.load_state(regs, nullptr, 0);
        set_vector(0x20, 0x0500, 0);
        set_vector(2, 0x0600, 0);
        set_vector(1, 0x0700, 0);
        set_vector(0, 0x0800, 0);
        // handlers: INC BX ; IRET
        for (std::uint32_t a : {0x500u, 0x600u, 0x700u, 0x800u}) {
            ram[a] = 0x43;
            ram[a + 1] = 0xCF;
        }
    }
    void set_vector(unsigned v, std::uint16_t ip, std::uint16_t cs) {
        ram[v * 4] = ip & 0xFF;
        ram[v * 4 + 1] = ip >> 8;
        ram[v * 4 + 2] = cs & 0xFF;
        ram[v * 4 + 3] = cs >> 8;
    }
    void load(const std::vector<std::uint8_t>& code, std::uint32_t at = 0x10000) {
        std::memcpy(ram.get() + at, code.data(), code.size());
    }
    unsigned bus_access(Bus kind, std::uint32_t addr, std::uint16_t& data, unsigned width, cycles_t start) override {
        unsigned waits = io_waits;
        switch (kind) {
        case Bus::int_ack:
            // The 8259A drives the type only in the second INTA; the first floats.
            data = (intas++ % 2) ? vector : 0xFF;
            waits = inta_waits;
            break;
        case Bus::io_read: data = io_value; break;
        case Bus::io_write: break;
        case Bus::mem_write:
            ram[addr] = std::uint8_t(data);
            if (width == 2) ram[addr + 1] = std::uint8_t(data >> 8);
            waits = window_waits;
            break;
        default: // memory read or code fetch in the device window
            data = width == 2 ? word_at(addr) : ram[addr];
            waits = window_waits;
            break;
        }
        const BusRecord r{kind, addr, data, std::uint8_t(width), waits, start};
        calls.push_back(r);
        if (on_access) on_access(r);
        return waits;
    }
    std::uint16_t word_at(std::uint32_t a) const { return std::uint16_t(ram[a] | (ram[a + 1] << 8)); }
    std::uint32_t pc() const { return cpu.pc(); }
};

} // namespace rcsim::i8086::test
