// The rcsim executable's peak memory does not grow with the length of a run: 60 s of the
// three-port worst case against 10 s of it, peak resident set size from the kernel (wait4).
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>

#include <fcntl.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace fs = std::filesystem;

namespace {

struct Finished {
    int exit_code = -1;
    long peak_kb = 0; // ru_maxrss: kilobytes on Linux
};

/// Runs `rcsim run FILE --out DIR --reproducible`, its output to DIR.txt.
Finished run_rcsim(const std::string& scenario, const fs::path& out) {
    fs::remove_all(out);
    const std::string log = out.string() + ".txt";
    const pid_t pid = fork();
    if (pid == 0) {
        const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
        }
        execl(RCSIM_EXE, RCSIM_EXE, "run", scenario.c_str(), "--out", out.c_str(), "--reproducible",
              static_cast<char*>(nullptr));
        _exit(127);
    }
    Finished r;
    int status = 0;
    rusage ru{};
    if (pid > 0 && wait4(pid, &status, 0, &ru) == pid && WIFEXITED(status)) {
        r.exit_code = WEXITSTATUS(status);
        r.peak_kb = ru.ru_maxrss;
    }
    return r;
}

} // namespace

TEST(Memory, PeakRssOfSixtySecondsIsThatOfTenSeconds) {
#ifdef RCSIM_SANITIZE_BUILD
    // AddressSanitizer keeps freed memory in quarantine and shadow: peak RSS measures it, not us.
    GTEST_SKIP() << "peak RSS is not meaningful in a sanitizer build";
#endif
    const fs::path work = RCSIM_MEMORY_WORK;
    fs::create_directories(work);
    const Finished a = run_rcsim(RCSIM_MEMORY_DATA "/three_ports_9600_10s.yaml", work / "10s");
    const Finished b = run_rcsim(RCSIM_MEMORY_DATA "/three_ports_9600_60s.yaml", work / "60s");
    // Both runs hold every check (exit 0) and wrote their reports.
    ASSERT_EQ(a.exit_code, 0) << "see " << (work / "10s.txt");
    ASSERT_EQ(b.exit_code, 0) << "see " << (work / "60s.txt");
    for (const char* f : {"report.json", "interrupts.csv", "report.html"}) EXPECT_TRUE(fs::exists(work / "60s" / f)) << f;
    // The scenario completes about 2 000 interrupts and reads about 1 000 characters per simulated
    // second (its report.json), so anything kept per event grows by megabytes in the 50 s between
    // the runs: a 100-byte record per interrupt is 10 MB. Bounded sample sets fill up to
    // a fixed size and then stop (models/stats.h). 5 MB tells the two apart.
    const long growth_kb = b.peak_kb - a.peak_kb;
    RecordProperty("peak_kb_10s", static_cast<int>(a.peak_kb));
    RecordProperty("peak_kb_60s", static_cast<int>(b.peak_kb));
    EXPECT_LT(growth_kb, 5 * 1024) << "peak RSS " << a.peak_kb << " kB after 10 s, " << b.peak_kb << " kB after 60 s";
}
