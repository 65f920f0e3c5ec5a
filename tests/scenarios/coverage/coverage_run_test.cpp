// `rcsim run --coverage`, `rcsim sweep --coverage` and `rcsim merge` through the executable
// (scenarios/coverage): counts of a ROM of hand-counted control flow, the shipped firmware's BREAK
// path hit only where a BREAK comes, reports unchanged by coverage, lcov and genhtml reading the
// files, the sweep's merge equal to `lcov -a`, and bad input to `rcsim merge`.
#include "scenarios/coverage/tracefile.h"
#include "tests/support/files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>

namespace fs = std::filesystem;
using namespace rcsim::coverage;
using rcsim::test::exit_code_of;
using rcsim::test::slurp;

namespace {

const std::string kData = RCSIM_COVERAGE_DATA;
const std::string kIsr = std::string(RCSIM_COMM_FW_SOURCES) + "/isr.s";

std::string q(const fs::path& p) { return "\"" + p.string() + "\""; }

/// A fresh work directory for one test (CTest runs the tests in parallel, each in its process).
fs::path work(const std::string& test) {
    const fs::path w = fs::path(RCSIM_COVERAGE_WORK) / test;
    fs::remove_all(w);
    fs::create_directories(w);
    return w;
}

/// rcsim COMMAND ARGS; stdout and stderr into `log`. Its exit code.
int rcsim_cmd(const std::string& args, const fs::path& log) {
    return exit_code_of(q(RCSIM_EXE) + " " + args + " > " + q(log) + " 2>&1");
}

/// `rcsim run SCENARIO --reproducible --out DIR EXTRA`; fails the test on an exit code above 1.
void run(const std::string& scenario, const fs::path& dir, const std::string& extra = "") {
    const int rc = rcsim_cmd("run " + q(kData + "/" + scenario) + " --reproducible --out " + q(dir) + " " + extra,
                         dir.string() + ".log");
    ASSERT_LE(rc, 1) << slurp(dir.string() + ".log");
}

/// The 1-based line of isr.s holding `text` (exactly one).
unsigned isr_line(const std::string& text) {
    std::ifstream in(kIsr);
    std::string row;
    unsigned found = 0;
    for (unsigned n = 1; std::getline(in, row); ++n)
        if (row.find(text) != std::string::npos) {
            EXPECT_EQ(found, 0u) << "'" << text << "' twice in isr.s";
            found = n;
        }
    EXPECT_NE(found, 0u) << "'" << text << "' not in isr.s";
    return found;
}

bool same(const FileCoverage& a, const FileCoverage& b) {
    if (a.lines != b.lines || a.branches != b.branches || a.functions.size() != b.functions.size()) return false;
    for (const auto& [name, fn] : a.functions) {
        const auto it = b.functions.find(name);
        if (it == b.functions.end() || it->second.line != fn.line || it->second.count != fn.count) return false;
    }
    return true;
}

} // namespace

// coverage_kat.asm's header derives each count by hand; the symbols (coverage_kat.sym) make
// 16-byte address ranges its "lines": main F0000 (lines 1, 2), count F0020 (3), unused F0030 (4).
TEST(CoverageKat, LineBranchAndFunctionCountsAreTheHandDerivedOnes) {
    const fs::path w = work("kat");
    run("kat.yaml", w / "run", "--rom " + q(RCSIM_COVERAGE_KAT_ROM) + " --symbols " + q(kData + "/coverage_kat.sym") + " --coverage");
    const Tracefile t = read_tracefile(w / "run" / "coverage.info");
    ASSERT_EQ(t.files.size(), 1u);
    EXPECT_EQ(t.files.begin()->first, fs::absolute(w / "run" / "coverage_rom.txt").lexically_normal().string());
    const FileCoverage& f = t.files.begin()->second;
    EXPECT_EQ(f.lines, (std::map<unsigned, std::uint64_t>{{1, 11}, {2, 3}, {3, 14}, {4, 0}}));
    using B = std::map<FileCoverage::BranchKey, std::optional<std::uint64_t>>;
    EXPECT_EQ(f.branches, (B{{{1, 0, 0}, 2}, {{1, 0, 1}, 1},   // jnz .l1
                             {{2, 0, 0}, 1}, {{2, 0, 1}, 0},   // je .eq
                             {{3, 0, 0}, 6}, {{3, 0, 1}, 2},   // loop .l2
                             {{3, 1, 0}, 2}, {{3, 1, 1}, 0}})); // jcxz .z
    ASSERT_EQ(f.functions.size(), 3u);
    EXPECT_EQ(f.functions.at("main").line, 1u);
    EXPECT_EQ(f.functions.at("main").count, 1u);
    EXPECT_EQ(f.functions.at("count").line, 3u);
    EXPECT_EQ(f.functions.at("count").count, 2u);
    EXPECT_EQ(f.functions.at("unused").line, 4u);
    EXPECT_EQ(f.functions.at("unused").count, 0u);
    EXPECT_EQ(slurp(w / "run" / "coverage_rom.txt"), "F0000  main+0x0\nF0010  main+0x10\nF0020  count+0x0\nF0030  unused+0x0\n");
}

