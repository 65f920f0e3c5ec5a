// rcsim — Intel 8086 core: the interrupt history the core keeps for the interrupt probe
// (Cpu::if_change, Cpu::held_cycle; docs/cpu8086.md "Interrupt history"). Plain C++.
#pragma once

#include <cstdint>

namespace rcsim::i8086 {

using cycles_t = std::uint64_t;
enum class Bus : std::uint8_t; // i8086.h

/// A change of the interrupt-enable flag IF, as the core made it (Cpu::if_change): what a probe
/// needs to say since when, and where, interrupts were off. Nothing here changes timing.
struct IfChange {
    enum class How : std::uint8_t {
        instruction, // CLI, STI, POPF, IRET, INT n / INT3 / INTO, a divide error: the instruction
        entry,       // an interrupt taken at a boundary (INTR, NMI, the single-step trap)
        reset,       // the hardware reset (IF = 0)
    };
    cycles_t cycle = 0;             // the boundary the instruction began at (an entry: the boundary
                                    // at which the interrupt was taken; a reset: its cycle)
    std::uint64_t instructions = 0; // instructions() at that boundary
    std::uint16_t cs = 0, ip = 0;   // the instruction (its first prefix); an entry: the CS:IP it
                                    // interrupted (the return address it pushes); reset FFFF:0000
    std::uint8_t opcode = 0;        // the instruction's opcode (0 for an entry or a reset)
    std::uint8_t vector = 0;        // the interrupt type of an entry or INT n
    bool enabled = false;           // IF after the change
    How how = How::instruction;
};

/// A bus cycle the BusHandler answered with wait states on a memory address (outside the direct
/// map: on the board only the DP-RAM, whose wait states are BUSY), for Cpu::held_cycle.
struct HeldCycle {
    cycles_t start = 0; // T1; the Tw states are the clocks start+3 .. start+3+waits-1
    std::uint32_t address = 0;
    unsigned waits = 0;
    Bus kind{};
};

} // namespace rcsim::i8086
