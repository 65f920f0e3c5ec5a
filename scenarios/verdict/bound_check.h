// rcsim — the check `bound_service_us` (docs/scenarios.md "Checks"): the paper's rule judged on
// the static bound (docs/tools.md "Bound") instead of a sample: every source's bound blocking time,
// the quantity of interrupt_blocking_max_us, within the budget. Off unless a scenario switches it
// on (`checks: {bound_service_us: on}`). verdict/ does not see the analysis (scenarios/bound/):
// the run hands it the figures.
#pragma once

#include "scenarios/verdict/checks.h"

#include <string>
#include <vector>

namespace rcsim {

/// One source's bound, as the check judges and names it.
struct BoundFigure {
    std::string source;   // rs232_0 .. dpram
    double blocking_us = 0;
    std::string handler;  // the path's handler (its symbol or address)
    std::string path;     // the path's first instructions, for the failing detail ("" when none)
};

/// The largest bound blocking time against `budget`; failed, `why` names the first source over
/// it, its bound, the budget and the handler; `detail` holds every source's bound.
Check bound_service_check(const std::vector<BoundFigure>& sources, const Figure& budget);

} // namespace rcsim
