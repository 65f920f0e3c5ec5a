// rcsim — interrupts.csv and report.html. See report_html.h.
#include "scenarios/report/report_html.h"

#include "models/plumbing/config_error.h"
#include "models/stats.h"
#include "scenarios/report/html_parts.h"
#include "scenarios/report/svg.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace rcsim::report {

using svg::esc;
using svg::num;
using json = nlohmann::json;
using namespace html;

// ---------------------------------------------------------------------------------------------
// HTML helpers
namespace {

const char* kCss = R"(
body{font-family:-apple-system,"Segoe UI",Helvetica,Arial,sans-serif;font-size:14px;color:#222;margin:0 auto;max-width:1200px;padding:0 16px 40px}
h1{font-size:22px;margin:0}
h2{font-size:18px;border-bottom:2px solid #ddd;padding-bottom:4px;margin-top:34px}
h3{font-size:15px;margin:18px 0 6px}
.banner{display:flex;justify-content:space-between;align-items:center;padding:14px 18px;margin:16px 0 10px;border-radius:6px;color:#fff}
.banner.pass{background:#1e7e34}.banner.fail{background:#c82333}.banner.inconclusive{background:#6c757d}
.banner.interrupted{background:#b8860b}.verdict-reason{margin:0 0 10px;font-weight:bold}
tr.unmeasured td.v{background:#eee}td.nm{color:#555;font-weight:bold}td.why{text-align:left;white-space:normal;font-size:13px}
.interrupted{background:#fff3cd;border:1px solid #e0a800;padding:8px 12px;font-weight:bold}
.verdict{font-size:26px;font-weight:bold;letter-spacing:1px}
table{border-collapse:collapse;margin:6px 0 10px}
th,td{border:1px solid #ccc;padding:3px 7px;text-align:right;white-space:nowrap}
th{background:#f2f2f2;white-space:normal;vertical-align:bottom}
td.l,th.l{text-align:left}
tr.pass td.v{background:#e3f4e6}tr.fail td.v{background:#fbe0e0}
td.bad{background:#fbe0e0;font-weight:bold}
td.ok{color:#1e7e34;font-weight:bold}td.ko{color:#c82333;font-weight:bold}
ul.warnings{background:#fff3cd;border:1px solid #e0c060;border-radius:6px;padding:8px 8px 8px 28px;margin:0 0 10px}
table.meta td{text-align:left;border:none;padding:1px 14px 1px 0}
table.meta td:first-child{color:#666}
nav a{margin-right:14px}
.grid{display:flex;flex-wrap:wrap;gap:10px}
.grid svg,.chart svg{border:1px solid #e4e4e4;background:#fff}
.note{color:#555;font-size:13px;max-width:1100px}
code{background:#f4f4f4;padding:0 3px}
)";

// ---------------------------------------------------------------------------------------------
// sections

/// The check's relation as report.json states it ("<=" or ">=").
std::string check_relation(const json& c) { return js(c, "relation", "<=") == ">=" ? "&ge;" : "&le;"; }

/// The run's verdict as report.json states it: passed, failed, inconclusive or interrupted.
std::string verdict_of(const json& r) { return js(r, "verdict", r.value("passed", false) ? "passed" : "failed"); }

/// The page's title, banner and, unless the run passed, the one-line reason.
void banner(std::ostream& o, const json& r, const char* what) {
    const std::string name = js(r, "scenario", "?");
    std::string v = verdict_of(r);
    const std::string css = v == "passed" ? "pass" : v == "failed" ? "fail" : v;
    for (char& ch : v) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>rcsim: " << esc(name) << " "
      << v << "</title>\n<style>" << kCss << "</style>\n</head>\n<body>\n";
    o << "<header id=\"header\"><div class=\"banner " << css << "\"><h1>" << what << ": " << esc(name)
      << "</h1><div class=\"verdict\">" << v << "</div></div>\n";
    const std::string why = js(r, "verdict_reason");
    if (!why.empty()) o << "<p class=\"verdict-reason\" id=\"verdict-reason\">" << esc(why) << "</p>\n";
    // Every warning at the top, under the verdict: a hint there explains a run that measured nothing.
    const json& warnings = jo(r, "warnings");
    if (warnings.is_array() && !warnings.empty()) {
        o << "<ul class=\"warnings\" id=\"warnings\">\n";
        for (const auto& w : warnings)
            if (w.is_string()) o << "<li>warning: " << esc(w.get<std::string>()) << "</li>\n";
        o << "</ul>\n";
    }
}

/// The anchor of a failed check's timeline ("Where the checks failed").
std::string failure_anchor(const json& c) { return "at-" + js(c, "name"); }

/// `timelines`: the page draws the timeline around each failed check's first event (at_us).
void section_checks(std::ostream& o, const json& r, bool timelines = false) {
    o << "<section id=\"checks\"><h2>Checks</h2>\n<table><tr><th class=\"l\">check</th><th>value</th><th></th>"
         "<th>limit</th><th>result</th><th class=\"l\">why</th></tr>\n";
    for (const auto& c : jo(r, "checks")) {
        const bool ok = c.value("passed", false);
        const bool unmeasured = c.value("status", "") == "not measured";
        const std::string name = js(c, "name");
        o << "<tr class=\"" << (ok ? "pass" : unmeasured ? "unmeasured" : "fail") << "\" id=\"check-" << esc(name)
          << "\"><td class=\"l\">" << esc(name) << "</td><td class=\"v\">"
          << (c["value"].is_number() ? smart(jd(c, "value")) : std::string("-")) << "</td><td>" << check_relation(c)
          << "</td><td>" << smart(jd(c, "limit")) << "</td><td class=\"" << (ok ? "ok" : unmeasured ? "nm" : "ko")
          << "\">" << (ok ? "PASS" : unmeasured ? "NOT MEASURED" : "FAIL") << "</td><td class=\"why\">"
          << esc(unmeasured ? js(c, "reason") : js(c, "why"));
        if (timelines && !ok && c.contains("at_us"))
            o << " <a href=\"#" << esc(failure_anchor(c)) << "\">timeline at " << num(jd(c, "at_us") / 1000, 3)
              << " ms</a>";
        o << "</td></tr>\n";
    }
    o << "</table></section>\n";
}

/// A Table 3 figure: its value, or "not measured" (never a 0 that reads as measured, never green).
std::string table3_cell(const json& t, const char* key, const char* colour_by_sign = nullptr) {
    if (!t.is_object() || !t.contains(key) || !t[key].is_number())
        return "<td class=\"nm\">not measured</td>";
    const double v = t[key].get<double>();
    const char* css = colour_by_sign ? (v >= 0 ? "ok" : "ko") : "";
    return std::string("<td class=\"") + css + "\">" + num(v, 3) + "</td>";
}

void section_table3(std::ostream& o, const json& r) {
    const json& t = jo(r, "table3");
    const double pisr = jd(t, "paper_rs232_isr_us", 82), pdp = jd(t, "paper_dpram_byte_us", 52.553);
    const bool measured = t.contains("rs232_isr_us") && t["rs232_isr_us"].is_number() && t.contains("dpram_byte_us") &&
                          t["dpram_byte_us"].is_number();
    json sum = json::object();
    if (measured) sum["sum"] = jd(t, "rs232_isr_us") + jd(t, "dpram_byte_us");
    o << "<section id=\"table3\"><h2>Table 3: processing time per character</h2>\n"
      << "<table><tr><th class=\"l\"></th><th>simulated [us]</th><th>paper [us]</th><th>simulated / paper</th></tr>\n";
    auto row = [&o](const std::string& name, const std::string& cell, double paper, const json& v) {
        o << "<tr><td class=\"l\">" << name << "</td>" << cell << "<td>" << num(paper, 3) << "</td><td>"
          << (v.is_number() && paper > 0 ? num(v.get<double>() / paper, 3) : std::string("-")) << "</td></tr>\n";
    };
    row("RS-232 interrupt (mean service of the RX interrupts)", table3_cell(t, "rs232_isr_us"), pisr,
        jo(t, "rs232_isr_us"));
    row("DP-RAM (1 byte)", table3_cell(t, "dpram_byte_us"), pdp, jo(t, "dpram_byte_us"));
    row("sum", table3_cell(sum, "sum"), pisr + pdp, jo(sum, "sum"));
    const json& budget = jo(t, "budget_us");
    o << "<tr><td class=\"l\">budget (one character time / 3 ports)</td>" << table3_cell(t, "budget_us") << "<td>"
      << (budget.is_number() ? num(budget.get<double>(), 3) : std::string("-")) << "</td><td></td></tr>\n"
      << "<tr><td class=\"l\">margin = budget - sum</td>" << table3_cell(t, "margin_us", "sign") << "<td>"
      << (budget.is_number() ? num(budget.get<double>() - pisr - pdp, 3) : std::string("-")) << "</td><td></td></tr>\n"
      << "<tr><td class=\"l\">longest RS-232 RX interrupt</td>" << table3_cell(t, "rs232_isr_max_us")
      << "<td></td><td></td></tr>\n"
      << "<tr><td class=\"l\">DP-RAM bytes measured</td><td>" << ju(t, "dpram_bytes_measured")
      << "</td><td></td><td></td></tr>\n</table>\n";
    if (t.contains("not_measured"))
        for (const auto& [k, why] : t["not_measured"].items())
            if (why.is_string()) o << "<p class=\"note\">not measured: " << esc(k) << ": " << esc(why.get<std::string>()) << "</p>\n";
    if (measured && budget.is_number()) o << "<div class=\"chart\">" << table3_svg(t) << "</div>";
    o << "</section>\n";
}

void section_interrupts(std::ostream& o, const json& r, const InterruptLog& log) {
    o << "<section id=\"interrupts\"><h2>Interrupt latency and service time</h2>\n"
      << "<p class=\"note\">Latency = first ISR instruction &minus; IR rise; service = IRET done &minus; first ISR "
         "instruction. <b>rs232_rx</b> are the RS-232 interrupts that took at least one character out of an RX "
         "FIFO (the paper's &ldquo;RS-232 interrupt&rdquo;). Every interrupt is in <code>interrupts.csv</code>.</p>\n"
      << "<table><tr><th class=\"l\">source</th><th>count</th><th>latency min</th><th>mean</th><th>p99</th>"
         "<th>max [us]</th><th>service min</th><th>mean</th><th>p99</th><th>max [us]</th></tr>\n";
    const json& in = jo(r, "interrupts");
    const char* names[] = {"rs232_0", "rs232_1", "rs232_2", "dpram", "rs232_rx"};
    for (const char* n : names) {
        const json& i = jo(in, n);
        const json &l = jo(i, "latency_us"), &s = jo(i, "service_us");
        o << "<tr><td class=\"l\">" << n << "</td><td>" << ju(i, "count") << "</td><td>" << num(jd(l, "min"), 1)
          << "</td><td>" << num(jd(l, "mean"), 1) << "</td><td>" << num(jd(l, "p99"), 1) << "</td><td>"
          << num(jd(l, "max"), 1) << "</td><td>" << num(jd(s, "min"), 1) << "</td><td>" << num(jd(s, "mean"), 1)
          << "</td><td>" << num(jd(s, "p99"), 1) << "</td><td>" << num(jd(s, "max"), 1) << "</td></tr>\n";
    }
    o << "</table>\n";
    for (unsigned k = 0; k < InterruptLog::kHistograms; ++k) {
        const bool rx = k == 4;
        const Samples &lat = log.latency(k), &svc = log.service(k);
        const std::string label = rx ? "rs232_rx (RS-232 interrupts that read a character)"
                                      : "IR" + std::to_string(k) + " " + source_name(k);
        const std::string colour = colour_of(rx ? 0u : k);
        o << "<h3>" << esc(label) << "</h3>\n<div class=\"grid\">"
          << histogram_svg(names[k] + std::string(": latency"), lat, "latency: IR rise to first ISR instruction [us]",
                           colour)
          << histogram_svg(names[k] + std::string(": service time"), svc,
                           "service: first ISR instruction to IRET done [us]", colour)
          << "</div>\n";
    }
    o << "</section>\n";
}

/// The interrupt timeline around the first offending event of each failed check that has one
/// (at most kShown), read back from interrupts.csv: what the CPU was doing then.
void section_failures(std::ostream& o, const json& r, const std::filesystem::path& csv) {
    constexpr std::size_t kShown = 4;
    constexpr double kWidthUs = 1000;
    std::vector<const json*> failed;
    for (const auto& c : jo(r, "checks"))
        if (!c.value("passed", true) && c.contains("at_us") && failed.size() < kShown) failed.push_back(&c);
    if (failed.empty() || csv.empty()) return;
    o << "<section id=\"failures\"><h2>Where the checks failed</h2>\n<p class=\"note\">The interrupts around the "
         "first offending event of each failed check (its time at the left quarter), read back from "
         "interrupts.csv. Hover over a bar for its times.</p>\n";
    for (const json* c : failed) {
        const double at = jd(*c, "at_us"), t0 = std::max(0.0, at - kWidthUs / 4), t1 = t0 + kWidthUs;
        const std::vector<TimelineRow> rows = csv_rows_around(csv, t0, t1);
        unsigned levels = 4;
        for (const TimelineRow& t : rows) levels = std::max(levels, t.row.level + 1);
        o << "<h3 id=\"" << esc(failure_anchor(*c)) << "\">" << esc(js(*c, "name")) << " at " << num(at / 1000, 3)
          << " ms</h3>\n<p class=\"note\">" << esc(js(*c, "why")) << "</p>\n<div class=\"chart\">"
          << timeline_svg(rows, levels, t0, t1, t0, 1, "time after " + num(t0 / 1000, 3) + " ms [us]", nullptr,
                          "around the first failure of " + js(*c, "name"))
          << "</div>\n";
    }
    o << "</section>\n";
}

/// One latency with what held it: a row of the latency-causes table.
void cause_row(std::ostream& o, const std::string& source, const json& w, double budget) {
    std::string phases;
    for (const auto& p : jo(w, "phases")) {
        phases += (phases.empty() ? "" : " &middot; ") + esc(js(p, "phase"));
        if (p.contains("source")) phases += " (" + esc(js(p, "source")) + ")";
        phases += " " + num(jd(p, "us"), 1);
    }
    const double latency = jd(w, "latency_us");
    o << "<tr><td class=\"l\">" << esc(source) << "</td><td" << (latency > budget ? " class=\"bad\"" : "") << ">"
      << num(latency, 1) << "</td><td>" << num(jd(w, "ir_rise_us"), 3) << "</td><td class=\"l\">" << esc(js(w, "cause"))
      << "</td><td class=\"l\" style=\"white-space:normal\">" << esc(js(w, "text"))
      << "</td><td class=\"l\" style=\"white-space:normal\">" << phases << "</td></tr>\n";
}

/// report.json "interrupts".SOURCE."worst": each source's longest latency and those over the
/// budget, with what held them, then the start-up interrupts with theirs (docs/scenarios.md
/// "Latency causes", "Start-up").
void section_latency_causes(std::ostream& o, const json& r) {
    const json& in = jo(r, "interrupts");
    const double budget = jd(jo(r, "table3"), "budget_us");
    std::ostringstream rows;
    std::string over;
    for (const char* n : {"rs232_0", "rs232_1", "rs232_2", "dpram", "rs232_rx"}) {
        const json& i = jo(in, n);
        for (const auto& w : jo(i, "worst")) cause_row(rows, n, w, budget);
        if (ju(i, "over_budget") > 0)
            over += std::string(over.empty() ? "" : ", ") + n + " " + std::to_string(ju(i, "over_budget"));
    }
    for (const auto& w : jo(jo(in, "startup"), "records"))
        if (w.contains("cause")) cause_row(rows, js(w, "source") + " (start-up, not judged)", w, budget);
    o << "<section id=\"latency-causes\"><h2>Longest latencies and their causes</h2>\n"
      << "<p class=\"note\">Each source's longest latency and every one over the budget (" << num(budget, 1)
      << " us; the " << WorstLatencies::kKeep << " longest of each source are kept), then the interrupts requested "
         "during start-up, with what held each, measured: the 8259A (masked, another level in service, a higher "
         "request first), the CPU's IF = 0 (since which change, enabled by which instruction), the instruction in "
         "progress, DP-RAM BUSY, and the entry itself. The phases add up to the latency; the cause is the one that "
         "took the most time.</p>\n";
    if (rows.str().empty()) {
        o << "<p>No interrupt with an IR rise completed in this run.</p></section>\n";
        return;
    }
    o << "<table><tr><th class=\"l\">source</th><th>latency [us]</th><th>IR rise [us]</th><th class=\"l\">cause</th>"
         "<th class=\"l\">what held it</th><th class=\"l\">phases [us]</th></tr>\n"
      << rows.str() << "</table>\n<p class=\"note\">Latencies over the budget after start-up: "
      << (over.empty() ? "none" : over) << ".</p></section>\n";
}

void section_timeline(std::ostream& o, const TimelineWindows& tl) {
    o << "<section id=\"timeline\"><h2>Timeline</h2>\n";
    if (tl.rows() == 0) {
        o << "<p>No interrupt completed in this run.</p></section>\n";
        return;
    }
    const TimeWindow& w = tl.busiest();
    o << "<h3>Busiest " << num(tl.window_us() / 1000, 0) << " ms: " << num(w.start_us / 1000, 3) << " .. "
      << num(w.end_us / 1000, 3) << " ms (" << w.interrupts << " interrupts start in it)</h3>\n"
      << "<p class=\"note\">The window of the run in which the most interrupts start (the earliest such window on "
         "a tie). Hover over a bar for its times.</p>\n<div class=\"chart\">"
      << timeline_svg(tl.busiest_rows(), tl.levels(), w.start_us, w.end_us, 0, 1000, "simulation time [ms]", nullptr,
                      "busiest window")
      << "</div>\n";
    const InterruptRow& worst = tl.worst();
    const double z0 = tl.zoom_start_us(), zoom = tl.zoom_width_us();
    o << "<h3>Zoom on the longest latency: IR" << worst.level << " " << esc(worst.source) << " entered at "
      << num(worst.inta1_us / 1000, 3) << " ms, latency "
      << (worst.has_rise ? num(worst.latency_us(), 1) : std::string("-")) << " us, service "
      << num(worst.service_us(), 1) << " us</h3>\n<div class=\"chart\">"
      << timeline_svg(tl.zoom_rows(), tl.levels(), z0, z0 + zoom, z0, 1, "time after " + num(z0 / 1000, 3) + " ms [us]",
                      &worst, "zoom on the longest latency")
      << "</div></section>\n";
}

/// Both directions for every port kind, as the exactly-once checks count them: what the line
/// observer saw acknowledged on the wire against what the main CPU took from or handed to DP-RAM.
void exactly_once_table(std::ostream& o, const json& ports) {
    o << "<h3>Frames both ways (line observer against the main CPU, every host kind)</h3>\n<table><tr>"
         "<th>port</th><th class=\"l\">host</th><th>commands EOT'd</th><th>main CPU got</th><th>lost</th>"
         "<th>dup</th><th>reordered</th><th>unexpected</th><th>responses handed</th><th>host got</th>"
         "<th>lost</th><th>dropped</th><th>dup</th><th>reordered</th><th>unexpected</th>"
         "<th>response timeouts</th></tr>\n";
    auto cell = [&o](std::uint64_t v, bool bad_if_nonzero) {
        o << "<td" << (bad_if_nonzero && v ? " class=\"bad\"" : "") << ">" << v << "</td>";
    };
    for (std::size_t p = 0; p < ports.size(); ++p) {
        const json& cmd = jo(ports[p], "commands");
        const json& rsp = jo(ports[p], "responses");
        const json& dropped = jo(rsp, "dropped");
        o << "<tr><td>" << p << "</td><td class=\"l\">" << esc(js(ports[p], "host")) << "</td>";
        cell(ju(cmd, "host_eot"), false);
        cell(ju(cmd, "main_cpu_received"), false);
        for (const char* k : {"lost", "duplicates", "reordered", "unexpected"}) cell(ju(cmd, k), true);
        cell(ju(rsp, "main_cpu_handed"), false);
        cell(ju(rsp, "host_received"), false);
        cell(ju(rsp, "lost"), true);
        cell(ju(dropped, "gave_up") + ju(dropped, "port_reset"), true);
        for (const char* k : {"duplicates", "reordered", "unexpected"}) cell(ju(rsp, k), true);
        cell(ju(ports[p], "response_timeouts"), false);
        o << "</tr>\n";
    }
    o << "</table>\n";
}

/// Below the exactly-once table, only when there is something to list (docs/scenarios.md
/// "Expected drops"): the expected drops with their causes, the frames in flight at an
/// interrupted stop, and the first frames that count against the exactly-once checks.
void exactly_once_notes(std::ostream& o, const json& r) {
    std::ostringstream rows;
    auto ms = [](double us) { return num(us / 1e3, 3) + " ms"; };
    // A give-up's attempts: made, hit by a cause, the retries the protocol still owed.
    auto attempts = [](const json& e) -> std::string {
        if (!e.contains("attempts")) return "";
        return "; attempts " + std::to_string(ju(e, "attempts")) + ", hit " + std::to_string(ju(e, "hit")) +
               ", retries owed " + std::to_string(ju(e, "owed_retries"));
    };
    const json& ports = jo(r, "ports");
    for (std::size_t p = 0; p < ports.size(); ++p)
        for (const char* k : {"commands", "responses"}) {
            const json& b = jo(ports[p], k);
            for (const auto& e : jo(b, "expected_drops"))
                rows << "<tr><td>" << p << "</td><td class=\"l\">" << k << "</td><td class=\"l\">expected: "
                     << esc(js(e, "dropped")) << "</td><td>" << ms(jd(e, "time_us")) << "</td><td class=\"l\">"
                     << esc(js(e, "frame")) << "</td><td class=\"l\">" << esc(js(e, "cause")) << " at "
                     << ms(jd(e, "cause_us")) << attempts(e) << "</td></tr>\n";
            if (ju(b, "in_flight"))
                rows << "<tr><td>" << p << "</td><td class=\"l\">" << k << "</td><td class=\"l\">in flight at the stop: "
                     << ju(b, "in_flight") << "</td><td></td><td></td><td></td></tr>\n";
        }
    for (const auto& c : jo(r, "checks")) {
        if (!c.contains("detail") || !c["detail"].is_object()) continue;
        for (const auto& e : jo(c["detail"], "unexplained"))
            rows << "<tr><td>" << ju(e, "port") << "</td><td class=\"l\">"
                 << (js(e, "direction") == "host_to_controller" ? "commands" : "responses")
                 << "</td><td class=\"l bad\">counted: " << esc(js(e, "what")) << "</td><td>" << ms(jd(e, "time_us"))
                 << "</td><td class=\"l\">" << esc(js(e, "frame")) << "</td><td class=\"l\">"
                 << (e.contains("cause") ? esc(js(e, "cause")) + " at " + ms(jd(e, "cause_us")) : std::string())
                 << attempts(e) << "</td></tr>\n";
    }
    if (rows.str().empty()) return;
    o << "<h3>Frames not delivered once: expected drops, in flight, the first counted</h3>\n<table><tr><th>port</th>"
         "<th class=\"l\">frames</th><th class=\"l\">what</th><th>time</th><th class=\"l\">frame</th>"
         "<th class=\"l\">cause</th></tr>\n"
      << rows.str() << "</table>\n";
}

/// rcsim run --bound: per source, this run's maxima, the searched worst (a --witness), the static
/// bound and the budget side by side; then the bound's path, symbolised, with its clocks, and its
/// loops with their bounds (docs/tools.md "Bound").
void section_bound(std::ostream& o, const json& r) {
    if (!r.contains("bound")) return;
    const json& b = r["bound"];
    auto cell = [](const json& x, const char* key) {
        const json& v = jo(x, key);
        return "<td>" + (v.is_number() ? num(v.get<double>(), 1) : std::string("-")) + "</td>";
    };
    const std::string budget = "<td>" + num(jd(b, "budget_us"), 1) + "</td>";
    o << "<section id=\"bound\"><h2>The static bound</h2>\n<p class=\"note\">The longest path of every handler, from the "
         "ROM's bytes at the core's worst clocks per instruction; the rule judges the blocking time.</p>\n";
    for (const auto& [name, x] : jo(b, "sources").items()) {
        o << "<h3>" << esc(name) << ": " << esc(js(x, "handler")) << "</h3>\n<table><tr><th class=\"l\">us</th>"
          << "<th>observed</th><th>searched</th><th>bound</th><th>budget</th></tr>\n";
        for (const char* what : {"service", "blocking", "latency"}) {
            const std::string k = what;
            o << "<tr><td class=\"l\">" << what << "</td>" << cell(x, ("observed_" + k + "_us").c_str())
              << (k == "latency" ? cell(x, "searched_us") : "<td></td>") << cell(x, ("bound_" + k + "_us").c_str())
              << (k == "blocking" ? budget : "<td></td>") << "</tr>\n";
        }
        o << "</table>\n<table class=\"bound-path\"><tr><th class=\"l\">where</th><th class=\"l\">instruction</th>"
          << "<th>clocks</th><th>times</th></tr>\n";
        for (const json& step : jo(x, "path"))
            o << "<tr><td class=\"l\">" << esc(js(step, "where")) << "</td><td class=\"l\">" << esc(js(step, "instruction"))
              << "</td><td>" << ju(step, "clocks") << "</td><td>" << ju(step, "times") << "</td></tr>\n";
        o << "</table>\n";
        for (const json& loop : jo(x, "loops"))
            o << "<p class=\"note\">loop at " << esc(js(loop, "where")) << ": at most " << ju(loop, "iterations")
              << " iterations (" << esc(js(loop, "reason")) << ")</p>\n";
    }
    o << "</section>\n";
}

void section_ports(std::ostream& o, const json& r) {
    const json& ports = jo(r, "ports");
    o << "<section id=\"ports\"><h2>Ports</h2>\n<table><tr><th>port</th><th class=\"l\">host</th>"
         "<th>frames sent</th><th>delivered</th><th>failed</th><th>NAKs</th><th>retries</th><th>timeouts</th>"
         "<th>overruns</th><th>parity err</th><th>framing err</th><th>breaks</th><th>RX FIFO high water</th>"
         "<th>chars rx</th><th>chars tx</th><th>char latency mean</th><th>p99</th><th>max [us]</th></tr>\n";
    auto cell = [&o](std::uint64_t v, bool bad_if_nonzero) {
        o << "<td" << (bad_if_nonzero && v ? " class=\"bad\"" : "") << ">" << v << "</td>";
    };
    for (std::size_t p = 0; p < ports.size(); ++p) {
        const json& j = ports[p];
        const json& c = jo(j, "char_latency_us");
        o << "<tr><td>" << p << "</td><td class=\"l\">" << esc(js(j, "host")) << "</td>";
        cell(ju(j, "frames_sent"), false);
        cell(ju(j, "frames_delivered"), false);
        cell(ju(j, "frames_failed"), true);
        cell(ju(j, "naks"), false);
        cell(ju(j, "retries"), false);
        cell(ju(j, "timeouts"), false);
        cell(ju(j, "overruns"), true);
        cell(ju(j, "parity_errors"), false);
        cell(ju(j, "framing_errors"), false);
        cell(ju(j, "break_detects"), false);
        o << "<td" << (ju(j, "rx_fifo_high_water") >= 4 ? " class=\"bad\"" : "") << ">"
          << ju(j, "rx_fifo_high_water") << " / 4</td>";
        cell(ju(j, "chars_received"), false);
        cell(ju(j, "chars_sent"), false);
        o << "<td>" << num(jd(c, "mean"), 1) << "</td><td>" << num(jd(c, "p99"), 1) << "</td><td>"
          << num(jd(c, "max"), 1) << "</td></tr>\n";
    }
    o << "</table>\n";
    exactly_once_table(o, ports);
    exactly_once_notes(o, r);
    double limit = -1;
    for (const auto& c : jo(r, "checks"))
        if (js(c, "name") == "char_latency_max_us") limit = jd(c, "limit");
    o << "<h3>Character latency (stop bit to RXD read)</h3>\n<div class=\"chart\">" << char_latency_svg(ports, limit)
      << "</div></section>\n";
}

void section_main_cpu(std::ostream& o, const json& r) {
    const json& m = jo(r, "main_cpu");
    o << "<section id=\"main-cpu\"><h2>Main CPU</h2>\n";
    auto summary_row = [&o](const std::string& name, const json& s) {
        o << "<tr><td class=\"l\">" << name << "</td><td>" << ju(s, "count") << "</td><td>" << num(jd(s, "min"), 2)
          << "</td><td>" << num(jd(s, "mean"), 2) << "</td><td>" << num(jd(s, "p50"), 2) << "</td><td>"
          << num(jd(s, "p99"), 2) << "</td><td>" << num(jd(s, "max"), 2) << "</td></tr>\n";
    };
    o << "<table><tr><th class=\"l\"></th><th>count</th><th>min</th><th>mean</th><th>p50</th><th>p99</th>"
         "<th>max [us]</th></tr>\n";
    summary_row("control-cycle jitter (start &minus; ideal start)", jo(m, "cycle_jitter_us"));
    summary_row("IRQ latency (INT from the DP-RAM mailbox)", jo(m, "irq_latency_us"));
    o << "</table>\n<table>";
    const char* counters[] = {"control_cycles", "cycle_overruns", "mailbox_words", "mailbox_overwrites",
                              "unknown_words", "dpram_accesses"};
    for (const char* k : counters)
        o << "<tr><td class=\"l\">" << k << "</td><td>" << ju(m, k) << "</td></tr>\n";
    o << "<tr><td class=\"l\">busy_wait_us</td><td>" << num(jd(m, "busy_wait_us"), 1) << "</td></tr>\n"
      << "<tr><td class=\"l\">cpu_busy_us</td><td>" << num(jd(m, "cpu_busy_us"), 1) << "</td></tr>\n"
      << "<tr><td class=\"l\">DP-RAM BUSY collisions</td><td>" << ju(jo(r, "dpram"), "collisions")
      << "</td></tr>\n</table></section>\n";
}

/// An SVG file's text from its <svg element on (no XML prolog inside the page).
std::string inline_svg(std::string s) {
    const auto at = s.find("<svg");
    if (at != std::string::npos) s.erase(0, at);
    return s;
}

/// The motion section: the figures of a run with main_cpu.motion (control cycle, command
/// latency, CSP path) when there are any, then the trajectory pictures.
/// A motion run's function-block outcomes (report.json motion.commands, token commands left out),
/// the largest following error and the final positions per axis.
void motion_outcomes(std::ostream& o, const json& m) {
    if (m.contains("max_following_error_pulses") || m.contains("final_cmd_pulses")) {
        o << "<table><tr><th class=\"l\"></th><th>axis 0</th><th>axis 1</th><th>axis 2</th><th>axis 3</th></tr>\n";
        for (const auto& [key, label] : {std::pair{"final_cmd_pulses", "final command position [pulses]"},
                                         std::pair{"final_act_pulses", "final actual position [pulses]"}}) {
            if (!m.contains(key) || !m[key].is_array()) continue;
            o << "<tr><td class=\"l\">" << label << "</td>";
            for (const json& v : m[key]) o << "<td>" << (v.is_number() ? std::to_string(v.get<std::int64_t>()) : "-") << "</td>";
            o << "</tr>\n";
        }
        o << "</table>\n";
        if (m.contains("max_following_error_pulses"))
            o << "<p class=\"note\">maximum following error (command &minus; actual, any axis): "
              << num(jd(m, "max_following_error_pulses"), 1) << " pulses</p>\n";
    }
    if (!m.contains("commands") || !m["commands"].is_array()) return;
    bool any = false;
    for (const json& c : m["commands"]) any |= c.contains("fb");
    if (!any) return;
    o << "<table id=\"fb-outcomes\"><tr><th>at [ms]</th><th class=\"l\">function block</th><th>expected</th>"
         "<th>outcome</th><th>at [ms]</th><th>ErrorID</th><th></th></tr>\n";
    for (const json& c : m["commands"]) {
        if (!c.contains("fb")) continue;
        const std::string expect = js(c, "expect", "done"), outcome = js(c, "outcome", "none");
        const bool id_ok = !c.contains("expect_error_id") || c.value("error_id", -1) == c.value("expect_error_id", -2);
        const bool ok = expect == outcome && id_ok;
        o << "<tr><td>" << num(jd(c, "at_ms"), 0) << "</td><td class=\"l\">" << esc(js(c, "fb")) << "</td><td>"
          << esc(expect) << "</td><td>" << esc(outcome) << "</td><td>"
          << (c.contains("outcome_ms") && c["outcome_ms"].is_number() ? num(jd(c, "outcome_ms"), 0) : "-") << "</td><td>"
          << (c.contains("error_id") ? std::to_string(c.value("error_id", 0)) : "") << "</td><td class=\""
          << (ok ? "ok\">as expected" : "ko\">NOT as expected") << "</td></tr>\n";
    }
    o << "</table>\n";
}

void section_motion(std::ostream& o, const json& r, const HtmlOptions& opt) {
    const json& m = jo(r, "motion");
    o << "<section id=\"motion\"><h2>Motion trajectory</h2>\n<p class=\"note\">state " << esc(js(m, "state", "?"))
      << ", " << ju(m, "samples") << " samples (<code>trajectory.csv</code>, <code>trajectory.svg</code>"
      << (opt.trajectory_time_svg.empty() ? "" : ", <code>trajectory_time.svg</code>") << ")</p>\n";
    if (m.contains("control_cycle")) {
        const json& c = jo(m, "control_cycle");
        auto row = [&o](const std::string& name, const json& s) {
            o << "<tr><td class=\"l\">" << name << "</td><td>" << ju(s, "count") << "</td><td>" << num(jd(s, "min"), 2)
              << "</td><td>" << num(jd(s, "mean"), 2) << "</td><td>" << num(jd(s, "p50"), 2) << "</td><td>"
              << num(jd(s, "p99"), 2) << "</td><td>" << num(jd(s, "max"), 2) << "</td></tr>\n";
        };
        o << "<table><tr><th class=\"l\"></th><th>count</th><th>min</th><th>mean</th><th>p50</th><th>p99</th>"
             "<th>max [us]</th></tr>\n";
        row("control-cycle duration (its work)", jo(c, "duration_us"));
        row("control-cycle start jitter", jo(c, "start_jitter_us"));
        row("command latency (host ETX &rarr; first pulse)", jo(m, "command_latency_us"));
        o << "</table>\n";
        if (m.contains("csp")) {
            const json& k = jo(m, "csp");
            o << "<p class=\"note\">CSP path (axes 2/3): " << ju(k, "setpoints") << " set-points, "
              << ju(k, "missed_sync") << " missed the drive's SYNC; set-point error max "
              << num(jd(k, "max_setpoint_error_pulses"), 2) << " pulses, actual path from the circle max "
              << num(jd(k, "max_actual_radial_error_pulses"), 2) << " pulses</p>\n";
            if (k.contains("first_miss"))
                o << "<p class=\"note\">First missed SYNC: " << esc(k["first_miss"].value("why", "")) << "</p>\n";
        }
    }
    motion_outcomes(o, m);
    if (!opt.trajectory_svg.empty()) o << "<div class=\"chart\">" << inline_svg(opt.trajectory_svg) << "</div>\n";
    if (!opt.trajectory_time_svg.empty())
        o << "<div class=\"chart\">" << inline_svg(opt.trajectory_time_svg) << "</div>\n";
    o << "</section>\n";
}

std::string slurp_if_exists(const std::filesystem::path& f) {
    if (!std::filesystem::exists(f)) return "";
    std::ifstream in(f);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void write_page(const std::filesystem::path& dir, const std::string& page) {
    const auto f = dir / "report.html";
    std::ofstream out(f);
    if (!out) throw ConfigError(f.string(), 0, "cannot write the file");
    out << page;
    out.flush();
    if (!out) throw ConfigError(f.string(), 0, std::string("cannot write the file: ") + std::strerror(errno));
}

} // namespace

// ---------------------------------------------------------------------------------------------
// the page

std::string render_html(const json& r, const InterruptLog& log, const HtmlOptions& opt) {
    std::ostringstream o;
    const std::string name = js(r, "scenario", "?");
    banner(o, r, "rcsim run");
    if (r.value("interrupted", false)) // a signal stopped the run: every figure covers only this far
        o << "<p class=\"interrupted\" id=\"interrupted\">INTERRUPTED at " << num(jd(r, "sim_time_s"), 6)
          << " s simulated: the run was stopped by a signal before its end</p>\n";
    const json& cpu = jo(r, "comm_cpu");
    const double wall = jd(r, "wall_time_s"), rtf = jd(r, "rtf");
    std::uint64_t held = 0, unmeasured = 0;
    for (const auto& c : jo(r, "checks")) {
        if (c.value("passed", false)) ++held;
        if (c.value("status", "") == "not measured") ++unmeasured;
    }
    o << "<table class=\"meta\">\n"
      << "<tr><td>scenario</td><td>" << esc(name) << "</td></tr>\n"
      << "<tr><td>seed</td><td>" << (r.contains("seed") ? r["seed"].dump() : "?") << "</td></tr>\n"
      << "<tr><td>ROM</td><td>" << esc(js(r, "rom", "-")) << "</td></tr>\n"
      << "<tr><td>simulated time</td><td>" << num(jd(r, "sim_time_s"), 6) << " s</td></tr>\n"
      << "<tr><td>wall time, real-time factor</td><td>"
      << (wall > 0 ? num(wall, 3) + " s, RTF " + num(rtf, 2) + " (simulated s per wall s)"
                   : std::string("not recorded (--reproducible)"))
      << "</td></tr>\n"
      << "<tr><td>comm CPU</td><td>" << num(jd(cpu, "clock_hz") / 1e6, 3) << " MHz 8086, " << ju(cpu, "cycles")
      << " cycles, " << ju(cpu, "instructions") << " instructions</td></tr>\n"
      << "<tr><td>interrupts recorded</td><td>" << log.rows() << "</td></tr>\n"
      << "<tr><td>checks</td><td>" << held << " of " << jo(r, "checks").size() << " hold"
      << (unmeasured ? ", " + std::to_string(unmeasured) + " not measured" : std::string()) << "</td></tr>\n</table>\n";
    o << "<nav><a href=\"#checks\">Checks</a><a href=\"#table3\">Table 3</a><a href=\"#interrupts\">Interrupts</a>"
         "<a href=\"#timeline\">Timeline</a><a href=\"#ports\">Ports</a><a href=\"#main-cpu\">Main CPU</a>"
      << (opt.trajectory_svg.empty() ? "" : "<a href=\"#motion\">Motion</a>")
      << (opt.flame_svg.empty() ? "" : "<a href=\"#profile\">Profile</a>")
      << (opt.coverage_html.empty() ? "" : "<a href=\"#coverage\">Coverage</a>") << "</nav></header>\n";
    section_checks(o, r, !opt.interrupts_csv.empty());
    section_table3(o, r);
    section_interrupts(o, r, log);
    section_latency_causes(o, r);
    section_bound(o, r);
    section_timeline(o, log.timeline());
    section_failures(o, r, opt.interrupts_csv);
    section_ports(o, r);
    section_main_cpu(o, r);
    if (!opt.trajectory_svg.empty()) section_motion(o, r, opt);
    if (!opt.flame_svg.empty())
        o << "<section id=\"profile\"><h2>Comm CPU profile</h2>\n<p class=\"note\">Clocks of the comm CPU by call "
             "path (--profile): the whole run at the bottom, the contexts above it, each function above its caller; "
             "hover a box for its clocks. The table is <code>profile.txt</code>, the stacks <code>profile.folded</code> "
             "(docs/tools.md \"Profiler\").</p>\n<div class=\"chart\">"
          << opt.flame_svg << "</div></section>\n";
    o << opt.coverage_html;
    o << "<footer><p class=\"note\">Files: <code>report.json</code> (every figure of this page), "
         "<code>interrupts.csv</code> (one row per interrupt). Times are measured from bus cycles and pins: IR rise "
         "(8259A input), INTA 1/2 (T1 of the INTA cycles), first ISR instruction (end of the first code fetch at the "
         "handler), EOI (T1 of the OCW2 write), IRET done (first code fetch at the return address). See "
         "docs/scenarios.md.</p></footer>\n</body>\n</html>\n";
    return o.str();
}

std::string render_html(const json& report, const std::vector<InterruptRow>& unsorted, const HtmlOptions& opt) {
    std::vector<InterruptRow> rows = unsorted;
    sort_rows(rows);
    InterruptLog log(opt.window_us, opt.zoom_us);
    for (const InterruptRow& row : rows) log.add(row);
    log.finish();
    return render_html(report, log, opt);
}

void write_report_html(const std::filesystem::path& dir, const json& report, const InterruptLog& log,
                       const std::string& flame_svg, const std::string& coverage_html) {
    HtmlOptions opt;
    opt.flame_svg = flame_svg;
    opt.coverage_html = coverage_html;
    for (const char* rows : {"interrupts.csv", "interrupts.csv.gz"}) // as the run chose (RunOptions::Rows)
        if (std::filesystem::exists(dir / rows)) opt.interrupts_csv = dir / rows;
    if (report.contains("motion")) {
        opt.trajectory_svg = slurp_if_exists(dir / "trajectory.svg");
        opt.trajectory_time_svg = slurp_if_exists(dir / "trajectory_time.svg");
    }
    write_page(dir, render_html(report, log, opt));
}

std::string render_motion_html(const json& r, const HtmlOptions& opt) {
    std::ostringstream o;
    const std::string name = js(r, "scenario", "?");
    banner(o, r, "rcsim motion run");
    o << "<table class=\"meta\">\n<tr><td>scenario</td><td>" << esc(name) << "</td></tr>\n"
      << "<tr><td>simulated time</td><td>" << num(jd(r, "sim_time_s"), 6) << " s</td></tr>\n</table>\n"
      << "<nav><a href=\"#checks\">Checks</a><a href=\"#motion\">Motion</a></nav></header>\n";
    section_checks(o, r);
    section_motion(o, r, opt);
    o << "<footer><p class=\"note\">Files: <code>report.json</code>, <code>trajectory.csv</code>. See "
         "docs/motion.md.</p></footer>\n</body>\n</html>\n";
    return o.str();
}

void write_motion_report_html(const std::filesystem::path& dir, const json& report) {
    HtmlOptions opt;
    opt.trajectory_svg = slurp_if_exists(dir / "trajectory.svg");
    opt.trajectory_time_svg = slurp_if_exists(dir / "trajectory_time.svg");
    write_page(dir, render_motion_html(report, opt));
}

} // namespace rcsim::report
