// scratch_dir() (files.h): the build tree's folder comes from CMake (RCSIM_TEST_SCRATCH_ROOT), in
// this one file, so that the tests' own objects do not depend on where the build tree is.
#include "tests/support/files.h"

#include <gtest/gtest.h>

#ifndef RCSIM_TEST_SCRATCH_ROOT
#error "RCSIM_TEST_SCRATCH_ROOT: tests/CMakeLists.txt sets it to a folder of the build tree"
#endif

namespace rcsim::test {

std::filesystem::path scratch_dir() {
    const testing::TestInfo* info = testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "no_test";
    for (char& c : name)
        if (c == '/') c = '_'; // a parameterised test is Prefix/Suite.Test/N: one folder, not three
    const std::filesystem::path dir = std::filesystem::path(RCSIM_TEST_SCRATCH_ROOT) / name;
    // Emptied once per test: what an earlier run left must not pass for this run's output, and a
    // second call within the test must not delete what the first one's caller wrote.
    static std::string emptied_for;
    if (emptied_for != name) {
        std::filesystem::remove_all(dir);
        emptied_for = name;
    }
    std::filesystem::create_directories(dir);
    return dir;
}

} // namespace rcsim::test
