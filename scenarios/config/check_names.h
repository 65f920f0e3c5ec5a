// rcsim — the names of the communication checks (docs/scenarios.md "Checks"): what a scenario may
// switch off by name (`checks: {NAME: off}`). The checks themselves are judged in
// scenarios/verdict/checks.h, in this order.
#pragma once

#include <string>
#include <vector>

namespace rcsim {

/// The names of the checks a scenario may switch off; a replay port's
/// `replay_port<n>_matches_record` is named by its port.
const std::vector<std::string>& communication_check_names();

} // namespace rcsim
