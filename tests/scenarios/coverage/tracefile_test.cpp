// The lcov tracefile (scenarios/coverage/tracefile.h): what it reads, how it merges (lcov -a's
// rules, from lcov's geninfo(1) / lcov(1) manual pages), what it writes, and the errors that name
// the file and line of bad input.
#include "models/plumbing/config_error.h"
#include "scenarios/coverage/tracefile.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace rcsim::coverage;

namespace {

// Each test writes under its own folder: ctest runs the tests of this file in parallel, and a
// file one test truncates must never be the one another test is reading.
fs::path write(const std::string& name, const std::string& text) {
    const fs::path dir = fs::path(RCSIM_COVERAGE_WORK) / "tracefile" /
                         ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::create_directories(dir);
    std::ofstream(dir / name, std::ios::binary) << text;
    return dir / name;
}

std::string error_of(const fs::path& file) {
    try {
        read_tracefile(file);
    } catch (const rcsim::ConfigError& e) {
        return e.what();
    }
    return "(no error)";
}

const char* const kOne = "TN:\nSF:/src/a.s\nFN:3,f\nFNDA:2,f\nFNF:1\nFNH:1\n"
                         "BRDA:4,0,0,1\nBRDA:4,0,1,-\nBRF:2\nBRH:1\nDA:3,2\nDA:4,1\nDA:5,0\nLF:3\nLH:2\nend_of_record\n";

} // namespace

TEST(Tracefile, ReadsTheRecords) {
    const Tracefile t = read_tracefile(write("one.info", kOne));
    ASSERT_EQ(t.files.size(), 1u);
    const FileCoverage& f = t.files.at("/src/a.s");
    EXPECT_EQ(f.lines, (std::map<unsigned, std::uint64_t>{{3, 2}, {4, 1}, {5, 0}}));
    EXPECT_EQ(f.functions.at("f").line, 3u);
    EXPECT_EQ(f.functions.at("f").count, 2u);
    EXPECT_EQ(f.branches.at({4, 0, 0}), std::optional<std::uint64_t>(1));
    EXPECT_EQ(f.branches.at({4, 0, 1}), std::nullopt);
}

TEST(Tracefile, WritesWhatItReads) {
    const Tracefile t = read_tracefile(write("one.info", kOne));
    std::ostringstream o;
    write_tracefile(o, t);
    EXPECT_EQ(o.str(), kOne);
}

TEST(Tracefile, MergeAddsCountsAndADashIsNoCount) {
    Tracefile a = read_tracefile(write("one.info", kOne));
    const Tracefile b = read_tracefile(write(
        "two.info", "SF:/src/a.s\nFN:3,f\nFNDA:5,f\nBRDA:4,0,0,-\nBRDA:4,0,1,7\nDA:3,5\nDA:6,1\nend_of_record\n"
                    "SF:/src/b.c\nFN:10,g\nFNDA:0,g\nend_of_record\n"));
    merge_into(a, b);
    const FileCoverage& f = a.files.at("/src/a.s");
    EXPECT_EQ(f.lines, (std::map<unsigned, std::uint64_t>{{3, 7}, {4, 1}, {5, 0}, {6, 1}}));
    EXPECT_EQ(f.functions.at("f").count, 7u);
    EXPECT_EQ(f.branches.at({4, 0, 0}), std::optional<std::uint64_t>(1)); // 1 + "-"
    EXPECT_EQ(f.branches.at({4, 0, 1}), std::optional<std::uint64_t>(7)); // "-" + 7
    EXPECT_EQ(a.files.at("/src/b.c").functions.at("g").line, 10u);
    const Summary s = summarize(a);
    EXPECT_EQ(s.lines_found, 4u);
    EXPECT_EQ(s.lines_hit, 3u);
    EXPECT_EQ(s.functions_found, 2u);
    EXPECT_EQ(s.functions_hit, 1u);
    EXPECT_EQ(s.branches_found, 2u);
    EXPECT_EQ(s.branches_hit, 2u);
}

TEST(Tracefile, BadInputNamesTheFileAndLine) {
    const fs::path count = write("bad_count.info", "SF:/a.s\nDA:3,x\nend_of_record\n");
    EXPECT_EQ(error_of(count), count.string() + ":2: DA count 'x' is not a count 0 .. 18446744073709551615");
    const fs::path fields = write("bad_fields.info", "SF:/a.s\nBRDA:1,2\nend_of_record\n");
    EXPECT_EQ(error_of(fields), fields.string() + ":2: BRDA:1,2: expected 4 comma-separated fields");
    const fs::path outside = write("outside.info", "DA:1,1\n");
    EXPECT_EQ(error_of(outside), outside.string() + ":1: DA: a record outside SF ... end_of_record");
    const fs::path unknown = write("unknown.info", "SF:/a.s\nXY:1\nend_of_record\n");
    EXPECT_EQ(error_of(unknown), unknown.string() + ":2: unknown lcov record 'XY'");
    const fs::path cut = write("cut.info", "SF:/a.s\nDA:1,1\n");
    EXPECT_EQ(error_of(cut), cut.string() + ":2: the file ends inside a record (no end_of_record)");
    const fs::path zero = write("zero.info", "SF:/a.s\nDA:0,1\nend_of_record\n");
    EXPECT_EQ(error_of(zero), zero.string() + ":2: DA line '0' is not a line number 1 .. 4294967295");
    const fs::path binary = write("binary.info", std::string("\x7f" "ELF\x01\x02", 6));
    EXPECT_NE(error_of(binary).find(binary.string() + ":1: "), std::string::npos);
    const fs::path none = write("missing.info", "").parent_path() / "none.info";
    EXPECT_EQ(error_of(none), none.string() + ": cannot read the tracefile");
}
