// rcsim — the printed summary of a report (what `rcsim run` shows on the terminal).
#include "scenarios/run/runner.h"

#include "models/plumbing/sim_time_text.h"

#include <algorithm>
#include <cctype>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace rcsim {

namespace {
/// The last line of every summary: the verdict, and why unless it passed. PASSED, "FAILED:
/// <checks>", "INCONCLUSIVE: <check>: <reason>", "INTERRUPTED at 1.234 500 s: stopped by ...".
std::string verdict_line(const nlohmann::json& r) {
    std::string v = r.value("verdict", r.value("passed", false) ? "passed" : "failed");
    const std::string why = r.value("verdict_reason", "");
    for (char& c : v) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    std::ostringstream os;
    if (v == "FAILED" && why.rfind("failed: ", 0) == 0) return "FAILED: " + why.substr(8);
    os << v;
    if (v == "INTERRUPTED") os << " at " << sim_time_text(r["sim_time_s"].get<double>());
    if (!why.empty()) os << ": " << why;
    return os.str();
}

/// PASS, FAIL, or ---- for a check that was not measured (neither).
const char* check_mark(const nlohmann::json& c) {
    if (c.value("status", "") == "not measured") return "----";
    return c.value("passed", false) ? "PASS" : "FAIL";
}

/// The function-block commands with their outcomes (docs/motion.md "Checks").
void print_motion_commands(const nlohmann::json& m, std::ostream& os) {
    os << "\n\nfunction blocks       at              expect   outcome\n";
    for (const auto& c : m.value("commands", nlohmann::json::array())) {
        if (!c.contains("outcome")) continue; // tokens and faults: no outcome of their own
        os << "  " << std::left << std::setw(20) << c["fb"].get<std::string>() << std::setw(16)
           << sim_time_text(c["at_ms"].get<double>() / 1e3) << std::setw(8) << c["expect"].get<std::string>() << " "
           << c["outcome"].get<std::string>() << std::right;
        if (c.contains("error_id")) os << " (ErrorID " << c["error_id"].get<unsigned>() << ")";
        if (c["outcome_ms"].is_number()) os << " at " << sim_time_text(c["outcome_ms"].get<double>() / 1e3);
        os << "\n";
    }
}

/// One line per check as in the communication summary, its detail below it.
void print_motion_checks(const nlohmann::json& checks, std::ostream& os) {
    // Seven significant digits: a swept angle one pulse of arc short of 2 pi still shows.
    auto num = [](const nlohmann::json& v) {
        if (!v.is_number()) return std::string("-");
        std::ostringstream s;
        s << std::setprecision(7) << v.get<double>();
        return s.str();
    };
    os << "\nchecks\n";
    for (const auto& c : checks) {
        os << "  " << check_mark(c) << "  " << std::left << std::setw(28) << c["name"].get<std::string>()
           << std::right << " value " << num(c["value"]) << "  " << c.value("relation", "<=") << " limit "
           << num(c["limit"]);
        if (c.value("status", "") == "not measured") os << "  NOT MEASURED: " << c.value("reason", "");
        os << "\n";
        if (c.contains("detail")) os << "        " << c["detail"].dump() << "\n";
    }
}

/// report.json "bus_errors": the counts, and the first cycles with address, kind and time.
void print_bus_errors(const nlohmann::json& r, std::ostream& os) {
    if (!r.contains("bus_errors")) return;
    const auto& b = r["bus_errors"];
    os << "\nbus errors " << b["total"].get<std::uint64_t>() << " (unmapped " << b["unmapped"].get<std::uint64_t>()
       << ", ROM write " << b["rom_write"].get<std::uint64_t>() << ", TLM error " << b["tlm_error"].get<std::uint64_t>()
       << ")\n";
    for (const auto& e : b["first"])
        os << "  " << e["kind"].get<std::string>() << " " << e["cycle"].get<std::string>() << " "
           << e["address"].get<std::string>() << " at " << sim_time_text_us(e["time_us"].get<double>()) << "\n";
}

void print_motion_summary(const nlohmann::json& r, std::ostream& os) {
    const auto& m = r["motion"];
    os << "scenario " << r["scenario"].get<std::string>() << "  seed " << r["seed"] << "  simulated "
       << sim_time_text(r["sim_time_s"].get<double>());
    if (r["wall_time_s"].get<double>() > 0)
        os << " in " << r["wall_time_s"].get<double>() << " s wall (" << r["rtf"].get<double>() << "x real time)";
    os << "\nmotion state " << m.value("state", std::string("?"));
    if (m.contains("final_cmd_pulses")) os << ", final command " << m["final_cmd_pulses"].dump();
    if (m.contains("final_act_pulses")) os << ", final actual " << m["final_act_pulses"].dump();
    if (m.contains("max_following_error_pulses"))
        os << "\nmax following error " << m["max_following_error_pulses"].get<double>() << " pulses";
    print_motion_commands(m, os);
    print_motion_checks(r["checks"], os);
    if (m.contains("trajectory_svg")) os << "trajectory: " << m["trajectory_svg"].get<std::string>() << "\n";
    os << verdict_line(r) << "\n";
}
std::uint64_t u(const nlohmann::json& j, const char* k) { return j.value(k, std::uint64_t{0}); }

/// report.json interrupts.startup: when the firmware first let an interrupt in, and the
/// interrupts requested before that, which no check judges (docs/scenarios.md "Start-up").
void print_startup(const nlohmann::json& interrupts, std::ostream& os) {
    if (!interrupts.contains("startup")) return;
    const auto& st = interrupts["startup"];
    if (!st["interrupts_enabled_us"].is_number()) {
        os << "  start-up: the CPU never had interrupts enabled\n";
        return;
    }
    os << std::fixed;
    os << "  start-up: interrupts first enabled at " << sim_time_text_us(st["interrupts_enabled_us"].get<double>());
    if (st["records"].empty()) os << "\n";
    else os << "; requested before that (reported, not judged):\n";
    for (const auto& rec : st["records"])
        os << "    " << rec["source"].get<std::string>() << " IR at " << sim_time_text_us(rec["ir_rise_us"].get<double>()) << ", latency "
           << std::setprecision(1) << rec["latency_us"].get<double>() << " us, service " << rec["service_us"].get<double>()
           << " us" << (rec.contains("text") ? ": " + rec["text"].get<std::string>() : std::string()) << "\n";
    os << std::defaultfloat;
}

// Per port, for every host kind: the 82510's counters, then what the line observer saw in each
// direction, then both exactly-once comparisons (docs/scenarios.md "How each figure is measured").
void print_ports(const nlohmann::json& ports, std::ostream& os) {
    auto fixed1 = [](const nlohmann::json& v) {
        if (!v.is_number()) return std::string("-");
        std::ostringstream s;
        s << std::fixed << std::setprecision(1) << v.get<double>();
        return s.str();
    };
    os << "\nport  host      overruns  parity  framing  fifo-hw  char-latency max us\n";
    for (std::size_t p = 0; p < ports.size(); ++p) {
        const auto& j = ports[p];
        os << "  " << p << "   " << std::left << std::setw(9) << j.value("host", std::string("?")) << std::right
           << std::setw(9) << u(j, "overruns") << std::setw(8) << u(j, "parity_errors") << std::setw(9)
           << u(j, "framing_errors") << std::setw(9) << u(j, "rx_fifo_high_water") << std::setw(12)
           << fixed1(j["char_latency_us"]["max"]) << "\n";
        if (j.value("host", std::string()) == "protocol")
            os << "      protocol host: sent " << u(j, "frames_sent") << ", delivered " << u(j, "frames_delivered")
               << ", failed " << u(j, "frames_failed") << ", timeouts " << u(j, "timeouts") << ", responses "
               << u(j, "responses_received") << ", response timeouts " << u(j, "response_timeouts") << "\n";
    }
    os << "\nline observer, per port and direction\n"
       << "  port  from          enq  offered   bad   eot   nak  retry  abandoned\n";
    for (std::size_t p = 0; p < ports.size(); ++p) {
        if (!ports[p].contains("line")) continue;
        const auto& l = ports[p]["line"];
        for (const char* d : {"host_to_controller", "controller_to_host"}) {
            const auto& c = l[d];
            os << "  " << std::setw(4) << p << "  " << std::left << std::setw(10)
               << (d[0] == 'h' ? "host" : "controller") << std::right << std::setw(7) << u(c, "enqs") << std::setw(9)
               << u(c, "frames_offered") << std::setw(6) << u(c, "frames_bad") << std::setw(6) << u(c, "frames_eot")
               << std::setw(6) << u(c, "naks") << std::setw(7) << u(c, "retries") << std::setw(11)
               << u(c, "abandoned") << "\n";
        }
    }
    // sent: commands the host got EOT for / responses the main CPU handed to DP-RAM;
    // received: valid frames the main CPU reassembled / responses that reached the host intact.
    os << "\nexactly once (docs/scenarios.md)\n"
       << "  port  frames        sent  received  matched  lost  dropped  dup  unexp  reord\n";
    for (std::size_t p = 0; p < ports.size(); ++p) {
        if (!ports[p].contains("commands")) continue;
        for (const char* k : {"commands", "responses"}) {
            const auto& c = ports[p][k];
            const bool cmd = k[0] == 'c';
            const std::uint64_t dropped = cmd ? 0 : u(c["dropped"], "gave_up") + u(c["dropped"], "port_reset");
            os << "  " << std::setw(4) << p << "  " << std::left << std::setw(10) << k << std::right << std::setw(7)
               << u(c, cmd ? "host_eot" : "main_cpu_handed") << std::setw(10)
               << u(c, cmd ? "main_cpu_received" : "host_received") << std::setw(9) << u(c, "matched") << std::setw(6)
               << u(c, "lost") << std::setw(9) << dropped << std::setw(5) << u(c, "duplicates") << std::setw(7)
               << u(c, "unexpected") << std::setw(7) << u(c, "reordered") << "\n";
        }
    }
}

/// Below the exactly-once table, only when there is something to say (docs/scenarios.md
/// "Expected drops"): each port's expected drops with their causes, the frames in flight at an
/// interrupted stop, and the first frames that count against the exactly-once checks.
void print_exactly_once_notes(const nlohmann::json& r, std::ostream& os) {
    std::ostringstream out;
    auto at = [](const nlohmann::json& us) { return sim_time_text_us(us.get<double>()); };
    // A give-up's attempts (docs/scenarios.md "Expected drops").
    auto attempts = [](const nlohmann::json& e) -> std::string {
        if (!e.contains("attempts")) return "";
        return "; attempts " + std::to_string(e["attempts"].get<unsigned>()) + ", hit " +
               std::to_string(e["hit"].get<unsigned>()) + ", retries owed " +
               std::to_string(e["owed_retries"].get<unsigned>());
    };
    const auto& ports = r["ports"];
    for (std::size_t p = 0; p < ports.size(); ++p)
        for (const char* k : {"commands", "responses"}) {
            if (!ports[p].contains(k)) continue;
            const auto& b = ports[p][k];
            for (const auto& e : b.value("expected_drops", nlohmann::json::array()))
                out << "  port " << p << " " << k << ": expected, " << e["dropped"].get<std::string>() << " at "
                    << at(e["time_us"]) << ": " << e["frame"].get<std::string>() << "; cause "
                    << e["cause"].get<std::string>() << " at " << at(e["cause_us"]) << attempts(e) << "\n";
            const std::uint64_t listed = b.value("expected_drops", nlohmann::json::array()).size();
            if (u(b, "expected") > listed)
                out << "  port " << p << " " << k << ": " << u(b, "expected") - listed << " more expected\n";
            if (u(b, "in_flight") > 0)
                out << "  port " << p << " " << k << ": " << u(b, "in_flight") << " in flight at the stop\n";
        }
    for (const auto& c : r["checks"]) {
        if (!c.contains("detail") || !c["detail"].is_object() || !c["detail"].contains("unexplained")) continue;
        for (const auto& e : c["detail"]["unexplained"])
            out << "  port " << e["port"].get<unsigned>() << " " << (e["direction"] == "host_to_controller" ? "commands" : "responses")
                << ": counted, " << e["what"].get<std::string>() << " at " << at(e["time_us"]) << ": "
                << e["frame"].get<std::string>()
                << (e.contains("cause") ? "; after " + e["cause"].get<std::string>() + " at " + at(e["cause_us"]) : "")
                << attempts(e) << "\n";
    }
    if (!out.str().empty()) os << "\nexactly once: expected drops, in flight, the first counted\n" << out.str();
}

/// Before the tables: why a run FAILED (its first failed check, with its why) or was
/// INCONCLUSIVE (the verdict's reason), and every warning: what to read first.
void print_first_cause(const nlohmann::json& r, std::ostream& os) {
    const std::string verdict = r.value("verdict", std::string());
    if (verdict == "failed") {
        for (const auto& c : r["checks"])
            if (c.value("status", "") == "failed") {
                os << "\n\nfirst cause: " << c["name"].get<std::string>() << " failed"
                   << (c.contains("why") ? ": " + c["why"].get<std::string>() : std::string());
                break;
            }
    } else if (verdict == "inconclusive") {
        os << "\n\nfirst cause: not measured: " << r.value("verdict_reason", std::string());
    }
    const auto warnings = r.value("warnings", nlohmann::json::array());
    if (!warnings.empty() && verdict != "failed" && verdict != "inconclusive") os << "\n";
    for (const auto& w : warnings) os << "\nwarning: " << w.get<std::string>();
}

/// Every kind of phase (with its source) that took 10 % or more of a latency, longest first:
/// "    phases: interrupts_disabled 171.7 us, in_service rs232_1 145.4 us" (the text names the
/// largest only).
void print_phases(const nlohmann::json& worst, std::ostream& os) {
    if (!worst.contains("phases") || !worst["latency_us"].is_number()) return;
    const double latency = worst["latency_us"].get<double>();
    std::vector<std::pair<std::string, double>> kinds; // in order of first appearance
    for (const auto& p : worst["phases"]) {
        const std::string name = p["phase"].get<std::string>() + (p.contains("source") ? " " + p["source"].get<std::string>() : "");
        auto it = std::find_if(kinds.begin(), kinds.end(), [&](const auto& k) { return k.first == name; });
        if (it == kinds.end()) kinds.emplace_back(name, p["us"].get<double>());
        else it->second += p["us"].get<double>();
    }
    std::stable_sort(kinds.begin(), kinds.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
    std::ostringstream line;
    line << std::fixed << std::setprecision(1);
    for (const auto& [name, us] : kinds)
        if (latency > 0 && us >= 0.1 * latency) line << (line.tellp() > 0 ? ", " : "") << name << " " << us << " us";
    if (line.tellp() > 0) os << "    phases of 10 % or more: " << line.str() << "\n";
}

/// The longest latency of each source with what held it, and how many were over the budget
/// (report.json "interrupts".SOURCE."worst", docs/scenarios.md "Latency causes").
void print_latency_causes(const nlohmann::json& r, std::ostream& os) {
    const auto& in = r["interrupts"];
    const nlohmann::json& budget = r["table3"]["budget_us"];
    std::ostringstream body;
    body << std::fixed;
    for (const char* name : {"rs232_0", "rs232_1", "rs232_2", "dpram"}) {
        if (!in.contains(name) || !in[name].contains("worst") || in[name]["worst"].empty()) continue;
        const auto& w = in[name]["worst"];
        const auto& top = w[0];
        if (!top["latency_us"].is_number()) continue;
        body << "  " << name << " latency max " << std::setprecision(1) << top["latency_us"].get<double>() << " us at "
             << sim_time_text_us(top["ir_rise_us"].get<double>()) << ": " << top.value("text", std::string("?"))
             << "\n";
        print_phases(top, body);
        const std::uint64_t over = in[name]["over_budget"].is_number() ? in[name]["over_budget"].get<std::uint64_t>() : 0;
        if (over > 0) {
            std::size_t listed = 0;
            for (const auto& e : w) listed += e["latency_us"].get<double>() > budget.get<double>();
            body << "    over the budget: " << over << " (the " << listed
                 << " longest with their causes in report.json)\n";
        }
    }
    if (body.str().empty()) return;
    os << "\nlongest latencies and their causes (";
    if (budget.is_number())
        os << "budget " << std::fixed << std::setprecision(1) << budget.get<double>() << std::defaultfloat << " us";
    else os << "budget not measured";
    os << "; latencies are reported, not judged: docs/scenarios.md \"Checks\")\n" << body.str();
}

} // namespace

namespace {

/// report.json "bound" (rcsim run --bound): per source, this run's maxima beside the bound and
/// the budget, all in us; the searched worst when a witness gave one.
void print_bound(const nlohmann::json& r, std::ostream& os) {
    if (!r.contains("bound")) return;
    const nlohmann::json& b = r["bound"];
    auto f = [](const nlohmann::json& v) {
        if (!v.is_number()) return std::string("-");
        std::ostringstream s;
        s << std::fixed << std::setprecision(1) << v.get<double>();
        return s.str();
    };
    os << "\nbound (us)        observed service/blocking/latency     bound service/blocking/latency   searched\n";
    for (const auto& [name, x] : b["sources"].items())
        os << "  " << std::left << std::setw(10) << name << std::right << std::setw(10) << f(x["observed_service_us"])
           << std::setw(10) << f(x["observed_blocking_us"]) << std::setw(10) << f(x["observed_latency_us"])
           << std::setw(14) << f(x["bound_service_us"]) << std::setw(10) << f(x["bound_blocking_us"]) << std::setw(10)
           << f(x["bound_latency_us"]) << std::setw(11) << f(x["searched_us"]) << "\n";
    os << "  budget " << f(b["budget_us"]) << " us: every blocking bound "
       << (b.value("fits", false) ? "fits" : "does not fit (bound.json names the path)") << "\n";
}

} // namespace

void print_summary(const nlohmann::json& r, std::ostream& os) {
    if (!r.contains("interrupts")) return print_motion_summary(r, os);
    // A figure that was not measured is null in the report: printed as "-".
    auto f = [](const nlohmann::json& v, int prec = 1) {
        if (!v.is_number()) return std::string("-");
        std::ostringstream s;
        s << std::fixed << std::setprecision(prec) << v.get<double>();
        return s.str();
    };
    auto sum = [](const nlohmann::json& a, const nlohmann::json& b) {
        return a.is_number() && b.is_number() ? nlohmann::json(a.get<double>() + b.get<double>()) : nlohmann::json();
    };
    os << "scenario " << r["scenario"].get<std::string>() << "  seed " << r["seed"] << "  simulated "
       << sim_time_text(r["sim_time_s"].get<double>());
    if (r["wall_time_s"].get<double>() > 0)
        os << " in " << f(r["wall_time_s"].get<double>(), 3) << " s wall (" << f(r["rtf"].get<double>(), 1)
           << "x real time)";
    // Which firmware ran, and how its image was read (a smaller one is mirrored: models/rom_image.h).
    if (r.contains("rom_format"))
        os << "\nROM: " << r["rom"].get<std::string>() << " (" << r["rom_format"].get<std::string>() << ")";
    print_first_cause(r, os);
    os << "\n\ninterrupts (us)      count   latency mean/p99/max        service mean/p99/max\n";
    for (const char* name : {"rs232_0", "rs232_1", "rs232_2", "dpram", "rs232_rx"}) {
        const auto& i = r["interrupts"][name];
        const auto& l = i["latency_us"];
        const auto& s = i["service_us"];
        os << "  " << std::left << std::setw(16) << name << std::right << std::setw(8) << i["count"].get<std::uint64_t>()
           << std::setw(10) << f(l["mean"]) << std::setw(9) << f(l["p99"]) << std::setw(9) << f(l["max"])
           << std::setw(12) << f(s["mean"]) << std::setw(9) << f(s["p99"]) << std::setw(9) << f(s["max"]) << "\n";
    }
    print_startup(r["interrupts"], os);
    print_latency_causes(r, os);
    const auto& t = r["table3"];
    os << "\nTable 3               simulated      paper\n"
       << "  RS-232 interrupt  " << std::setw(10) << f(t["rs232_isr_us"], 3) << " us" << std::setw(10)
       << f(t["paper_rs232_isr_us"], 3) << " us   (max " << f(t["rs232_isr_max_us"], 3)
       << " us; receive interrupts that read a character)\n"
       << "  DP-RAM (1 byte)   " << std::setw(10) << f(t["dpram_byte_us"], 3) << " us" << std::setw(10)
       << f(t["paper_dpram_byte_us"], 3) << " us\n"
       << "  sum               " << std::setw(10)
       << f(sum(t["rs232_isr_us"], t["dpram_byte_us"]), 3) << " us" << std::setw(10)
       << f(sum(t["paper_rs232_isr_us"], t["paper_dpram_byte_us"]), 3) << " us\n"
       << "  budget " << f(t["budget_us"], 3) << " us, margin " << f(t["margin_us"], 3) << " us (worst case "
       << f(t["worst_margin_us"], 3) << " us)\n";
    if (t.contains("longest_service") && t["longest_service"].is_object())
        os << "  longest service of any kind: " << t["longest_service"]["source"].get<std::string>() << " "
           << f(t["longest_service"]["service_us"], 3) << " us (the rule judges its blocking time: interrupt_blocking_max_us)\n";
    if (t.contains("not_measured"))
        for (const auto& [k, why] : t["not_measured"].items()) os << "  not measured: " << k << ": " << why.get<std::string>() << "\n";
    print_ports(r["ports"], os);
    print_exactly_once_notes(r, os);
    if (r.contains("main_cpu") && r["main_cpu"].contains("cycle_jitter_us")) {
        const auto& j = r["main_cpu"]["cycle_jitter_us"];
        os << "\nmain CPU control-cycle jitter: mean " << f(j["mean"]) << " us, max " << f(j["max"]) << " us\n";
    }
    print_bus_errors(r, os);
    print_bound(r, os);
    os << "\nchecks\n";
    for (const auto& c : r["checks"]) {
        const bool unmeasured = c.value("status", "") == "not measured";
        os << "  " << check_mark(c) << "  " << std::left << std::setw(33) << c["name"].get<std::string>()
           << std::right << " value " << f(c["value"], 3) << "  " << c.value("relation", "<=") << " limit "
           << f(c["limit"], 3);
        if (unmeasured) os << "  NOT MEASURED: " << c.value("reason", "");
        os << "\n";
        if (c.contains("why")) os << "        " << c["why"].get<std::string>() << "\n";
    }
    for (const auto& name : r.value("checks_off", nlohmann::json::array()))
        os << "  off   " << name.get<std::string>() << "\n";
    os << verdict_line(r) << "\n";
}

void print_report_paths(const nlohmann::json& report, const std::string& out_dir, std::ostream& os) {
    if (out_dir.empty()) return;
    os << "report: " << out_dir << "/report.json\n"
       << "html:   " << out_dir << "/report.html\n"; // a motion run writes one too (issue #51 item 7)
    if (report.contains("bound")) os << "bound:  " << out_dir << "/bound.json\n";
}

} // namespace rcsim
