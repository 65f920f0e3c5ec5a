#include "tests/support/sc_test.h"

#include <cstdlib>
#include <filesystem>

#ifndef RCSIM_DEFAULT_SST_DIR
#define RCSIM_DEFAULT_SST_DIR ""
#endif

namespace rcsim::test {
namespace {
int g_allow_depth = 0;
std::vector<std::string> g_messages;

void report_handler(const sc_core::sc_report& report, const sc_core::sc_actions& actions) {
    if (report.get_severity() == sc_core::SC_WARNING) {
        if (g_allow_depth > 0)
            g_messages.emplace_back(report.get_msg());
        else
            ADD_FAILURE() << "SystemC warning: " << report.get_msg_type() << ": " << report.get_msg();
        return;
    }
    sc_core::sc_report_handler::default_handler(report, actions);
}
} // namespace

ScAllowWarnings::ScAllowWarnings() { ++g_allow_depth; }
ScAllowWarnings::~ScAllowWarnings() { --g_allow_depth; }
const std::vector<std::string>& ScAllowWarnings::messages() const { return g_messages; }

std::string sst_dir() {
    if (const char* env = std::getenv("RCSIM_SST_DIR"); env && *env)
        return std::filesystem::is_directory(env) ? env : "";
    const std::string d = RCSIM_DEFAULT_SST_DIR;
    return std::filesystem::is_directory(d) ? d : "";
}

} // namespace rcsim::test

int sc_main(int argc, char* argv[]) {
    testing::InitGoogleTest(&argc, argv);
    sc_core::sc_report_handler::set_handler(rcsim::test::report_handler);
    // An error must reach the test as an exception, never abort the process.
    sc_core::sc_report_handler::set_actions(sc_core::SC_ERROR, sc_core::SC_THROW);
    return RUN_ALL_TESTS();
}

#ifdef RCSIM_SANITIZE_BUILD
// LeakSanitizer cannot walk SystemC's coroutine stacks and aborts at exit (CMakeLists.txt).
extern "C" const char* __asan_default_options() { return "detect_leaks=0"; }
#endif

int main(int argc, char* argv[]) {
    setenv("SC_COPYRIGHT_MESSAGE", "DISABLE", 0);
    return sc_core::sc_elab_and_sim(argc, argv);
}
