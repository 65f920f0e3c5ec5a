// rcsim — the motion layer in a communication run. See motion_system.h.
#include "scenarios/verdict/motion_figures.h"

#include "models/clock.h"
#include "models/plumbing/sim_time_text.h"
#include "models/stats.h"
#include "scenarios/world/world.h"
#include "scenarios/verdict/checks.h"
#include "scenarios/verdict/motion_checks.h"

#include <iomanip>
#include <sstream>
#include <string>

namespace rcsim {

namespace {

double ms(const sc_core::sc_time& t) { return to_us(t) / 1000.0; }

const char* const kNoLatency = "no scripted move command reached its first pulse";


/// The first missed SYNC in words: when, how late the set-point was, and what made it late.
std::string why_csp_missed(const motion::CspStats& c) {
    const motion::CspStats::Miss& m = *c.first_miss;
    std::ostringstream os;
    os << std::fixed << std::setprecision(1);
    os << c.missed << " of " << c.setpoints << " set-points came after their drive's SYNC; the first, for the SYNC at "
       << sim_time_text(m.sync.to_seconds()) << ", was written " << to_us(m.written - m.sync) << " us after it: the control cycle started "
       << to_us(m.cycle_start - m.cycle_ideal) << " us after its ideal start "
       << (m.held_by.empty() ? std::string("") : "(the processor held by " + m.held_by + ") ") << "and wrote it "
       << to_us(m.written - m.cycle_start) << " us into the cycle; the drives took the set-point before, "
       << std::setprecision(2) << m.setpoint_error << " pulses from the path";
    return os.str();
}

/// Host ETX to first pulse, over the scripted hosts' moves (one host may script moves).
Samples command_latency(const World& w) {
    Samples lat(0.001);
    for (unsigned p = 0; p < World::kPorts; ++p)
        if (w.protocol[p])
            for (double v : command_latencies_us(w.protocol[p]->script_result(), w.motion->moves())) lat.add(v);
    return lat;
}

} // namespace

nlohmann::json script_json(const ScriptResult& r) {
    nlohmann::json j = {{"steps", r.steps}, {"completed", r.completed}, {"failed", r.failed}};
    if (r.failed) j["failure"] = {{"step", r.failed_step}, {"line", r.failed_line}, {"reason", r.failure}};
    j["finished_ms"] = r.done() ? nlohmann::json(ms(r.finished_at)) : nlohmann::json(nullptr);
    return j;
}

std::vector<double> command_latencies_us(const ScriptResult& host, const std::vector<motion::MoveRecord>& moves) {
    std::vector<double> out;
    std::size_t m = 0;
    for (const ScriptResult::Sent& c : host.commands) {
        if (!starts_move(c.token) || c.bch != 0) continue;
        if (m >= moves.size()) break;
        const motion::MoveRecord& mv = moves[m++];
        if (mv.token == c.token && mv.first_pulse && *mv.first_pulse >= c.etx) out.push_back(to_us(*mv.first_pulse - c.etx));
    }
    return out;
}

nlohmann::json motion_system_json(const World& w) {
    motion::MotionController& mc = *w.motion;
    const motion::MotionSnapshot snap = mc.snapshot();
    nlohmann::json j = {{"state", snap.state},
                        {"positions", mc.positions()},
                        {"final_cmd_pulses", snap.cmd},
                        {"final_act_pulses", snap.act},
                        {"samples", mc.recorder().count()}};
    const MainCpu& cpu = w.ctl.main;
    j["control_cycle"] = {{"period_us", to_us(cpu.config().cycle_period)},
                          {"duration_us", to_json(cpu.cycle_duration_us().summary())},
                          {"start_jitter_us", to_json(cpu.cycle_jitter_us().summary())},
                          {"overruns", cpu.cycle_overruns()}};
    j["cost"] = {{"chip_accesses", mc.chip_accesses()},
                 {"chip_bus_us", to_us(mc.bus_time())},
                 {"fb_calls_us", to_us(mc.fb_time())},
                 {"fb_call_us", to_us(cpu.config().fb_call)}};
    const Samples lat = command_latency(w);
    j["command_latency_us"] = to_json(lat.summary());
    if (lat.empty()) j["command_latency_not_measured"] = kNoLatency;
    if (w.scenario().csp) {
        const motion::CspStats& c = mc.csp_stats();
        j["csp"] = {{"setpoints", c.setpoints},
                    {"missed_sync", c.missed},
                    {"max_setpoint_error_pulses", c.max_setpoint_error},
                    {"max_actual_radial_error_pulses", c.max_actual_radial_error}};
        if (c.first_miss)
            j["csp"]["first_miss"] = {{"sync_us", to_us(c.first_miss->sync)},
                                      {"written_us", to_us(c.first_miss->written)},
                                      {"cycle_ideal_us", to_us(c.first_miss->cycle_ideal)},
                                      {"cycle_start_us", to_us(c.first_miss->cycle_start)},
                                      {"held_by", c.first_miss->held_by},
                                      {"setpoint_error_pulses", c.first_miss->setpoint_error},
                                      {"why", why_csp_missed(c)}};
    }
    if (const auto& c = mc.last_circle()) {
        j["circle"] = {{"at_ms", ms(c->at)},
                       {"center", {c->center_x, c->center_y}},
                       {"start", {c->start_x, c->start_y}},
                       {"end", {c->end_x, c->end_y}},
                       {"direction", c->ccw ? "ccw" : "cw"},
                       {"outcome_ms", c->outcome_at ? nlohmann::json(ms(*c->outcome_at)) : nlohmann::json(nullptr)}};
    }
    return j;
}

std::optional<CircleOverlay> circle_overlay(const World& w, const Scenario& s) {
    if (!w.motion || !s.checks.circle || !w.motion->last_circle()) return std::nullopt;
    const motion::CircleRecord& c = *w.motion->last_circle();
    const double end = c.outcome_at ? c.outcome_at->to_seconds() : sc_core::sc_time_stamp().to_seconds();
    return CircleOverlay{s.checks.circle->center_x, s.checks.circle->center_y, s.checks.circle->radius,
                         c.at.to_seconds(), end, s.checks.circle->max_radial_error};
}

std::vector<TimeMark> trajectory_marks(const World& w) {
    if (!w.motion || !w.motion->csp_stats().first_miss) return {};
    const motion::CspStats& c = w.motion->csp_stats();
    return {{c.first_miss->sync.to_seconds(), "CSP: SYNC missed (first of " + std::to_string(c.missed) + ")"}};
}

std::vector<Check> system_motion_checks(const World& w, const Scenario& s) {
    std::vector<Check> out;
    for (unsigned p = 0; p < World::kPorts; ++p) {
        if (!w.protocol[p] || s.ports[p].protocol.traffic.pattern != HostTraffic::Pattern::script) continue;
        const ScriptResult& r = w.protocol[p]->script_result();
        Check c = Check::at_most("port" + std::to_string(p) + "_script_completed",
                                 Figure::of(double(r.steps - r.completed)), 0);
        c.detail = script_json(r);
        out.push_back(std::move(c));
    }
    if (w.program) out.push_back(program_check(*w.program));
    if (!w.motion) return out;
    motion::MotionController& mc = *w.motion;
    const CheckLimits& L = s.checks;
    if (L.circle) {
        CircleLimits lim{L.circle->center_x, L.circle->center_y, L.circle->radius, L.circle->max_radial_error,
                         L.circle->max_end_error};
        std::optional<ArcRun> run;
        if (const auto& c = mc.last_circle()) {
            const CommandedArc arc{c->start_x, c->start_y, c->center_x, c->center_y, c->end_x, c->end_y, c->ccw};
            const double end = c->outcome_at ? c->outcome_at->to_seconds() : sc_core::sc_time_stamp().to_seconds();
            run = ArcRun{arc, c->at.to_seconds(), end};
        }
        for (Check& c : circle_checks(lim, run, mc.recorder().window(), "no MC token was accepted"))
            out.push_back(std::move(c));
    }
    if (!L.motion_final_state.empty()) out.push_back(final_state_check(L.motion_final_state, mc.state()));
    if (L.max_cycle_jitter_us) {
        const Samples& j = w.ctl.main.cycle_jitter_us();
        out.push_back(Check::at_most("control_cycle_jitter_max_us",
                                     j.empty() ? Figure::none("no control cycle ran") : Figure::of(j.summary().max),
                                     *L.max_cycle_jitter_us));
    }
    if (s.csp) {
        // Judged by default: a set-point the drive did not take is a step in the path.
        const motion::CspStats& c = mc.csp_stats();
        Check k = Check::at_most("csp_missed_sync",
                                 c.setpoints == 0 ? Figure::none("the CSP path never started")
                                                  : Figure::of(double(c.missed)),
                                 double(L.max_csp_missed_sync));
        k.detail = {{"setpoints", c.setpoints}, {"max_setpoint_error_pulses", c.max_setpoint_error}};
        if (c.first_miss) {
            k.at = c.first_miss->sync;
            if (k.status == Check::Status::failed) k.why = why_csp_missed(c);
        }
        out.push_back(std::move(k));
    }
    if (L.max_command_latency_us) {
        const Samples lat = command_latency(w);
        out.push_back(Check::at_most("command_latency_max_us",
                                     lat.empty() ? Figure::none(kNoLatency) : Figure::of(lat.summary().max),
                                     *L.max_command_latency_us));
    }
    return out;
}

} // namespace rcsim
