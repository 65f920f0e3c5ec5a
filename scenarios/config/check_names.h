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

/// The checks that are off unless a scenario switches them on by name (`checks: {NAME: on}`):
/// `bound_service_us`, the rule on the static bound (docs/scenarios.md "Checks").
const std::vector<std::string>& optional_check_names();

/// Whether a report can carry a check named `name` (report.json `checks[].name`): the
/// communication checks, the motion checks, and the per-port ones (`port<n>_char_latency_max_us`,
/// `port<n>_script_completed`, `replay_port<n>_matches_record`). `char_latency_max_us` switches
/// the per-port latency checks off but names none of them, so it is not one.
bool is_report_check_name(const std::string& name);

} // namespace rcsim
