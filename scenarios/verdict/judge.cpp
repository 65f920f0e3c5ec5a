#include "scenarios/verdict/judge.h"

#include "scenarios/verdict/motion_figures.h"
#include "scenarios/world/world.h"

#include <string>

namespace rcsim {

namespace {

constexpr unsigned kPorts = World::kPorts;

bool active(const Scenario& s, unsigned p) { return s.ports[p].host != PortScenario::Host::none; }

bool any_active(const Scenario& s) {
    for (unsigned p = 0; p < kPorts; ++p)
        if (active(s, p)) return true;
    return false;
}

/// The ports whose 82510 the budget is computed from (budget_us): the active ones, or all three.
bool counts_for_budget(const Scenario& s, unsigned p) { return !any_active(s) || active(s, p); }

/// The Table 3 sums, given the budget: the mean and the worst margin, or why they are not measured.
void put_margins(const Figure& budget, const InterruptFigures& c, const std::string& idle, nlohmann::json& j,
                 CheckFigures& f) {
    nlohmann::json missing = nlohmann::json::object();
    if (!budget.value) missing["budget_us"] = budget.reason;
    if (c.rs232_rx_service.count() == 0)
        missing["rs232_isr_us"] = "no RS-232 receive interrupt" +
                                  (idle.empty() ? std::string(" took a character out of an RX FIFO") : ": " + idle);
    if (!c.dpram_byte_us)
        missing["dpram_byte_us"] =
            "no chunk of two or more bytes was forwarded into DP-RAM" + (idle.empty() ? "" : ": " + idle);
    if (missing.empty()) {
        const double mean = *budget.value - (j["rs232_isr_us"].get<double>() + *c.dpram_byte_us);
        const double worst = *budget.value - (j["rs232_isr_max_us"].get<double>() + *c.dpram_byte_us);
        j["margin_us"] = mean;
        j["worst_margin_us"] = worst;
        f.table3_margin_us = Figure::of(mean);
        f.table3_worst_margin_us = Figure::of(worst);
        return;
    }
    // The budget first, then the RS-232 interrupt: it is what the budget is about.
    std::string why;
    if (!budget.value) why = budget.reason;
    else if (missing.size() == 2 && !idle.empty())
        why = "no RS-232 receive interrupt and no DP-RAM chunk: " + idle;
    else
        for (const char* k : {"rs232_isr_us", "dpram_byte_us"})
            if (missing.contains(k)) why += (why.empty() ? "" : "; ") + std::string(k) + ": " + missing[k].get<std::string>();
    f.table3_margin_us = f.table3_worst_margin_us = Figure::none(why);
    j["not_measured"] = missing;
}

/// The longest service of any kind and source after start-up (a receive that read nothing, line
/// status, transmit, timer, DP-RAM mailbox): {"source", "service_us"}, null before the first.
nlohmann::json longest_service_json(const World& w) {
    nlohmann::json j = nullptr;
    for (unsigned level = 0; level < 8; ++level) {
        const Samples& s = w.probe.service_us(level);
        if (s.count() && (j.is_null() || s.summary().max > j["service_us"].get<double>()))
            j = {{"source", source_name(level)}, {"service_us", s.summary().max}};
    }
    return j;
}

/// report.json "table3": the paper's equation, margin = budget - (RS-232 ISR + DP-RAM per byte),
/// and its worst case with the longest RS-232 receive service. A figure with no samples is null
/// and named in "not_measured" with the reason.
nlohmann::json table3_json(const World& w, const Figure& budget, const InterruptFigures& c, const std::string& idle,
                           CheckFigures& f) {
    nlohmann::json j = {{"rs232_isr_us", nullptr},
                        {"rs232_isr_max_us", nullptr},
                        {"rs232_isr_covers", "RS-232 receive interrupts that took a character out of an RX FIFO "
                                             "(the paper's RS-232 interrupt); every service of every source is "
                                             "judged by interrupt_blocking_max_us"},
                        {"dpram_byte_us", nullptr},
                        {"dpram_bytes_measured", c.dpram_bytes},
                        {"paper_rs232_isr_us", kPaperRs232IsrUs},
                        {"paper_dpram_byte_us", kPaperDpramByteUs},
                        {"budget_us", budget.value ? nlohmann::json(*budget.value) : nlohmann::json(nullptr)},
                        {"margin_us", nullptr},
                        {"worst_margin_us", nullptr}};
    if (c.rs232_rx_service.count() > 0) {
        j["rs232_isr_us"] = c.rs232_rx_service.summary().mean;
        j["rs232_isr_max_us"] = c.rs232_rx_service.summary().max;
    }
    if (c.dpram_byte_us) j["dpram_byte_us"] = *c.dpram_byte_us;
    j["longest_service"] = longest_service_json(w);
    put_margins(budget, c, idle, j, f);
    return j;
}

} // namespace

Check as_so_far(Check c) {
    if (c.status != Check::Status::failed) return c;
    // A maximum or a count of bad events only grows: its failure is final. A minimum not reached
    // yet and a mean can still come good.
    const bool can_recover = (c.relation == Check::Relation::at_least && c.name != "table3_worst_margin_us") ||
                             c.name == "table3_margin_us";
    if (!can_recover) return c;
    c.status = Check::Status::not_measured;
    c.figure.reason = "not final before the end of the run (so far " +
                      (c.figure.value ? std::to_string(*c.figure.value) : std::string("nothing")) + ")";
    c.figure.value.reset();
    c.why.clear();
    c.at.reset();
    return c;
}

nlohmann::json Judgement::checks_json() const {
    nlohmann::json j = nlohmann::json::array();
    for (const Check& c : checks) j.push_back(to_json(c));
    return j;
}

Figure budget_figure(const World& w, const Scenario& s) {
    if (s.budget_us > 0) return Figure::of(s.budget_us);
    std::string never;
    for (unsigned p = 0; p < kPorts; ++p)
        if (counts_for_budget(s, p) && !w.ctl.comm.uart[p].format_programmed())
            never += (never.empty() ? "" : ", ") + std::to_string(p);
    if (!never.empty())
        return Figure::none("the firmware never programmed the character format of the 82510 of port" +
                            std::string(never.size() > 1 ? "s " : " ") + never +
                            ": its character time, and so the budget, is unknown");
    return Figure::of(budget_us(w, s));
}

std::string why_no_traffic(const World& w, const Scenario& s) {
    std::string driven;
    bool any_host = false;
    for (unsigned p = 0; p < s.ports.size(); ++p) {
        const PortScenario& ps = s.ports[p];
        if (ps.host == PortScenario::Host::none) continue;
        any_host = true;
        if (ps.host == PortScenario::Host::protocol && ps.protocol.traffic.pattern != HostTraffic::Pattern::none) return "";
        if (ps.host == PortScenario::Host::raw && !ps.raw.sends.empty()) return "";
        if (ps.host == PortScenario::Host::replay) return "";
        if (ps.host != PortScenario::Host::tcp && ps.host != PortScenario::Host::pty) continue;
        // What the user's client sent onto the line, and what the controller sent back to it.
        std::uint64_t sent = 0, received = 0;
        if (w.tcp[p]) sent = w.tcp[p]->counters().bytes_sent, received = w.tcp[p]->counters().bytes_received;
        if (w.pty[p]) sent = w.pty[p]->counters().bytes_sent, received = w.pty[p]->counters().bytes_received;
        driven += (driven.empty() ? "" : "; ") + std::string("port ") + std::to_string(p) +
                  (ps.host == PortScenario::Host::tcp ? " (tcp)" : " (pty)") + ": the user's client sent " +
                  std::to_string(sent) + " character(s) to the controller and received " + std::to_string(received);
    }
    if (!any_host) return "no host is attached to any port";
    if (!driven.empty()) return "only what the user sends reaches the controller: " + driven;
    return "no host sent traffic";
}

CheckFigures check_figures(const World& w, const Scenario& s, const InterruptFigures& c, nlohmann::json* table3) {
    CheckFigures f;
    for (unsigned p = 0; p < kPorts; ++p) {
        f.overruns += w.ctl.comm.uart[p].stats().overruns;
        if (const auto& h = w.protocol[p]) {
            f.frames_failed += h->counters().frames_failed;
            f.frames_delivered += h->counters().frames_delivered;
            if (s.ports[p].protocol.traffic.pattern != HostTraffic::Pattern::none) ++f.traffic_ports;
        }
        f.command_mismatches += w.observers[p].commands().mismatches();
        f.response_mismatches += w.observers[p].responses().mismatches();
        f.malformed += w.ctl.main.port_stats(p).malformed;
        const Samples& lat = w.char_latency_us[p];
        f.char_latency_max_us[p] = lat.count() ? Figure::of(lat.summary().max)
                                               : Figure::none("the controller read no character on this port");
    }
    f.bus_errors = w.ctl.comm.cpu.bus_errors().total();
    f.budget = budget_figure(w, s);
    const nlohmann::json t = table3_json(w, f.budget, c, why_no_traffic(w, s), f);
    if (table3) *table3 = t;
    return f;
}

Judgement judge(const World& w, const Scenario& s, Moment m, int stop_signal, const SymbolOf& symbol) {
    Judgement j;
    j.interrupts = measure_interrupts(w);
    const CheckFigures f = check_figures(w, s, j.interrupts, &j.table3);
    j.budget = f.budget;
    j.checks = communication_checks(w, s, f, symbol);
    if (m == Moment::end)
        for (Check& ch : system_motion_checks(w, s)) j.checks.push_back(std::move(ch)); // scripted hosts, motion
    else
        for (Check& ch : j.checks) ch = as_so_far(std::move(ch));
    j.verdict = judge_run(j.checks_json(), stop_signal, why_no_traffic(w, s));
    return j;
}

} // namespace rcsim
