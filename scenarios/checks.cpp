#include "scenarios/checks.h"

#include "scenarios/measure.h"

namespace rcsim {

nlohmann::json to_json(const Check& c) {
    return {{"name", c.name}, {"passed", c.passed}, {"value", c.value}, {"limit", c.limit}};
}

double char_latency_limit_us(const Bench& b, const Scenario& s) {
    if (s.checks.max_char_latency_us >= 0) return s.checks.max_char_latency_us;
    const unsigned fifo_depth = b.ctl.comm.uart[0].config().fifo_depth;
    return fifo_depth * default_budget_us(s) * Bench::kPorts;
}

std::vector<Check> communication_checks(const Bench& b, const Scenario& s, const CheckFigures& f) {
    const CheckLimits& L = s.checks;
    auto at_most = [](const std::string& name, std::uint64_t v, std::uint64_t limit) {
        return Check{name, v <= limit, double(v), double(limit)};
    };
    std::vector<Check> checks;
    checks.push_back(at_most("overruns", f.overruns, L.max_overruns));
    checks.push_back(at_most("frames_failed", f.frames_failed, L.max_frames_failed));
    checks.push_back(at_most("frames_delivered_exactly_once", f.frame_mismatches, L.max_frame_mismatches));
    checks.push_back(at_most("main_cpu_malformed_frames", f.malformed, 0));
    checks.push_back({"frames_delivered", f.frames_delivered >= L.min_frames_delivered, double(f.frames_delivered),
                      double(L.min_frames_delivered)});
    checks.push_back({"char_latency_max_us", f.char_latency_max_us <= f.char_latency_limit_us,
                      f.char_latency_max_us, f.char_latency_limit_us});
    checks.push_back({"table3_margin_us", f.table3_margin_us >= L.min_margin_us, f.table3_margin_us, L.min_margin_us});
    for (unsigned p = 0; p < Bench::kPorts; ++p)
        if (const auto& h = b.replay[p]) {
            // The replayed session must draw the recorded answers: same bytes at the same times.
            const std::uint64_t bad = h->counters().out_mismatched + h->out_missing();
            checks.push_back(at_most("replay_port" + std::to_string(p) + "_matches_record", bad, 0));
        }
    return checks;
}

} // namespace rcsim
