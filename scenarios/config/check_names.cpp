// rcsim — the names of the communication checks. See check_names.h.
#include "scenarios/config/check_names.h"

#include <algorithm>

namespace rcsim {

const std::vector<std::string>& communication_check_names() {
    static const std::vector<std::string> names = {
        "overruns", "frames_failed", "commands_delivered_exactly_once", "responses_delivered_exactly_once",
        "main_cpu_malformed_frames",
        "frames_delivered", "char_latency_max_us", "interrupt_blocking_max_us", "table3_margin_us", "table3_worst_margin_us",
        "replay_port0_matches_record", "replay_port1_matches_record", "replay_port2_matches_record",
        "bus_errors"};
    return names;
}

const std::vector<std::string>& optional_check_names() {
    static const std::vector<std::string> names = {"bound_service_us"};
    return names;
}

namespace {

/// The motion checks (scenarios/verdict/motion_checks.cpp, motion_figures.cpp).
const std::vector<std::string>& motion_check_names() {
    static const std::vector<std::string> names = {
        "fb_outcomes_as_expected", "final_state", "st_program_error_free", "final_positions",
        "circle_radial_error_pulses", "circle_swept_angle_rad", "circle_end_error_pulses",
        "control_cycle_jitter_max_us", "command_latency_max_us", "csp_missed_sync"};
    return names;
}

/// `port<digits><suffix>`, a check judged per port.
bool per_port_name(const std::string& name, const std::string& suffix) {
    const std::string prefix = "port";
    if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
        return false;
    const auto digits_begin = name.begin() + static_cast<long>(prefix.size());
    const auto digits_end = name.end() - static_cast<long>(suffix.size());
    return std::all_of(digits_begin, digits_end, [](char c) { return c >= '0' && c <= '9'; });
}

bool listed(const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
}

} // namespace

bool is_report_check_name(const std::string& name) {
    if (name == "char_latency_max_us") return false;
    return listed(communication_check_names(), name) || listed(optional_check_names(), name) ||
           listed(motion_check_names(), name) ||
           per_port_name(name, "_char_latency_max_us") || per_port_name(name, "_script_completed");
}

} // namespace rcsim
