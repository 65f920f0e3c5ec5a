// rcsim — the figures of a communication run, from what the bench's probes saw (docs/scenarios.md
// "How each figure is measured"). Pure functions of the finished bench: they change nothing.
#pragma once

#include "scenarios/bench.h"
#include "scenarios/report_html.h"
#include "models/stats.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace rcsim {

// The paper's Table 3 (HP 8086 emulator measurements).
constexpr double kPaperRs232IsrUs = 82.0;
constexpr double kPaperDpramByteUs = 52.553;

/// What the interrupt probe and the DP-RAM watch measured.
struct InterruptFigures {
    nlohmann::json interrupts = nlohmann::json::object(); // report.json "interrupts"
    Samples rs232_rx_service, rs232_rx_latency;
    std::optional<double> dpram_byte_us; // none: no chunk of two or more writes
    std::uint64_t dpram_bytes = 0;
};

InterruptFigures measure_interrupts(const Bench& b);

/// One character time (START through STOP) of port p as its 82510 is programmed.
double controller_char_us(const Bench& b, unsigned p);

/// The Table 3 budget: the scenario's `budget_us`, else the mean character arrival period of all
/// active ports together, 1 / sum(1 / t_char_p) (= t_char / 3 for three equal ports), each t_char
/// from the format the port's 82510 is programmed with (docs/system.md §9). A port is active when
/// a host is attached; with none, all three count.
double budget_us(const Bench& b, const Scenario& s);

/// report.json "ports[p]": the host's counters, the 82510's, the main CPU's, and the line
/// observer's (call Bench::finish_observers() first).
nlohmann::json port_json(const Bench& b, unsigned p);

/// report.json "ports[p].line", ".commands", ".responses": what the observer of port p counted.
nlohmann::json observer_json(const LineObserver& o);

/// The probe's records for interrupts.csv and report.html, with the rs232_rx classification.
std::vector<report::InterruptRow> interrupt_rows(const Bench& b);

nlohmann::json samples_json(const Samples& s);

} // namespace rcsim
