// models/plumbing/output_file.h: a file is written whole or the error names it, with the system's reason.
#include "models/plumbing/config_error.h"
#include "models/plumbing/output_file.h"
#include "tests/support/files.h"

#include <gtest/gtest.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <functional>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;
using rcsim::ConfigError;

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "no error";
}

TEST(OutputFile, WritesTheTextWholeAndUntranslated) {
    const fs::path p = rcsim::test::scratch_dir() / "output_file_test.txt";
    const std::string text = std::string("a\r\nb\0c\n", 7);
    rcsim::write_file(p, text);
    EXPECT_EQ(rcsim::test::slurp(p), text);
    rcsim::OutputFile f(p); // truncates
    f.stream() << "x";
    f.close();
    EXPECT_EQ(rcsim::test::slurp(p), "x");
    fs::remove(p);
}

TEST(OutputFile, AFileThatCannotBeCreatedIsNamedWithTheReason) {
    const fs::path p = rcsim::test::scratch_dir() / "no_such_dir" / "report.json";
    EXPECT_EQ(error_of([&] { rcsim::write_file(p, "{}", "the report"); }),
              p.string() + ": cannot write the report: " + std::strerror(ENOENT));
}

// /dev/full accepts the open and refuses every write with ENOSPC: a full disk.
TEST(OutputFile, AWriteThatFailsIsReportedAtCloseNotLost) {
    if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
    EXPECT_EQ(error_of([] { rcsim::write_file("/dev/full", std::string(1 << 16, 'x'), "the log"); }),
              std::string("/dev/full: cannot write the log: ") + std::strerror(ENOSPC));
    rcsim::OutputFile f("/dev/full");
    f.stream() << std::string(1 << 16, 'x');
    EXPECT_THROW(f.check(), ConfigError);
}

} // namespace
