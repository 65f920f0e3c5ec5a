// The annotations file of the static bound (scenarios/bound/bound.h, docs/tools.md "Annotations"):
// what each kind of line gives, and bad input named by file and line.
#include "models/plumbing/config_error.h"
#include "scenarios/bound/bound.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;
using namespace rcsim;
using namespace rcsim::bound;

namespace {

debug::Symbol code(const std::string& name, std::uint32_t address) {
    debug::Symbol s;
    s.name = name;
    s.address = address;
    return s;
}

debug::SymbolTable symbols() {
    debug::SymbolTable t;
    t.add(code("rs232_isr", 0xF0200));
    t.add(code("irq_off", 0xF00CC));
    t.fill_sizes(0x100000, 0x10000);
    return t;
}

/// Writes `text` to a file of this test's own and returns its path.
std::string file(const std::string& text) {
    const fs::path dir = fs::path(RCSIM_BOUND_WORK) / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::create_directories(dir);
    std::ofstream(dir / "a.annotations", std::ios::binary) << text;
    return (dir / "a.annotations").string();
}

std::string error_of(const std::string& text) {
    const std::string path = file(text);
    try {
        load_annotations(path, symbols());
    } catch (const ConfigError& e) {
        const std::string what = e.what();
        return what.rfind(path, 0) == 0 ? what.substr(path.size()) : "(does not name the file) " + what;
    }
    return "(no error)";
}

} // namespace

TEST(BoundAnnotations, EachKindOfLine) {
    const auto a = load_annotations(file("# a comment\n\n"
                                         "rs232_isr+0x35D iterations 4  # the TX FIFO holds 4\n"
                                         "0xF0010 targets rs232_isr rs232_isr+16 0xF0300  # a jump table\n"
                                         "irq_off irq_save\n"
                                         "irq_off+2 irq_restore\n"),
                                    symbols());
    ASSERT_EQ(a.size(), 4u);
    EXPECT_EQ(a[0].kind, Annotation::Kind::iterations);
    EXPECT_EQ(a[0].address, 0xF0200u + 0x35D);
    EXPECT_EQ(a[0].iterations, 4u);
    EXPECT_EQ(a[0].reason, "the TX FIFO holds 4");
    EXPECT_EQ(a[1].kind, Annotation::Kind::targets);
    EXPECT_EQ(a[1].address, 0xF0010u);
    EXPECT_EQ(a[1].targets, (std::vector<std::uint32_t>{0xF0200, 0xF0210, 0xF0300}));
    EXPECT_EQ(a[2].kind, Annotation::Kind::irq_save);
    EXPECT_EQ(a[2].address, 0xF00CCu);
    EXPECT_EQ(a[3].kind, Annotation::Kind::irq_restore);
    EXPECT_EQ(a[3].address, 0xF00CEu);
}

TEST(BoundAnnotations, BadLinesAreNamedByFileAndLine) {
    EXPECT_EQ(error_of("\nnosuch iterations 3  # why\n"),
              ":2: no symbol 'nosuch' (a name of the ROM's symbols, or an address 0x...)");
    EXPECT_EQ(error_of("rs232_isr iterations 3\n"), ":1: a loop bound needs its reason after '#'");
    EXPECT_EQ(error_of("rs232_isr iterations 0  # why\n"), ":1: iterations needs a count 1 .. 1048576");
    EXPECT_EQ(error_of("rs232_isr iterations x  # why\n"), ":1: iterations needs a count 1 .. 1048576");
    EXPECT_EQ(error_of("rs232_isr\n"),
              ":1: 'rs232_isr' needs a kind: iterations N, targets A ..., irq_save or irq_restore");
    EXPECT_EQ(error_of("rs232_isr loops 3  # why\n"),
              ":1: unknown kind 'loops' (iterations, targets, irq_save, irq_restore)");
    EXPECT_EQ(error_of("rs232_isr+zz iterations 3  # why\n"), ":1: offset 'zz' is not a number");
    EXPECT_EQ(error_of("0x123456 iterations 3  # why\n"), ":1: address 0x123456 is beyond 1 MB");
    EXPECT_EQ(error_of("rs232_isr targets  # why\n"), ":1: targets needs at least one address or symbol");
    EXPECT_EQ(error_of("irq_off irq_save extra\n"), ":1: unexpected 'extra'");
    EXPECT_EQ(error_of(std::string("rs232_isr iterations 3 \0 # why\n", 32)), ":1: a NUL byte: not a text file");
}

TEST(BoundAnnotations, AFileThatCannotBeReadIsNamed) {
    try {
        load_annotations("/nonexistent/bound.annotations", symbols());
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()), "/nonexistent/bound.annotations: cannot read the annotations file");
    }
}
