// The process pool behind `rcsim sweep --jobs`: parallelism, exit codes, logs.
#include "scenarios/sweep/process_pool.h"
#include "tests/support/files.h"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace rcsim::sweep;

namespace {

Job shell(const std::string& script, const fs::path& log) { return {{"/bin/sh", "-c", script}, log.string()}; }

double seconds_for(const std::vector<Job>& jobs, unsigned parallel) {
    const auto t0 = std::chrono::steady_clock::now();
    run_jobs(jobs, parallel, [](std::size_t, const JobResult&, std::size_t) {});
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

TEST(ProcessPool, RunsNAtATime) {
    // Four jobs that each sleep 0.4 s (no CPU, so a loaded host does not matter): one at a time
    // they take 1.6 s, two at a time 0.8 s, four at a time 0.4 s.
    const fs::path d = rcsim::test::scratch_dir();
    std::vector<Job> jobs;
    for (int i = 0; i < 4; ++i) jobs.push_back(shell("sleep 0.4", d / ("j" + std::to_string(i))));
    const double one = seconds_for(jobs, 1), two = seconds_for(jobs, 2), four = seconds_for(jobs, 4);
    EXPECT_GE(one, 1.6);
    EXPECT_GE(two, 0.8);
    EXPECT_LT(two, 1.2) << "two at a time took as long as one at a time would";
    EXPECT_GE(four, 0.4);
    EXPECT_LT(four, 0.8);
}

TEST(ProcessPool, ExitCodesSignalsAndLogs) {
    const fs::path d = rcsim::test::scratch_dir();
    const std::vector<Job> jobs{shell("echo out; echo err >&2; exit 0", d / "a.log"), shell("exit 3", d / "b.log"),
                                shell("kill -9 $$", d / "c.log"), {{(d / "no-such-program").string()}, (d / "d.log").string()}};
    std::vector<std::size_t> order;
    const auto r = run_jobs(jobs, 2, [&](std::size_t i, const JobResult&, std::size_t done) {
        order.push_back(i);
        EXPECT_EQ(done, order.size());
    });
    ASSERT_EQ(r.size(), 4u);
    EXPECT_EQ(r[0].exit_code, 0);
    EXPECT_EQ(r[1].exit_code, 3);
    EXPECT_EQ(r[2].exit_code, 128 + 9);
    EXPECT_EQ(r[3].exit_code, 127);
    EXPECT_EQ(order.size(), 4u);
    EXPECT_EQ(rcsim::test::slurp(d / "a.log"), "out\nerr\n"); // stdout and stderr both in the log
}

// A stop request (a sweep's SIGINT): no job starts any more, the running one gets the signal once.
TEST(ProcessPool, StopStartsNoMoreJobsAndPassesTheSignalOn) {
    const fs::path d = rcsim::test::scratch_dir();
    // The job reports the signal it got and exits 130 as `rcsim run` does; unsignalled it sleeps.
    // `started` is made once the sleep runs, so the trap always has its $! to kill: a signal
    // that came between the file and the sleep would leave kill without a pid (a usage error
    // in the log) on a loaded host.
    const std::string job = "trap 'echo got INT; kill $!; exit 130' INT; sleep 30 & touch " +
                            (d / "started").string() + "; wait";
    const std::vector<Job> jobs{shell(job, d / "a.log"), shell(job, d / "b.log")};
    std::size_t ended = 0;
    const auto r = run_jobs(
        jobs, 1, [&](std::size_t, const JobResult&, std::size_t) { ++ended; },
        [&] { return fs::exists(d / "started") ? SIGINT : 0; });
    ASSERT_EQ(r.size(), 2u);
    EXPECT_TRUE(r[0].started);
    EXPECT_EQ(r[0].exit_code, 130);
    EXPECT_FALSE(r[1].started);
    EXPECT_EQ(ended, 1u);
    EXPECT_EQ(rcsim::test::slurp(d / "a.log"), "got INT\n");
}
