// rcsim — the one judge of a communication run (docs/scenarios.md "Checks"): every figure the
// checks judge (Table 3, the budget, the longest service and blocking time of every source), the
// checks and the verdict, computed in one place from the world's measurements. The end of a run
// (scenarios/run/runner.cpp), the live page and the JSON API (scenarios/monitor) and the Modbus
// registers (scenarios/modbus) all ask it, so they cannot disagree: live on the figures so far,
// at the end on the final ones.
#pragma once

#include "scenarios/verdict/checks.h"
#include "scenarios/verdict/measure.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace rcsim {

class World;
struct Scenario;

/// When the judge looks. At the end every check is final. While the run goes (so_far) a check
/// whose figure can still come good (a count that must reach a minimum, a mean, a motion outcome)
/// reads "not measured" instead of failed: a live FAIL is one no later event can undo.
enum class Moment { end, so_far };

struct Judgement {
    InterruptFigures interrupts; // what the probe and the DP-RAM watch measured (measure_interrupts)
    Figure budget;              // the Table 3 budget, us (budget_figure)
    nlohmann::json table3;      // report.json "table3"
    std::vector<Check> checks;  // communication checks, then (at the end) the motion ones
    RunVerdict verdict;
    nlohmann::json checks_json() const;
};

/// A check as judged so far (Moment::so_far): a failure that a later event could undo (a minimum
/// not reached yet, a mean) is not measured yet, with the figure so far in its reason; any other
/// status stands.
Check as_so_far(Check c);

/// The budget of the rule: the scenario's `budget_us`, else the mean character arrival period of
/// the active ports (budget_us in measure.h) — measured only once the firmware has programmed the
/// character format of every active port's 82510; before that the reason names the port.
Figure budget_figure(const World& w, const Scenario& s);

/// Why the scenario gave the controller nothing to measure ("" when some host generates traffic).
std::string why_no_traffic(const World& w, const Scenario& s);

/// The figures the communication checks judge, read from the world (the same at the end and live).
CheckFigures check_figures(const World& w, const Scenario& s, const InterruptFigures& c, nlohmann::json* table3);

/// Judges the run. `stop_signal`: the signal that stopped it (0: none); `symbol` names code
/// addresses in the explanations (empty: addresses). At the end call it once after
/// World::finish_observers() and World::finish().
Judgement judge(const World& w, const Scenario& s, Moment m, int stop_signal, const SymbolOf& symbol = {});

} // namespace rcsim
