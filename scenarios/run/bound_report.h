// rcsim — the static bound in a run's reports (docs/scenarios.md "The bound"): report.json
// "bound", its figures for the check bound_service_us, and the human text of `rcsim bound`.
#pragma once

#include "scenarios/bound/bound.h"
#include "scenarios/verdict/bound_check.h"

#include <nlohmann/json.hpp>

#include <iosfwd>
#include <string>
#include <vector>

namespace rcsim {

class World;

/// A search's search.json (`--witness`), read for its figure and best value. ConfigError when
/// it cannot be read or is no search.json.
nlohmann::json read_witness(const std::string& path);

/// report.json "bound": {"budget_us", "sources": {SOURCE: {"observed_service_us",
/// "observed_blocking_us", "observed_latency_us", "bound_service_us", "bound_blocking_us",
/// "bound_latency_us", "searched_us", "handler", "vector", "handler_address" (SEG:OFF from the vector
/// table), "path", "loops"}}}. The observed figures are this
/// run's maxima (null when the source was not serviced); searched_us is the witness's best value
/// when its figure is that source's (`interrupts.SOURCE....`), else null.
nlohmann::json bound_report(const bound::Result& result, const World& world, const nlohmann::json& interrupts,
                            const nlohmann::json& witness);

/// What the check judges, in the order of the sources' levels (IR0 first).
std::vector<BoundFigure> bound_figures(const bound::Result& result);

/// `rcsim bound`'s text (bound.txt and its output): a line per source, its bound against the
/// budget, and for one over it the handler and the path's first instructions.
void write_bound_text(const bound::Result& result, std::ostream& os);

} // namespace rcsim
