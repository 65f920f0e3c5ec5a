// report.html and interrupts.csv from real runs of a short three-port scenario: the CSV against
// report.json, and two runs of the rcsim executable giving byte-identical files.
#include "tests/support/files.h"
#include "tests/support/report_counts.h"
#include "scenarios/run/runner.h"
#include "tests/support/sc_test.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace rcsim;
namespace fs = std::filesystem;

namespace {

using rcsim::test::slurp;

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> f;
    std::string cur;
    for (char c : line) {
        if (c == ',') {
            f.push_back(cur);
            cur.clear();
        } else {
            cur += c;
        }
    }
    f.push_back(cur);
    return f;
}

std::size_t count_of(const std::string& s, const std::string& what) {
    std::size_t n = 0;
    for (auto at = s.find(what); at != std::string::npos; at = s.find(what, at + what.size())) ++n;
    return n;
}

} // namespace

TEST(ReportRun, CsvHasOneConsistentRowPerInterruptOfTheReport) {
    const fs::path out = fs::path(RCSIM_REPORT_WORK) / "in_process";
    fs::remove_all(out);
    RunOptions opt;
    opt.out_dir = out.string();
    opt.reproducible = true;
    nlohmann::json report;
    run_scenario(load_scenario(RCSIM_REPORT_DATA "/short_report.yaml"), opt, report);

    std::ifstream in(out / "interrupts.csv");
    ASSERT_TRUE(in) << "no interrupts.csv";
    std::string line;
    std::getline(in, line);
    const auto head = split(line);
    ASSERT_EQ(head.size(), 16u) << line;
    auto col = [&head](const std::string& name) {
        for (std::size_t i = 0; i < head.size(); ++i)
            if (head[i] == name) return i;
        ADD_FAILURE() << "column " << name << " missing";
        return std::size_t{0};
    };
    const std::size_t c_src = col("source"), c_rise = col("ir_rise_us"), c_i1 = col("inta1_us"),
                      c_i2 = col("inta2_us"), c_isr = col("first_isr_us"), c_eoi = col("eoi_us"),
                      c_iret = col("iret_done_us"), c_lat = col("latency_us"), c_svc = col("service_us"),
                      c_rx = col("rx"), c_depth = col("depth");
    std::map<std::string, std::uint64_t> per_source;
    std::uint64_t rx = 0, rows = 0, nested = 0, with_rise = 0;
    double last_inta1 = -1;
    while (std::getline(in, line)) {
        const auto f = split(line);
        ASSERT_EQ(f.size(), head.size()) << line;
        ++rows;
        ++per_source[f[c_src]];
        const double i1 = std::stod(f[c_i1]), i2 = std::stod(f[c_i2]), isr = std::stod(f[c_isr]),
                     iret = std::stod(f[c_iret]);
        EXPECT_GE(i1, last_inta1) << "rows in entry order: " << line;
        last_inta1 = i1;
        if (!f[c_rise].empty()) {
            ++with_rise;
            const double rise = std::stod(f[c_rise]);
            EXPECT_LE(rise, i1) << line;
            EXPECT_NEAR(std::stod(f[c_lat]), isr - rise, 1e-5) << line;
        } else {
            EXPECT_TRUE(f[c_lat].empty()) << line;
        }
        EXPECT_LT(i1, i2) << line;
        EXPECT_LT(i2, isr) << line;
        EXPECT_LE(isr, iret) << line;
        if (!f[c_eoi].empty()) {
            const double eoi = std::stod(f[c_eoi]);
            EXPECT_LE(isr, eoi) << line;
            EXPECT_LE(eoi, iret) << line;
        }
        EXPECT_NEAR(std::stod(f[c_svc]), iret - isr, 1e-5) << line;
        rx += f[c_rx] == "1";
        nested += f[c_depth] != "0";
    }
    EXPECT_GT(rows, 100u);
    EXPECT_GT(with_rise, 0u);
    std::uint64_t total = 0;
    for (const char* s : {"rs232_0", "rs232_1", "rs232_2", "dpram"}) {
        EXPECT_EQ(per_source[s], rcsim::test::completed(report, s)) << s;
        EXPECT_GT(per_source[s], 0u) << s;
        total += per_source[s];
    }
    EXPECT_EQ(total, rows) << "no other source";
    EXPECT_EQ(rx, report["interrupts"]["rs232_rx"]["count"].get<std::uint64_t>());
    RecordProperty("nested", static_cast<int>(nested));

    const std::string html = slurp(out / "report.html");
    ASSERT_FALSE(html.empty());
    for (const char* id : {"header", "checks", "table3", "interrupts", "timeline", "ports", "main-cpu"})
        EXPECT_NE(html.find(std::string(" id=\"") + id + "\""), std::string::npos) << id;
    EXPECT_EQ(count_of(html, "<svg "), 14u);
    EXPECT_NE(html.find(report["passed"].get<bool>() ? "PASSED" : "FAILED"), std::string::npos);
}

TEST(ReportRun, TwoRunsOfTheExecutableGiveIdenticalFilesAndTheSummaryEndsWithTheHtml) {
    const fs::path work = fs::path(RCSIM_REPORT_WORK) / "cli";
    fs::remove_all(work);
    fs::create_directories(work);
    std::vector<std::string> outputs;
    for (const char* run : {"a", "b"}) {
        const fs::path dir = work / run, log = work / (std::string(run) + ".txt");
        const std::string cmd = std::string("\"") + RCSIM_EXE + "\" run \"" RCSIM_REPORT_DATA "/short_report.yaml\" --out \"" +
                                dir.string() + "\" --reproducible > \"" + log.string() + "\" 2>&1";
        const int rc = std::system(cmd.c_str());
        ASSERT_NE(rc, -1);
        outputs.push_back(slurp(log));
        ASSERT_TRUE(fs::exists(dir / "report.html")) << outputs.back();
    }
    for (const char* f : {"report.html", "interrupts.csv", "report.json"}) {
        const std::string a = slurp(work / "a" / f), b = slurp(work / "b" / f);
        EXPECT_GT(a.size(), 1000u) << f;
        EXPECT_TRUE(a == b) << f << " differs between two identical runs";
    }
    // The printed summary ends with the path of report.html.
    std::string last = outputs[0];
    while (!last.empty() && last.back() == '\n') last.pop_back();
    last = last.substr(last.rfind('\n') + 1);
    EXPECT_NE(last.find((work / "a" / "report.html").string()), std::string::npos) << outputs[0];
}
