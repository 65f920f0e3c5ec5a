// rcsim — report.json "interrupts".SOURCE."worst": the longest latencies of each interrupt source
// with what held them (scenarios/board/latency_cause.h), in figures and in words
// (docs/scenarios.md "Latency causes"). Reads what the probe kept; changes no figure or check.
#pragma once

#include "scenarios/board/interrupt_probe.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace rcsim {

class World;

/// The code symbol holding a linear address ("main", "rs232_isr+0x1C"), "" where none is known.
using SymbolOf = std::function<std::string(std::uint32_t linear)>;

/// The routines of a call path (InterruptRecord::path, holder_path), outermost first: each
/// address's symbol without its offset ("rs232_isr"), consecutive repeats once; an address without
/// a symbol as its linear address in hex ("F0123").
std::vector<std::string> path_names(const std::uint32_t* path, unsigned n, const SymbolOf& symbol);

/// One record's latency and cause: {"latency_us", "ir_rise_us", "boundary_us", "first_isr_us",
/// "cause", "text", "detail", "phases"}, its own service ("service_us", "blocking_us", "path",
/// "rx_fifo_level") and, when IF = 0 held it, who held it ("holder", "holder_source",
/// "interrupted_at", "interrupted_symbol", "if_on_us"; docs/scenarios.md "Latency causes"). `vector_base`: the 8259A's ICW2 (names the level of an
/// interrupt entry that cleared IF); `symbol` may be empty.
nlohmann::json latency_cause_json(const InterruptRecord& r, unsigned vector_base, const SymbolOf& symbol);
/// Its cause in words: "interrupts disabled (IF=0) since 0.000 us at FFFF:0000 (reset), ...".
std::string latency_cause_text(const InterruptRecord& r, unsigned vector_base, const SymbolOf& symbol);

/// Adds to each source of report.json "interrupts" (rs232_0..2, dpram, rs232_rx) "over_budget", how
/// many of its latencies exceeded `budget_us` (null without a budget), and "worst": its longest
/// latency and every kept one over the budget (at most WorstLatencies::kKeep), longest first, each
/// with its cause; and to each of "startup"."records" its cause.
void add_latency_causes(nlohmann::json& interrupts, const World& w, std::optional<double> budget_us,
                        const SymbolOf& symbol);

} // namespace rcsim
