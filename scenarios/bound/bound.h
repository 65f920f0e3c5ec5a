// rcsim — the static worst case of every interrupt path, derived from the ROM's bytes
// (docs/tools.md "Bound", docs/firmware.md "The bound").
//
// A sample, however searched, only shows the paths a scenario drives. This bounds every path: the
// control flow is read from the ROM (direct transfers, calls inlined per call site, returns,
// IRET, jump tables read from the ROM or named by an annotation), each instruction costs the
// worst clocks the exact core gives its form (comm_cpu/i8086/worst_clocks.h), loops cost their
// bound (inferred where the code states it, else from the annotations file) times their longest
// iteration, and the longest path wins. For each interrupt source the firmware installs:
//
//   service_us   entry to IRET on the longest path, nested services left out;
//   blocking_us  the part of it that keeps other requests waiting (the rule of
//                interrupt_blocking_max_us): IF = 0, or its level in service before its EOI;
//   latency_us   a stated composition, every term named (Result::latency_terms).
//
// and for the code outside interrupts the longest IF = 0 stretch after start-up.
#pragma once

#include "comm_cpu/i8086/worst_clocks.h"
#include "scenarios/debug/symbols.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace rcsim::bound {

/// A loop bound or a transfer's targets the code does not state (the annotations file,
/// docs/tools.md "Annotations"): one per line, `WHERE iterations N  # reason` or
/// `WHERE targets A B ...  # reason`, `WHERE irq_save` / `WHERE irq_restore` for routines that
/// save IF and put it back through memory (bcc's irq_off / irq_restore). WHERE is SYMBOL,
/// SYMBOL+OFFSET (hex with 0x, or decimal) or a linear address (hex with 0x).
struct Annotation {
    enum class Kind { iterations, targets, irq_save, irq_restore };
    Kind kind = Kind::iterations;
    std::uint32_t address = 0; // linear
    std::uint64_t iterations = 0;
    std::vector<std::uint32_t> targets; // linear
    std::string reason;
    std::string where; // "FILE:LINE" for messages
    mutable bool used = false;
};

/// Reads an annotations file; ConfigError naming FILE:LINE for anything malformed or a name the
/// symbols do not have.
std::vector<Annotation> load_annotations(const std::string& path, const debug::SymbolTable& symbols);

/// One interrupt source the firmware installs, as report.json names it, and its vector.
struct Source {
    std::string name;   // rs232_0, rs232_1, rs232_2, dpram
    std::uint8_t vector = 0;
    std::uint16_t cs = 0, ip = 0; // the handler, from the interrupt vector table
};

/// What the analysis is given.
struct Inputs {
    std::vector<std::uint8_t> rom;       // the ROM image, `rom_base` .. + size
    std::uint32_t rom_base = 0xF0000;
    debug::SymbolTable symbols;          // may be empty: addresses stay addresses
    std::vector<Annotation> annotations;
    std::vector<Source> sources;         // from the vector table at the end of start-up
    i8086::WaitBounds waits;             // the board's, per kind of bus cycle, at their worst
    std::string waits_reason;            // how `waits` was derived (the DP-RAM's BUSY at its worst)
    double clock_mhz = 8.0;
    double budget_us = 0;                // the paper's rule: one character time of the fastest port
    std::uint8_t pic_port = 0xC0;        // the 8259A's A0 = 0 port: an EOI is written there
};

/// One instruction of a worst path: where, what, its worst clocks, how often the path runs it.
/// Instructions that always run together in a straight line are measured as one: the last
/// carries the line's clocks and `line` = how many instructions they cover; the others 0 and 0.
struct Step {
    std::uint32_t address = 0;
    std::string where;        // SYMBOL+0xOFF or the address
    std::string instruction;  // the mnemonic (i8086::mnemonic)
    unsigned clocks = 0;
    std::uint64_t times = 1;
    unsigned line = 1;
};

/// A loop on a bounded path and where its bound came from.
struct Loop {
    std::uint32_t header = 0;
    std::string where;
    std::uint64_t iterations = 0;
    std::string reason; // "CX <= 339 at entry (LOOP)", or the annotation's reason and FILE:LINE
};

/// A named term of a composition, in clocks and microseconds.
struct Term {
    std::string name;
    std::uint64_t clocks = 0;
    double us = 0;
    std::string what;
};

struct SourceBound {
    Source source;
    std::string entry;           // the handler's symbol (or address)
    std::uint64_t service_clocks = 0, blocking_clocks = 0, latency_clocks = 0;
    double service_us = 0, blocking_us = 0, latency_us = 0;
    std::vector<Step> path;           // the longest service path
    std::vector<Step> blocking_path;  // the longest blocking path (often the same)
    std::vector<Loop> loops;          // the loops of either path
    std::vector<Term> latency_terms;
    bool reenables = false;           // the handler sets IF = 1 before its IRET (nested services possible)
};

/// The longest IF = 0 stretch of the code outside interrupts, after start-up.
struct Stretch {
    std::uint64_t clocks = 0;
    double us = 0;
    std::vector<Step> path;
    std::vector<Loop> loops;
};

struct Result {
    double budget_us = 0, clock_mhz = 8;
    i8086::WaitBounds waits;
    std::string waits_reason;
    std::map<std::string, SourceBound> sources; // by Source::name
    Stretch main_if0;
    Term longest_instruction;  // of the code outside interrupts
    Term entry;                // INTA and entry sequence
    /// Whether every source's blocking bound is within the budget.
    bool fits() const;
};

/// Bounds every source and the main code's IF = 0 stretches. Throws ConfigError (exit 2) for an
/// unbounded loop or recursion, an unresolved indirect transfer, control flow leaving the ROM or
/// an undecodable byte: each names the address, the symbol and, where one helps, the annotation
/// line to add.
Result analyse(const Inputs& inputs);

/// bound.json: {"budget_us", "clock_mhz", "waits", "sources": {SOURCE: {"service_us",
/// "blocking_us", "latency_us", "path", "loops", "latency_terms", ...}}, "main_if0": {...}}.
nlohmann::json to_json(const Result& result);

/// The handler's name and the first instructions over the budget, for a one-line message.
std::string describe_over_budget(const Result& result);

} // namespace rcsim::bound
