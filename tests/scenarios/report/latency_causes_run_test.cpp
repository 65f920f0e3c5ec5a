// The latency causes of real runs through the rcsim executable (docs/scenarios.md "Latency
// causes"): the shipped firmware's three_ports_9600 whose start-up interrupt waits with IF = 0
// since the reset until the firmware's first STI, and the all-C firmware whose worst cases are
// other handlers in service; in report.json, the printed summary and report.html.
#include "models/plumbing/sim_time_text.h"
#include "tests/support/files.h"
#include "tests/support/sc_test.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

namespace fs = std::filesystem;
using nlohmann::json;
using rcsim::test::slurp;

namespace {

struct Outcome {
    json report;
    std::string summary, html;
};

Outcome run_rcsim(const std::string& name, const std::string& extra) {
    const fs::path dir = fs::path(RCSIM_REPORT_WORK) / name, log = fs::path(RCSIM_REPORT_WORK) / (name + ".txt");
    fs::remove_all(dir);
    fs::create_directories(RCSIM_REPORT_WORK);
    const std::string cmd = std::string("\"") + RCSIM_EXE + "\" run \"" RCSIM_SOURCE_DIR
                            "/scenarios/three_ports_9600.yaml\" --out \"" + dir.string() + "\" --reproducible " + extra +
                            " > \"" + log.string() + "\" 2>&1";
    EXPECT_NE(rcsim::test::exit_code_of(cmd), -1);
    Outcome r;
    r.summary = slurp(log);
    r.html = slurp(dir / "report.html");
    r.report = json::parse(slurp(dir / "report.json"));
    return r;
}

std::string html_escaped(std::string s) {
    std::string out;
    for (char c : s) out += c == '&' ? "&amp;" : c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '"' ? "&quot;" : std::string(1, c);
    return out;
}

// Every source: the longest latency first, then only those over the budget, longest first; each
// with a cause, words, and phases that add up to it; each in report.html.
void expect_worst_lists(const Outcome& r) {
    const double budget = r.report["table3"]["budget_us"].get<double>();
    for (const char* name : {"rs232_0", "rs232_1", "rs232_2", "dpram", "rs232_rx"}) {
        SCOPED_TRACE(name);
        const json& i = r.report["interrupts"][name];
        ASSERT_TRUE(i.contains("worst"));
        const json& w = i["worst"];
        if (i["latency_us"]["max"].is_null()) {
            EXPECT_TRUE(w.empty());
            continue;
        }
        ASSERT_FALSE(w.empty());
        EXPECT_EQ(w[0]["latency_us"].get<double>(), i["latency_us"]["max"].get<double>());
        std::uint64_t over = 0;
        for (std::size_t k = 0; k < w.size(); ++k) {
            const json& e = w[k];
            const double latency = e["latency_us"].get<double>();
            if (k > 0) {
                EXPECT_GT(latency, budget);
                EXPECT_LE(latency, w[k - 1]["latency_us"].get<double>());
            }
            over += latency > budget;
            EXPECT_FALSE(e["cause"].get<std::string>().empty());
            EXPECT_FALSE(e["text"].get<std::string>().empty());
            double sum = 0;
            for (const json& p : e["phases"]) sum += p["us"].get<double>();
            EXPECT_NEAR(sum, latency, 1e-6);
            EXPECT_EQ(e["phases"][0]["from_us"], e["ir_rise_us"]);
            EXPECT_NE(r.html.find(html_escaped(e["text"].get<std::string>())), std::string::npos) << e["text"];
        }
        for (const json& e : w) { // its own service, with what blocked (docs/scenarios.md "Latency causes")
            EXPECT_LE(e["blocking_us"].get<double>(), e["service_us"].get<double>() + 1e-9);
            EXPECT_GT(e["blocking_us"].get<double>(), 0.0);
            EXPECT_FALSE(e["path"].empty());
            // An RS-232 service's RX FIFO level: at most the 82510's 4-byte FIFO (docs/serial.md).
            if (std::string(name).rfind("rs232_", 0) == 0 && e.contains("rx_fifo_level")) {
                EXPECT_LE(e["rx_fifo_level"].get<unsigned>(), 4u);
            }
        }
        EXPECT_LE(over, i["over_budget"].get<std::uint64_t>());
        if (i["over_budget"].get<std::uint64_t>() <= 20) {
            EXPECT_EQ(over, i["over_budget"].get<std::uint64_t>());
        }
    }
}

} // namespace

