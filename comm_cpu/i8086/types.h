// rcsim — Intel 8086 core: the types of its interface (bus cycles and their handler, the
// observation hooks, the registers), apart from the Cpu class (comm_cpu/i8086/cpu.h) that uses them.
#pragma once

#include <cstddef>
#include <cstdint>

namespace rcsim::i8086 {

using cycles_t = std::uint64_t;

/// Bus cycle kind = the status lines S2..S0 (same encoding as rcsim::BusCycle).
enum class Bus : std::uint8_t { int_ack, io_read, io_write, halt, code_fetch, mem_read, mem_write, passive };
const char* to_string(Bus b);

/// T-states of the bus interface unit.
enum class TState : std::uint8_t { Ti, T1, T2, T3, Tw, T4 };
const char* to_string(TState t);

/// Queue status QS1/QS0 as reported for the previous clock.
enum class QueueOp : std::uint8_t { idle, first, subsequent, flush };

/// Segment status S4/S3 during a bus cycle.
enum class SegStatus : std::uint8_t { ES, SS, CS, DS, none };

/// Everything that is not direct RAM/ROM. Called once per bus cycle at T1 with the absolute
/// start cycle; returns the number of Tw states the device inserts. `width` is 1 or 2 (a word
/// only at an even address). For reads, the handler stores the value in `data`.
class BusHandler {
public:
    virtual ~BusHandler() = default;
    virtual unsigned bus_access(Bus kind, std::uint32_t address, std::uint16_t& data, unsigned width,
                                cycles_t start) = 0;
    /// A write into a read-only direct region (ROM) at T1 cycle `start`: the core drops it (the
    /// ROM's outputs stay off during a write cycle); the handler may log it.
    virtual void write_ignored(std::uint32_t /*address*/, unsigned /*width*/, cycles_t /*start*/) {}
    /// The slice chain: run_until() reached its limit at the boundary at cycle `at`. A handler
    /// that would begin the next slice right there, with nothing else to run in between, sets
    /// its limit and horizon and answers true; run_until() goes on (docs/architecture.md "Slice
    /// chain"). False (the default): run_until() returns.
    virtual bool next_slice(cycles_t /*at*/, cycles_t& /*limit*/, cycles_t& /*horizon*/) { return false; }
};

/// One completed bus cycle, for the observation hook.
struct BusRecord {
    Bus kind;
    std::uint32_t address;
    std::uint16_t data;   // value transferred (word or byte, lane-aligned to bit 0)
    std::uint8_t width;   // 1 or 2 bytes
    unsigned wait_states;
    cycles_t start;       // cycle number of T1
};
using BusHook = void (*)(void* context, const BusRecord& record);
/// A set of bus-cycle kinds, one bit each (bus_kind_bit): the cycles a bus hook is called for.
using BusKinds = std::uint8_t;
constexpr BusKinds bus_kind_bit(Bus b) { return static_cast<BusKinds>(1u << static_cast<unsigned>(b)); }
constexpr BusKinds kAllBusKinds = 0xFF;

class Cpu;
/// Called at each instruction boundary, before the instruction at cpu.pc() executes (its opcode
/// byte is already read from the queue; prefixes count as part of it). Returning true stops the
/// run_until() in progress before that instruction; the next step() executes it without calling
/// the hook again, so a debugger can resume from a breakpoint without removing it.
using StepHook = bool (*)(void* context, const Cpu& cpu);

/// One clock of the per-cycle trace (the fields of the SingleStepTests cycle lists).
struct CycleRecord {
    bool ale;
    std::uint32_t address_latch;
    SegStatus segment;
    bool mem_read, mem_write, io_read, io_write; // 8288 command outputs active this clock
    bool bhe;                                    // BHE# asserted (active low on the pin)
    std::uint16_t data;                          // data bus (valid where a transfer completes)
    Bus status;                                  // S2..S0 (passive outside T1/T2 of a cycle)
    TState t;
    QueueOp qop;                                 // queue operation of the previous clock
    std::uint8_t qbyte;
    bool transfer;                               // a read or write completes in this clock
    bool lock;                                   // LOCK# asserted (active low on the pin)
};

enum Reg16 { AX, CX, DX, BX, SP, BP, SI, DI };
enum SReg { ES, CS, SS, DS };

struct Registers {
    std::uint16_t r[8] = {};
    std::uint16_t s[4] = {};
    std::uint16_t ip = 0;
    std::uint16_t flags = 0xF002;
};

namespace flag {
constexpr std::uint16_t CF = 0x0001, PF = 0x0004, AF = 0x0010, ZF = 0x0040, SF = 0x0080, TF = 0x0100,
                        IF = 0x0200, DF = 0x0400, OF = 0x0800;
}

/// An instruction boundary the idle fast-forward went past without executing its instruction
/// (so without calling the step hook there): its address and the registers before it.
struct Boundary {
    std::uint32_t pc;
    Registers regs;
};
/// Told, as a fast-forward ends, of the boundaries it went past: each of boundaries[0..n) was
/// passed `times` more times. A count, not a sequence: whole periods come as one call, and the
/// calls do not keep their order with the step hook's (a coverage counter needs no more, and
/// so is told a period once instead of once per repeat).
using SkipHook = void (*)(void* context, const Boundary* boundaries, std::size_t n, std::uint64_t times);

} // namespace rcsim::i8086