// The counters chain in front of the profiler on the one step hook: neither changes the other.
TEST(CoverageFirmware, WithTheProfilerTheCountsAndTheProfileAreTheSame) {
    const fs::path w = work("with_profile");
    run("clean.yaml", w / "alone", "--coverage");
    run("clean.yaml", w / "both", "--coverage --profile");
    run("clean.yaml", w / "profile", "--profile");
    const Tracefile alone = read_tracefile(w / "alone" / "coverage.info"), both = read_tracefile(w / "both" / "coverage.info");
    ASSERT_EQ(alone.files.size(), both.files.size());
    for (const auto& [sf, f] : alone.files) {
        ASSERT_TRUE(both.files.count(sf)) << sf;
        EXPECT_TRUE(same(f, both.files.at(sf))) << sf;
    }
    const std::string profile = slurp(w / "profile" / "profile.txt");
    EXPECT_NE(profile.find("isr_port0"), std::string::npos);
    EXPECT_EQ(profile, slurp(w / "both" / "profile.txt"));
}

TEST(CoverageKat, AUserRomWithoutSymbolsIsBadInput) {
    const fs::path w = work("kat_no_symbols");
    const int rc = rcsim_cmd("run " + q(kData + "/kat.yaml") + " --out " + q(w / "run") + " --rom " + q(RCSIM_COVERAGE_KAT_ROM) +
                             " --coverage",
                         w / "log.txt");
    EXPECT_EQ(rc, 2);
    EXPECT_NE(slurp(w / "log.txt").find("--coverage: the ROM " + std::string(RCSIM_COVERAGE_KAT_ROM) + " has no symbols"),
              std::string::npos)
        << slurp(w / "log.txt");
}

// The BREAK path of isr.s's line_status: the count of BREAKs, then the reset asked for (the main
// loop runs it: docs/firmware.md "Faults and the rule").
TEST(CoverageFirmware, BreakLinesAreHitInTheBreakScenarioAndNotInTheCleanOne) {
    const fs::path w = work("break");
    run("break.yaml", w / "break", "--coverage");
    run("clean.yaml", w / "clean", "--coverage");
    const Tracefile brk = read_tracefile(w / "break" / "coverage.info"), clean = read_tracefile(w / "clean" / "coverage.info");
    const FileCoverage& b = brk.files.at(kIsr);
    const FileCoverage& c = clean.files.at(kIsr);
    for (const char* text : {"inc\tword ptr _n_break[si]", "br\treset_ask_r"}) {
        const unsigned line = isr_line(text);
        EXPECT_GT(b.lines.at(line), 0u) << text;
        EXPECT_EQ(c.lines.at(line), 0u) << text;
    }
    // line_status's first test: BKD set jumps on (not taken), clear takes `jz ls_err`.
    const unsigned jz = isr_line("\tjz\tls_err");
    EXPECT_GT(b.branches.at({jz, 0, 1}).value_or(0), 0u);
    EXPECT_EQ(c.branches.at({jz, 0, 1}), std::nullopt) << "line_status never runs without a BREAK or a line error";
    // The receive path runs in both.
    const unsigned rx = isr_line("rx_char_entry:") + 1;
    EXPECT_GT(c.lines.at(rx), 0u);
    // report.html has the section and links genhtml's pages.
    const std::string html = slurp(w / "break" / "report.html");
    EXPECT_NE(html.find("<section id=\"coverage\">"), std::string::npos);
    EXPECT_NE(html.find("href=\"coverage/index.html\""), std::string::npos);
    EXPECT_NE(html.find("<tr><td>isr_port0</td><td>isr.s:"), std::string::npos) << "the handlers' table";
    EXPECT_TRUE(fs::exists(w / "break" / "coverage" / "index.html"));
}

