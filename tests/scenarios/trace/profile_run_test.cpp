// `rcsim run --profile` through the executable (scenarios/trace/profile_run.h) on the built
// firmware: the files it writes, their agreement with each other and with the interrupt probe's
// counts, and a report that does not change.
#include "tests/support/files.h"
#include "tests/support/report_counts.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using rcsim::test::slurp;

int rcsim(const std::string& args, const fs::path& log) {
    const std::string cmd = std::string("\"") + RCSIM_EXE + "\" run \"" + RCSIM_TRACE_DATA + "/short_trace.yaml\" " +
                            args + " > \"" + log.string() + "\" 2>&1";
    return rcsim::test::exit_code_of(cmd);
}

struct Profiled {
    fs::path work;
    int rc_plain = -1, rc_profiled = -1;
    explicit Profiled(const std::string& test) : work(fs::path(RCSIM_TRACE_WORK) / test) {
        fs::remove_all(work);
        fs::create_directories(work);
        rc_plain = rcsim("--reproducible --out \"" + (work / "plain").string() + "\"", work / "plain.txt");
        rc_profiled = rcsim("--reproducible --profile --out \"" + (work / "prof").string() + "\"", work / "prof.txt");
    }
};

// profile.txt's rows: function, context -> the columns after them.
struct TableRow {
    std::uint64_t calls = 0, self = 0, inclusive = 0;
};
std::map<std::pair<std::string, std::string>, TableRow> table(const std::string& text, std::uint64_t& total) {
    std::map<std::pair<std::string, std::string>, TableRow> rows;
    std::istringstream in(text);
    std::string line;
    total = 0;
    while (std::getline(in, line)) {
        if (line.rfind("# rcsim cycle profile: ", 0) == 0) total = std::stoull(line.substr(23));
        if (line.empty() || line[0] == '#' || line.rfind("function", 0) == 0) continue;
        std::istringstream f(line);
        std::string fn, ctx, word;
        TableRow r;
        f >> fn >> ctx;
        if (ctx == "IR0" || ctx == "IR1" || ctx == "IR2" || ctx == "IR3") {
            // "IRn nested" is two words
            const auto pos = f.tellg();
            f >> word;
            if (word == "nested") ctx += " nested";
            else f.seekg(pos);
        }
        double pct;
        f >> r.calls >> r.self >> pct >> r.inclusive;
        rows[{fn, ctx}] = r;
    }
    return rows;
}

TEST(ProfileRun, TheReportIsUnchangedAndTheHtmlGainsTheFlameGraph) {
    const Profiled p("profile_same");
    ASSERT_EQ(p.rc_plain, p.rc_profiled) << slurp(p.work / "prof.txt");
    for (const char* f : {"report.json", "interrupts.csv"})
        EXPECT_TRUE(slurp(p.work / "plain" / f) == slurp(p.work / "prof" / f)) << f << " differs with --profile";
    const std::string plain = slurp(p.work / "plain" / "report.html"), html = slurp(p.work / "prof" / "report.html");
    EXPECT_EQ(plain.find("id=\"profile\""), std::string::npos);
    EXPECT_NE(html.find("<section id=\"profile\">"), std::string::npos);
    EXPECT_NE(html.find("<title>IR0 &gt; isr_port0"), std::string::npos);
    EXPECT_NE(html.find("<title>main &gt; "), std::string::npos);
}

TEST(ProfileRun, TableFoldedStacksAndTheProbeAgree) {
    const Profiled p("profile_agree");
    ASSERT_EQ(p.rc_profiled, p.rc_plain) << slurp(p.work / "prof.txt");
    std::uint64_t total = 0;
    const auto rows = table(slurp(p.work / "prof" / "profile.txt"), total);
    ASSERT_FALSE(rows.empty());
    std::uint64_t self = 0;
    for (const auto& [k, r] : rows) self += r.self;
    EXPECT_EQ(self, total) << "every clock is one function's self clock";
    const json report = json::parse(slurp(p.work / "prof" / "report.json"));
    EXPECT_LE(total, report["comm_cpu"]["cycles"].get<std::uint64_t>()) << "from the first instruction on";

    // The collapsed stacks hold the same clocks; their first frame is the context.
    std::istringstream folded(slurp(p.work / "prof" / "profile.folded"));
    std::string line;
    std::uint64_t folded_sum = 0;
    std::map<std::string, std::uint64_t> per_context;
    while (std::getline(folded, line)) {
        const auto sp = line.rfind(' ');
        ASSERT_NE(sp, std::string::npos) << line;
        const std::uint64_t n = std::stoull(line.substr(sp + 1));
        folded_sum += n;
        per_context[line.substr(0, line.find(';'))] += n;
    }
    EXPECT_EQ(folded_sum, total);
    EXPECT_GT(per_context["main"], 0u);

    // Each level's handler (the vectors crt0.s sets) completed as many calls as the probe counted
    // interrupts of that level, nested or not.
    const std::pair<const char*, const char*> handlers[] = {
        {"isr_port0", "rs232_0"}, {"isr_port1", "rs232_1"}, {"isr_port2", "rs232_2"}, {"isr_dpram", "dpram"}};
    for (unsigned level = 0; level < 4; ++level) {
        const std::string ctx = "IR" + std::to_string(level);
        const auto [fn, source] = handlers[level];
        std::uint64_t calls = 0;
        for (const std::string& c : {ctx, ctx + " nested"})
            if (rows.count({fn, c})) calls += rows.at({fn, c}).calls;
        EXPECT_EQ(calls, rcsim::test::completed(report, source)) << fn;
        EXPECT_GT(per_context[ctx], 0u) << ctx;
    }

    // main_loop calls the static functions of main.c by name: mb_pump once per pass and
    // area_watch once per port and pass, so both completed calls in the main context. Their time
    // is theirs, not that of the global before them in the ROM (mb_post) at an offset.
    for (const char* fn : {"mb_pump", "area_watch"}) {
        ASSERT_TRUE(rows.count({fn, "main"})) << fn << " has no row of its own";
        EXPECT_GT(rows.at({fn, "main"}).calls, 0u) << fn;
    }
    EXPECT_GE(rows.at({"area_watch", "main"}).calls, 3 * rows.at({"mb_pump", "main"}).calls);
    for (const auto& [k, r] : rows) EXPECT_NE(k.first.rfind("mb_post+0x", 0), 0u) << k.first;
}

TEST(ProfileRun, BadUseIsOneMessageAndExitCode2) {
    const fs::path work = fs::path(RCSIM_TRACE_WORK) / "profile_errors";
    fs::create_directories(work);
    std::ofstream(work / "bad.sym") << "start F000:0000\nbroken line with too many words here\n";
    EXPECT_EQ(rcsim("--profile --symbols \"" + (work / "bad.sym").string() + "\" --out \"" + (work / "o").string() + "\"",
                    work / "bad_sym.txt"),
              2);
    EXPECT_NE(slurp(work / "bad_sym.txt").find("bad.sym:2"), std::string::npos) << slurp(work / "bad_sym.txt");
}

} // namespace
