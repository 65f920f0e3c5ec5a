// rcsim — the figures of a communication run, from what the bench's probes saw (docs/scenarios.md
// "How each figure is measured"). Pure functions of the finished bench: they change nothing.
#pragma once

#include "scenarios/bench.h"
#include "scenarios/report_html.h"
#include "models/stats.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <vector>

namespace rcsim {

// The paper's Table 3 (HP 8086 emulator measurements).
constexpr double kPaperRs232IsrUs = 82.0;
constexpr double kPaperDpramByteUs = 52.553;

/// What the interrupt probe and the DP-RAM watch measured.
struct InterruptFigures {
    nlohmann::json interrupts = nlohmann::json::object(); // report.json "interrupts"
    Samples rs232_rx_service, rs232_rx_latency;
    double dpram_byte_us = 0;
    std::uint64_t dpram_bytes = 0;
};

InterruptFigures measure_interrupts(const Bench& b);

/// The Table 3 character budget when the scenario names none (docs/system.md §9).
double default_budget_us(const Scenario& s);

/// report.json "ports[p]": the host's counters, the 82510's, the main CPU's.
nlohmann::json port_json(const Bench& b, unsigned p);

/// Frames the host saw EOT for that the main CPU did not receive intact, in order, exactly once.
std::uint64_t frame_mismatches(const ProtocolHost& host, const MainCpu& main, unsigned port);

/// The probe's records for interrupts.csv and report.html, with the rs232_rx classification.
std::vector<report::InterruptRow> interrupt_rows(const Bench& b);

nlohmann::json samples_json(const Samples& s);

} // namespace rcsim
