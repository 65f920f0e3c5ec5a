// The latency causes of real runs through the rcsim executable (docs/scenarios.md "Latency
// causes"): the shipped firmware's three_ports_9600 whose start-up interrupt waits with IF = 0
// since the reset until the firmware's first STI, and the all-C firmware whose worst cases are
// other handlers in service; in report.json, the printed summary and report.html.
#include "tests/support/files.h"
#include "tests/support/sc_test.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
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
    EXPECT_NE(r.summary.find("rs232_0 IR at " + [&] {
                  char buf[96];
                  std::snprintf(buf, sizeof buf, "%.3f us, latency %.1f us", top["ir_rise_us"].get<double>(),
                                top["latency_us"].get<double>());
                  return std::string(buf);
              }()),
              std::string::npos)
        << r.summary;
    EXPECT_NE(r.summary.find("interrupts disabled (IF=0) since 0.000 us (reset at FFFF:0000)"), std::string::npos)
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
}
