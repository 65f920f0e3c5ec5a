// rcsim — the figures of a communication run, from what the world's probes saw (docs/scenarios.md
// "How each figure is measured"). The figures that need more than a count are gathered online
// while the run goes (DpramByteTime here, the sample sets of models/stats.h), in memory that does
// not grow with the run; the functions below read them from the finished world and change nothing.
#pragma once

#include "scenarios/board/dpram_byte_time.h"
#include "scenarios/board/line_observer.h"
#include "models/dpram_layout.h"
#include "models/frame_codec.h"
#include "models/stats.h"

#include <systemc>

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <utility>
#include <vector>

namespace rcsim {

class World;
class InterruptProbe;
class MainCpu;
class ProtocolHost;
struct Scenario;

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

/// Of the finished world (World::finish()). The per-source figures and the rs232_rx set leave
/// the start-up interrupts out; "startup" lists them (startup_json).
InterruptFigures measure_interrupts(const World& w);

/// report.json interrupts.startup: when the CPU could first take an interrupt
/// ("interrupts_enabled_us", null if never) and the interrupts requested before it, each with
/// its source, IR rise, latency and service; judged by no check (docs/scenarios.md "Start-up").
nlohmann::json startup_json(const InterruptProbe& probe);

/// One character time (START through STOP) of port p as its 82510 is programmed.
double controller_char_us(const World& w, unsigned p);

/// The Table 3 budget: the scenario's `budget_us`, else the mean character arrival period of all
/// active ports together, 1 / sum(1 / t_char_p) (= t_char / 3 for three equal ports), each t_char
/// from the format the port's 82510 is programmed with (docs/system.md §9). A port is active when
/// a host is attached; with none, all three count.
double budget_us(const World& w, const Scenario& s);

/// report.json "ports[p]": the host's counters, the 82510's, the main CPU's, and the line
/// observer's (call World::finish_observers() first).
nlohmann::json port_json(const World& w, unsigned p);

/// report.json "ports[p].line", ".commands", ".responses": what the observer of port p counted.
nlohmann::json observer_json(const LineObserver& o);

nlohmann::json samples_json(const Samples& s);

/// "host_to_controller" or "controller_to_host" (LineObserver::Dir).
const char* direction_name(unsigned d);
/// One frame of the exactly-once books: {direction, frame, dropped (an expected drop: lost,
/// gave_up, port_reset), time_us, cause, cause_us}, or for one that counts against the check
/// {direction, frame, what (lost, gave_up, port_reset, duplicate, unexpected, reordered), time_us}.
nlohmann::json frame_event_json(const FrameEvent& e, unsigned direction);
/// Adds to one exactly-once book (report.json "ports[p].commands" or ".responses") `expected`
/// (drops the scenario caused, docs/scenarios.md "Expected drops"), `expected_drops` (the first
/// SequenceMatcher::kListed of them) and `in_flight` (on their way when a signal stopped the run).
void add_expected_drops(nlohmann::json& book, const SequenceMatcher& m, unsigned direction);

} // namespace rcsim
