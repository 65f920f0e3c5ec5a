// Small helpers the tests share for files, scratch folders and child commands.
#pragma once

#include <sys/wait.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace rcsim::test {

/// The whole file, bytes as they are (empty when it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// The same as bytes (a ROM image, a program to load).
inline std::vector<std::uint8_t> slurp_bytes(const std::filesystem::path& p) {
    const std::string s = slurp(p);
    return {s.begin(), s.end()};
}

/// A folder of the running test's own, emptied at the test's first call and the same for the rest
/// of it: <build tree>/test_scratch/<Suite>.<Test>. Under the build tree, so that two builds
/// testing at once on one machine (Release and the sanitizer build in CI) never share a file;
/// named by the test, so that no two tests share one (CTest runs each in its own process).
/// Outside a test it is <build tree>/test_scratch/no_test. Defined in scratch.cpp.
std::filesystem::path scratch_dir();

/// Runs `command` through the shell; its exit code, or -1 when it could not run or was killed.
inline int exit_code_of(const std::string& command) {
    const int rc = std::system(command.c_str());
    return rc == -1 || !WIFEXITED(rc) ? -1 : WEXITSTATUS(rc);
}

} // namespace rcsim::test