TEST(CoverageFirmware, ReportsAreByteIdenticalWithAndWithoutCoverage) {
    const fs::path w = work("identical");
    run("break.yaml", w / "off", "--trace " + q(w / "off.trace.json"));
    run("break.yaml", w / "on", "--trace " + q(w / "on.trace.json") + " --coverage");
    ASSERT_TRUE(fs::exists(w / "on" / "coverage.info"));
    EXPECT_FALSE(fs::exists(w / "off" / "coverage.info"));
    for (const char* file : {"report.json", "interrupts.csv"}) {
        const std::string off = slurp(w / "off" / file);
        EXPECT_FALSE(off.empty()) << file;
        EXPECT_EQ(off, slurp(w / "on" / file)) << file;
    }
    EXPECT_EQ(slurp(w / "off.trace.json"), slurp(w / "on.trace.json"));
}

// The core's fast-forward stays on under --coverage and tells the counters the instruction
// boundaries it skipped (i8086::SkipHook): the tracefile (lines, functions, BRDA taken / not
// taken) is the one of the run that executes every instruction (board: {fast_forward: false}),
// with traffic and on an idle board, where most of the run is forwarded.
TEST(CoverageFirmware, TheTracefileIsByteIdenticalWithTheFastForwardOffAndOn) {
    const fs::path w = work("fast_forward");
    for (const char* scenario : {"clean", "idle"}) {
        const std::string text = slurp(kData + "/" + scenario + ".yaml");
        ASSERT_EQ(text.find("\nboard:"), std::string::npos) << scenario;
        for (const char* value : {"false", "true"}) {
            const fs::path yaml = w / (std::string(scenario) + "_" + value + ".yaml");
            std::ofstream(yaml) << text << "board: {fast_forward: " << value << "}\n";
            const fs::path dir = w / (std::string(scenario) + "_" + value);
            const int rc = rcsim_cmd("run " + q(yaml) + " --reproducible --coverage --out " + q(dir), dir.string() + ".log");
            ASSERT_LE(rc, 1) << slurp(dir.string() + ".log");
        }
        const std::string off = slurp(w / (std::string(scenario) + "_false") / "coverage.info");
        EXPECT_NE(off.find("BRDA:"), std::string::npos) << scenario;
        EXPECT_EQ(off, slurp(w / (std::string(scenario) + "_true") / "coverage.info")) << scenario;
        EXPECT_EQ(slurp(w / (std::string(scenario) + "_false") / "report.json"),
                  slurp(w / (std::string(scenario) + "_true") / "report.json"))
            << scenario;
    }
}

