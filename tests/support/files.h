// Small helpers the tests share for files and child commands.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace rcsim::test {

/// The whole file, bytes as they are (empty when it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Runs `command` through the shell; its exit code, or -1 when it could not run or was killed.
inline int exit_code_of(const std::string& command) {
    const int rc = std::system(command.c_str());
    return rc == -1 || !WIFEXITED(rc) ? -1 : WEXITSTATUS(rc);
}

} // namespace rcsim::test
