// sc_spawn needs the dynamic-process part of SystemC; the tests call it only through here.
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include "tests/support/sc_test.h"

#include <cstdlib>
#include <filesystem>
#include <memory>

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

/// One spawn_checked body: set when the body returns. A body stopped in a wait(), killed, or left
/// by an exception never sets it.
struct CheckedBody {
    std::string name;
    bool finished = false;
};
std::vector<std::shared_ptr<CheckedBody>> g_checked;

/// Runs the completion check when each test ends. gtest calls OnTestEnd while the test is still
/// the current one, so ADD_FAILURE there fails that test (and its exit status).
class BodyCompletionListener : public testing::EmptyTestEventListener {
    void OnTestEnd(const testing::TestInfo&) override { expect_bodies_finished(); }
};
} // namespace

ScAllowWarnings::ScAllowWarnings() { ++g_allow_depth; }
ScAllowWarnings::~ScAllowWarnings() { --g_allow_depth; }
const std::vector<std::string>& ScAllowWarnings::messages() const { return g_messages; }

sc_core::sc_process_handle spawn_checked(std::function<void()> body, const char* name) {
    auto record = std::make_shared<CheckedBody>();
    g_checked.push_back(record);
    sc_core::sc_process_handle h = sc_core::sc_spawn(
        [record, body = std::move(body)] {
            body();
            record->finished = true;
        },
        name);
    record->name = h.name();
    return h;
}

sc_core::sc_process_handle spawn_forever(std::function<void()> body, const char* name) {
    return sc_core::sc_spawn(std::move(body), name);
}

void expect_bodies_finished() {
    // Checked only once sc_start has returned normally: before that no body ran (the test checks
    // elaboration), and a status still SC_RUNNING outside sc_start means an exception ended the
    // simulation, which reached the test already (as the error it expected, or as a failure).
    const sc_core::sc_status status = sc_core::sc_get_status();
    const bool ran = status == sc_core::SC_PAUSED || status == sc_core::SC_STOPPED;
    for (const auto& body : g_checked)
        if (ran && !body->finished)
            ADD_FAILURE() << "SystemC thread '" << body->name << "' did not run to completion (at "
                          << sc_core::sc_time_stamp() << " it was still in a wait(), or had been killed); "
                          << "the checks after that point did not run";
    g_checked.clear();
}

std::string sst_dir() {
    if (const char* env = std::getenv("RCSIM_SST_DIR"); env && *env)
        return std::filesystem::is_directory(env) ? env : "";
    const std::string d = RCSIM_DEFAULT_SST_DIR;
    return std::filesystem::is_directory(d) ? d : "";
}

} // namespace rcsim::test

int sc_main(int argc, char* argv[]) {
    testing::InitGoogleTest(&argc, argv);
    // Appended after the default printer: gtest calls OnTestEnd in reverse order, so the check's
    // failures are recorded before the printer reports the test's verdict.
    testing::UnitTest::GetInstance()->listeners().Append(new rcsim::test::BodyCompletionListener);
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