// lcov --summary and genhtml read the tracefile; lcov's figures are ours.
TEST(CoverageFirmware, LcovSummaryAndGenhtmlReadTheTracefile) {
    const fs::path w = work("lcov");
    run("break.yaml", w / "run", "--coverage");
    const fs::path info = w / "run" / "coverage.info";
    ASSERT_EQ(exit_code_of(std::string(RCSIM_LCOV) + " --rc lcov_branch_coverage=1 --summary " + q(info) + " > " +
                           q(w / "summary.txt") + " 2>&1"),
              0)
        << slurp(w / "summary.txt");
    const Summary s = summarize(read_tracefile(info));
    const std::string summary = slurp(w / "summary.txt");
    auto figure = [&summary](const std::string& what) {
        std::smatch m;
        const std::regex re(what + R"(\.*: [0-9.]+% \(([0-9]+) of ([0-9]+) )");
        EXPECT_TRUE(std::regex_search(summary, m, re)) << what << " in\n" << summary;
        return m.size() == 3 ? std::make_pair(std::stoull(m[1]), std::stoull(m[2])) : std::make_pair(0ull, 0ull);
    };
    EXPECT_EQ(figure("lines"), std::make_pair(static_cast<unsigned long long>(s.lines_hit), static_cast<unsigned long long>(s.lines_found)));
    EXPECT_EQ(figure("functions"),
              std::make_pair(static_cast<unsigned long long>(s.functions_hit), static_cast<unsigned long long>(s.functions_found)));
    EXPECT_EQ(figure("branches"),
              std::make_pair(static_cast<unsigned long long>(s.branches_hit), static_cast<unsigned long long>(s.branches_found)));
    EXPECT_GT(s.lines_hit, 0u);
    // genhtml renders isr.s with its source lines.
    ASSERT_EQ(exit_code_of(std::string(RCSIM_GENHTML) + " --quiet --branch-coverage -o " + q(w / "html") + " " + q(info) +
                           " > " + q(w / "genhtml.txt") + " 2>&1"),
              0)
        << slurp(w / "genhtml.txt");
    bool isr_page = false;
    for (const auto& e : fs::recursive_directory_iterator(w / "html"))
        if (e.path().filename() == "isr.s.gcov.html")
            isr_page = slurp(e.path()).find("line_status:") != std::string::npos;
    EXPECT_TRUE(isr_page) << "no isr.s page with its source";
}

TEST(CoverageSweep, TheMergedTracefileHasTheCountsOfLcovA) {
    const fs::path w = work("sweep");
    const int rc = rcsim_cmd("sweep " + q(kData + "/sweep.yaml") + " --out " + q(w / "runs") + " --jobs 2 --coverage", w / "log.txt");
    ASSERT_LE(rc, 1) << slurp(w / "log.txt");
    std::vector<fs::path> infos;
    for (const auto& e : fs::directory_iterator(w / "runs"))
        if (fs::exists(e.path() / "coverage.info")) infos.push_back(e.path() / "coverage.info");
    ASSERT_EQ(infos.size(), 2u);
    std::string cmd = std::string(RCSIM_LCOV) + " --quiet --rc lcov_branch_coverage=1";
    for (const fs::path& i : infos) cmd += " -a " + q(i);
    ASSERT_EQ(exit_code_of(cmd + " -o " + q(w / "lcov.info") + " > " + q(w / "lcov.txt") + " 2>&1"), 0) << slurp(w / "lcov.txt");
    const Tracefile ours = read_tracefile(w / "runs" / "coverage.info"), lcov = read_tracefile(w / "lcov.info");
    ASSERT_EQ(ours.files.size(), lcov.files.size());
    for (const auto& [sf, f] : lcov.files) {
        ASSERT_TRUE(ours.files.count(sf)) << sf;
        EXPECT_TRUE(same(ours.files.at(sf), f)) << sf;
    }
    // The merge is the runs' sum: more than either run alone on the receive path.
    const Tracefile one = read_tracefile(infos[0]);
    const unsigned rx = isr_line("rx_char_entry:") + 1;
    EXPECT_GT(ours.files.at(kIsr).lines.at(rx), one.files.at(kIsr).lines.at(rx));
    // rcsim merge of the same folder writes the same tracefile.
    ASSERT_EQ(rcsim_cmd("merge " + q(w / "runs") + " --out " + q(w / "merged"), w / "merge.txt"), 0) << slurp(w / "merge.txt");
    EXPECT_EQ(slurp(w / "merged" / "coverage.info"), slurp(w / "runs" / "coverage.info"));
}

TEST(CoverageMerge, AMalformedTracefileIsBadInputNamingIt) {
    const fs::path w = work("merge_bad");
    fs::create_directories(w / "sweep" / "a");
    std::ofstream(w / "sweep" / "a" / "report.json") << "{\"name\": \"a\", \"passed\": true, \"checks\": []}\n";
    std::ofstream(w / "sweep" / "a" / "coverage.info") << "TN:\nSF:/x.s\nDA:7,seven\nend_of_record\n";
    EXPECT_EQ(rcsim_cmd("merge " + q(w / "sweep"), w / "log.txt"), 2);
    const std::string log = slurp(w / "log.txt");
    EXPECT_NE(log.find((w / "sweep" / "a" / "coverage.info").string() + ":3: DA count 'seven'"), std::string::npos) << log;
}
