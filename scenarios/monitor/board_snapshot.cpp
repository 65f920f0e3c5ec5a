// rcsim — the monitor's snapshot of the board (docs/monitor.md "Snapshot"): read from the
// world's objects between two slices, never while sc_start() runs.
#include "scenarios/monitor/board_monitor.h"

#include "scenarios/verdict/latency_causes.h"
#include "scenarios/verdict/measure.h"
#include "scenarios/verdict/judge.h"
#include "models/clock.h"


namespace rcsim::monitor {

namespace {

nlohmann::json fb_json(const char* name, int axis, const motion::McExecuteFb& fb) {
    return {{"name", name}, {"axis", axis}, {"execute", fb.Execute}, {"busy", fb.Busy}, {"active", fb.Active},
            {"done", fb.Done}, {"aborted", fb.CommandAborted}, {"error", fb.Error}, {"error_id", fb.ErrorID}};
}

nlohmann::json samples_brief(const Samples& s) {
    if (s.count() == 0) return nullptr;
    const Summary m = s.summary();
    return {{"count", m.count}, {"mean", m.mean}, {"max", m.max}, {"p99", m.p99}};
}

} // namespace

nlohmann::json BoardMonitor::snapshot() {
    const double wall = std::chrono::duration<double>(Clock::now() - wall0_).count();
    nlohmann::json j = {{"api", kApiVersion},
                        {"scenario", world_.scenario().name},
                        {"sim_time_s", sc_core::sc_time_stamp().to_seconds()},
                        {"wall_time_s", wall},
                        {"paused", paused_},
                        {"rtf", rtf_measured_},
                        {"rtf_target", rtf_target_},
                        {"clients", server_ ? server_->clients() : 0}};
    j["motion"] = motion_json();
    j["ports"] = ports_json();
    const Judgement& judged = judgement();
    j["table3"] = judged.table3;
    j["verdict"] = {{"verdict", verdict_name(judged.verdict.verdict)},
                    {"reason", judged.verdict.reason},
                    {"checks", judged.checks_json()}};
    j["interrupts"] = interrupts_json(judged.budget.value);
    return j;
}

const Judgement& BoardMonitor::judgement() {
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    if (!judged_ || now != judged_at_ || sc_core::sc_delta_count() != judged_delta_) {
        judged_ = judge(world_, world_.scenario(), Moment::so_far, 0);
        judged_at_ = now;
        judged_delta_ = sc_core::sc_delta_count();
    }
    return *judged_;
}

// Per interrupt source: counts, rate, latency and service so far against the budget, and the
// longest latency with its cause in words (scenarios/verdict/latency_causes.h). The figures only
// change when an interrupt completes: they are made again only then (a sim-clock subscriber may
// ask for hundreds of snapshots a second).
nlohmann::json BoardMonitor::interrupts_json(std::optional<double> budget) {
    std::uint64_t completed = 0;
    for (unsigned l = 0; l < 4; ++l) completed += world_.probe.count(l);
    if (irq_cache_.is_null() || completed != irq_cache_completed_ || budget != irq_cache_budget_) {
        irq_cache_ = interrupt_figures(budget);
        irq_cache_completed_ = completed;
        irq_cache_budget_ = budget;
    }
    nlohmann::json irq = irq_cache_;
    for (unsigned l = 0; l < 4; ++l) irq[l]["rate_hz"] = irq_rate_hz_[l];
    return irq;
}

nlohmann::json BoardMonitor::interrupt_figures(std::optional<double> budget) {
    nlohmann::json irq = nlohmann::json::array();
    const char* names[] = {"IR0 82510 port 0", "IR1 82510 port 1", "IR2 82510 port 2", "IR3 DP-RAM INT_L"};
    const unsigned base = world_.ctl.comm.pic.vector_base();
    for (unsigned l = 0; l < 4; ++l) {
        const Samples& latency = world_.probe.latency_us(l);
        nlohmann::json i = {{"level", l},
                            {"name", names[l]},
                            {"count", world_.probe.count(l)},
                            {"rate_hz", 0.0},
                            {"latency_us", samples_brief(latency)},
                            {"service_us", samples_brief(world_.probe.service_us(l))},
                            // No budget, no count over it: not measured, never a reassuring 0.
                            {"over_budget", budget ? nlohmann::json(latency.count_above(*budget)) : nlohmann::json(nullptr)},
                            {"worst", nullptr}};
        const auto& worst = world_.probe.worst(l).records();
        if (!worst.empty())
            i["worst"] = {{"latency_us", to_us(worst.front().first_isr - worst.front().ir_rise)},
                          {"t_s", worst.front().ir_rise.to_seconds()},
                          {"cause", latency_cause_text(worst.front(), base, SymbolOf())}};
        irq.push_back(i);
    }
    return irq;
}

// The axes (command = CAMC-QI CNT1, actual = drive position, from the latest trajectory sample),
// their PLCopen states and every function block's outputs.
nlohmann::json BoardMonitor::motion_json() {
    motion::MotionController* mc = world_.motion.get();
    if (!mc) return nullptr;
    const motion::TrajectorySample* latest = mc->recorder().last();
    nlohmann::json axes = nlohmann::json::array();
    for (unsigned a = 0; a < motion::MotionController::axes; ++a) {
        motion::McAxis& ax = mc->axis(a);
        nlohmann::json aj = {{"axis", a}, {"state", motion::to_string(ax.state())}, {"error_id", ax.error_id()},
                             {"powered", ax.powered()}, {"cmd", nullptr}, {"act", nullptr}};
        if (latest && a < latest->cmd.size()) {
            aj["cmd"] = latest->cmd[a];
            aj["act"] = latest->act[a];
        }
        axes.push_back(aj);
    }
    nlohmann::json fbs = nlohmann::json::array();
    for (unsigned a = 0; a < motion::MotionController::axes; ++a) {
        const motion::MC_Power& p = mc->power(a);
        fbs.push_back({{"name", "MC_Power"}, {"axis", a}, {"enable", p.Enable}, {"status", p.Status},
                       {"valid", p.Valid}, {"error", p.Error}, {"error_id", p.ErrorID}});
        auto& b = mc->blocks(a);
        const int ai = static_cast<int>(a);
        fbs.push_back(fb_json("MC_Reset", ai, b.reset));
        fbs.push_back(fb_json("MC_Stop", ai, b.stop));
        fbs.push_back(fb_json("MC_Home", ai, b.home));
        fbs.push_back(fb_json("MC_MoveAbsolute", ai, b.move_abs));
        fbs.push_back(fb_json("MC_MoveRelative", ai, b.move_rel));
        fbs.push_back(fb_json("MC_Halt", ai, b.halt));
    }
    fbs.push_back(fb_json("MC_LineMove2", -1, mc->line_move()));
    fbs.push_back(fb_json("MC_CircleCenterMove", -1, mc->circle_move()));
    return {{"state", mc->state()}, {"axes", axes}, {"fbs", fbs}, {"path_samples", mc->recorder().count()}};
}

// Per port: the host's latest protocol step and counters, the main CPU's counters and last frames.
nlohmann::json BoardMonitor::ports_json() {
    nlohmann::json ports = nlohmann::json::array();
    for (unsigned p = 0; p < World::kPorts; ++p) {
        nlohmann::json pj = {{"port", p}, {"host", world_.host_kind(p)}, {"step", nullptr}};
        if (const auto& h = world_.protocol[p]) {
            const auto& c = h->counters();
            pj["step"] = {{"t_s", h->last_step().at.to_seconds()}, {"text", h->last_step().text}};
            pj["host_counters"] = {{"frames_sent", c.frames_sent},     {"frames_delivered", c.frames_delivered},
                                   {"frames_failed", c.frames_failed}, {"naks", c.naks},
                                   {"timeouts", c.timeouts},           {"retries", c.retries},
                                   {"responses_received", c.responses_received}};
        }
        const MainCpuPortStats& m = world_.ctl.main.port_stats(p);
        pj["main_cpu"] = {{"frames_received", m.frames_received}, {"frames_sent", m.frames_sent},
                          {"malformed", m.malformed},             {"ack_timeouts", m.ack_timeouts},
                          {"resets_received", m.resets_received}};
        const auto& u = world_.ctl.comm.uart[p].stats();
        pj["uart"] = {{"overruns", u.overruns}, {"parity_errors", u.parity_errors}, {"framing_errors", u.framing_errors}};
        const auto& line = world_.observers[p];
        pj["line"] = {{"host_frames", line.counts(LineObserver::host_to_controller).frames_offered},
                      {"controller_frames", line.counts(LineObserver::controller_to_host).frames_offered},
                      {"breaks", line.breaks()}};
        auto frame = [](const LastFrame& f) -> nlohmann::json {
            if (!f.seen) return nullptr;
            return {{"t_s", f.t_s}, {"token", f.token}, {"bch", f.bch}, {"data", printable_frame_data(f.data)}};
        };
        pj["last_received"] = frame(last_rx_[p]);
        pj["last_sent"] = frame(last_tx_[p]);
        ports.push_back(pj);
    }
    return ports;
}

} // namespace rcsim::monitor
