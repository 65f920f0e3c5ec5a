// rcsim — the names of the communication checks. See check_names.h.
#include "scenarios/config/check_names.h"

namespace rcsim {

const std::vector<std::string>& communication_check_names() {
    static const std::vector<std::string> names = {
        "overruns", "frames_failed", "commands_delivered_exactly_once", "responses_delivered_exactly_once",
        "main_cpu_malformed_frames",
        "frames_delivered", "char_latency_max_us", "table3_margin_us", "table3_worst_margin_us",
        "replay_port0_matches_record", "replay_port1_matches_record", "replay_port2_matches_record",
        "bus_errors"};
    return names;
}

} // namespace rcsim
