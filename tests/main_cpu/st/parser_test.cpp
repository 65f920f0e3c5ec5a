// The parser and the compiler's checks on a corpus (tests/main_cpu/st/corpus): every valid program
// compiles; every invalid one fails with exactly the message in its .expect file, which names
// file:line:column and what was expected or is wrong. The plotter program of the shipped scenario
// is in the valid set too.
#include "tests/support/files.h"
#include "tests/main_cpu/st/st_test.h"

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace rcsim::st;
using namespace rcsim::st::test;
namespace fs = std::filesystem;

namespace {

using rcsim::test::slurp;

std::vector<fs::path> files(const fs::path& dir) {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ".st") out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

const fs::path corpus = fs::path(RCSIM_SOURCE_DIR) / "tests/main_cpu/st/corpus";

TEST(StParser, EveryValidProgramCompiles) {
    auto valid = files(corpus / "valid");
    valid.push_back(fs::path(RCSIM_SOURCE_DIR) / "scenarios/st/xy_plotter.st");
    ASSERT_GE(valid.size(), 4u);
    for (const fs::path& f : valid) EXPECT_EQ(compile_error(slurp(f), f.filename().string()), "") << f;
}

TEST(StParser, EveryInvalidProgramFailsWithItsMessage) {
    const auto invalid = files(corpus / "invalid");
    ASSERT_GE(invalid.size(), 40u);
    for (const fs::path& f : invalid) {
        fs::path expect = f;
        expect.replace_extension(".expect");
        std::string want = slurp(expect);
        while (!want.empty() && want.back() == '\n') want.pop_back();
        EXPECT_EQ(compile_error(slurp(f), f.filename().string()), f.filename().string() + ":" + want);
    }
}

TEST(StParser, ARunOfTheEverythingProgramDoesNotFail) {
    // The corpus program calls every block once; with no axes the MC blocks answer invalid_axis.
    StProgram p_(slurp(corpus / "valid/everything.st"), "everything.st", std::vector<rcsim::motion::McAxis*>(4),
                 std::vector<rcsim::motion::MC_Power*>{});
    ASSERT_EQ(p_.start("Everything"), "");
    StProgram* p = &p_;
    for (int k = 0; k < 3; ++k) p->run_once(k * 1000);
    EXPECT_TRUE(p->running()) << p->error();
    EXPECT_EQ(p->value("power.Error").i, 1);
    EXPECT_EQ(p->value("power.ErrorID").i, 4101); // err::invalid_axis (AXL code)
    EXPECT_EQ(p->value("out").i, 6);              // Counter: 2 per cycle
}

TEST(StParser, ErrorsInTheStandardLibraryCannotHappenButUserErrorsNameTheUserFile) {
    EXPECT_EQ(compile_error("PROGRAM P VAR x : INT; END_VAR x := ; END_PROGRAM", "mine.st"),
              "mine.st:1:37: expected an expression, found ';'");
}

} // namespace
