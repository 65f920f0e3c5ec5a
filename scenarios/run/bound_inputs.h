// rcsim — what the static bound (scenarios/bound/bound.h) is given, taken from a run: the run's
// ROM and symbols, the annotations, the interrupt vectors as the firmware leaves them when it
// first enables interrupts, the board's wait states at their worst and the rule's budget
// (docs/tools.md "Bound"). `rcsim bound` and `rcsim run --bound` both build their Inputs here.
#pragma once

#include "comm_cpu/i8086/history.h"
#include "scenarios/bound/bound.h"
#include "scenarios/config/scenario.h"
#include "scenarios/debug/rom_symbols.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace rcsim {

class World;

/// Copies the interrupt vector table (RAM 0..3FF) at the first change of IF to 1: the table as
/// start-up leaves it. Chains the core's IF hook (the interrupt probe's) so both see every change;
/// must outlive the simulation of `world` and be made after the probe.
class VectorCapture {
public:
    explicit VectorCapture(World& world);
    VectorCapture(const VectorCapture&) = delete;
    VectorCapture& operator=(const VectorCapture&) = delete;
    bool captured() const { return captured_; }
    const std::vector<std::uint8_t>& table() const { return table_; }

private:
    static void on_if(void* self, const i8086::IfChange& change);
    World& world_;
    i8086::Cpu::IfHook previous_ = nullptr;
    void* previous_context_ = nullptr;
    bool captured_ = false;
    std::vector<std::uint8_t> table_;
};

/// The four sources of the board (docs/system.md §3.3: ICW2 0x20; IR0..2 the 82510s, IR3 the
/// DP-RAM), named as report.json names them, with their handlers from `table` (1 KB).
std::vector<bound::Source> sources_from_table(const std::vector<std::uint8_t>& table);

/// The board's wait states at their worst per kind of cycle, and in `reason` how the DP-RAM's
/// BUSY worst was derived (dpram/README.md "BUSY arbitration").
i8086::WaitBounds board_waits(const ControllerConfig& board, std::string& reason);

/// The annotations file of a run: `annotations` when given; else, for the built firmware, the
/// one shipped beside its sources (comm_cpu/firmware/bound.annotations); else "" (none).
std::string annotations_file(const RomSource& rom, const std::string& annotations);

/// The annotations of annotations_file(rom, annotations), read before the run so that a bad
/// file is bad input at once (ConfigError naming FILE:LINE).
std::vector<bound::Annotation> run_annotations(const RomSource& rom, const std::string& annotations,
                                               const debug::RomSymbols& symbols);

/// Everything together. Throws ConfigError when the firmware never enabled interrupts within
/// `ran` (a duration in words).
bound::Inputs bound_inputs(const RomSource& rom, const debug::RomSymbols& symbols,
                           std::vector<bound::Annotation> annotations, const VectorCapture& vectors,
                           const ControllerConfig& board, double budget_us, const std::string& ran);

} // namespace rcsim