// Start-up: the firmware enables interrupts (its first STI, in irq_on) only once every port is
// programmed; an RS-232 request that rises before waits with IF = 0 since the reset. That
// interrupt is reported apart (interrupts.startup, docs/scenarios.md "Start-up") with its cause,
// in report.json, the summary's start-up line and report.html; it is in no source's worst list.
TEST(LatencyCausesRun, ShippedFirmwareStartUpInterruptWaitsWithInterruptsDisabledSinceReset) {
    const Outcome r = run_rcsim("causes_shipped", "");
    const json& st = r.report["interrupts"]["startup"];
    ASSERT_FALSE(st["records"].empty());
    const json& top = st["records"][0];
    EXPECT_EQ(top["source"], "rs232_0");
    EXPECT_EQ(top["cause"], "interrupts_disabled");
    const json& d = top["detail"]["interrupts_disabled"];
    EXPECT_EQ(d["by"], "reset");
    EXPECT_EQ(d["since_us"].get<double>(), 0.0);
    EXPECT_EQ(d["at"], "FFFF:0000");
    EXPECT_EQ(d["enabled_by"], "STI");
    EXPECT_EQ(d["enabled_symbol"], "irq_on");
    EXPECT_LT(top["ir_rise_us"].get<double>(), d["until_us"].get<double>());
    // IF came back at the STI's following boundary: start-up ends within a few clocks of it.
    EXPECT_LE(d["until_us"].get<double>(), st["interrupts_enabled_us"].get<double>());
    EXPECT_EQ(top["phases"][0]["phase"], "interrupts_disabled");
    double sum = 0;
    for (const json& p : top["phases"]) sum += p["us"].get<double>();
    EXPECT_NEAR(sum, top["latency_us"].get<double>(), 1e-6);
    EXPECT_NE(r.summary.find("rs232_0 IR at " + rcsim::sim_time_text_us(top["ir_rise_us"].get<double>()) + [&] {
                  char buf[96];
                  std::snprintf(buf, sizeof buf, ", latency %.1f us", top["latency_us"].get<double>());
                  return std::string(buf);
              }()),
              std::string::npos)
        << r.summary;
    EXPECT_NE(r.summary.find("interrupts disabled (IF=0) since 0.000 s (reset at FFFF:0000)"), std::string::npos)
        << r.summary;
    EXPECT_NE(r.html.find("rs232_0 (start-up, not judged)"), std::string::npos);
    EXPECT_NE(r.html.find(html_escaped(top["text"].get<std::string>())), std::string::npos);
    for (const json& w : r.report["interrupts"]["rs232_0"]["worst"])
        EXPECT_NE(w["ir_rise_us"], top["ir_rise_us"]) << "a start-up interrupt in the judged worst list";
    expect_worst_lists(r);
}

// The all-C firmware nests its handlers: its worst latencies wait for other levels in service.
TEST(LatencyCausesRun, AllCFirmwareWorstCasesHaveTheirCauses) {
    const Outcome r = run_rcsim("causes_c", "--rom \"" RCSIM_COMM_FW_C_ROM "\"");
    const json& i = r.report["interrupts"]["rs232_rx"];
    ASSERT_GT(i["over_budget"].get<std::uint64_t>(), 20u);
    ASSERT_EQ(i["worst"].size(), 20u);
    std::size_t in_service = 0;
    for (const json& e : i["worst"]) in_service += e["cause"] == "in_service";
    EXPECT_GT(in_service, 0u);
    EXPECT_NE(r.summary.find("longest latencies and their causes"), std::string::npos);
    expect_worst_lists(r);
    // A receive interrupt begins with its character in the FIFO: of the 20 longest receive
    // latencies, each RS-232 record reached its handler with at least one.
    for (const json& e : i["worst"]) EXPECT_GE(e["rx_fifo_level"].get<unsigned>(), 1u) << e["ir_rise_us"];
    // The summary's line of each source's longest latency lists every phase kind of 10 % or more
    // of it (the text names only the largest), each with its total.
    for (const char* name : {"rs232_0", "rs232_1", "rs232_2", "dpram"}) {
        const json& w = r.report["interrupts"][name]["worst"];
        if (w.empty()) continue;
        const double latency = w[0]["latency_us"].get<double>();
        std::map<std::string, double> kinds;
        for (const json& p : w[0]["phases"])
            kinds[p["phase"].get<std::string>() + (p.contains("source") ? " " + p["source"].get<std::string>() : "")] +=
                p["us"].get<double>();
        const std::size_t line = r.summary.find(std::string("  ") + name + " latency max ");
        ASSERT_NE(line, std::string::npos) << name;
        const std::size_t next = r.summary.find('\n', line) + 1;
        const std::string phases = r.summary.substr(next, r.summary.find('\n', next) - next);
        std::size_t listed = 0;
        for (const auto& [kind, us] : kinds) {
            char want[96];
            std::snprintf(want, sizeof want, "%s %.1f us", kind.c_str(), us);
            const bool shown = phases.find(want) != std::string::npos;
            EXPECT_EQ(shown, us >= 0.1 * latency) << name << ": " << want << " in \"" << phases << "\"";
            listed += us >= 0.1 * latency;
        }
        EXPECT_GE(listed, 1u);
        EXPECT_EQ(phases.rfind("    phases of 10 % or more: ", 0), 0u) << phases;
    }
}
