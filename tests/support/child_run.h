// A run in a child process. SystemC elaborates once per process, and two boards in one kernel
// would bound each other's CPU slices, so a test that compares two runs of a board (a switch on
// and off) makes each in a child of its own and gets what the run counted back through a pipe.
#pragma once

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace rcsim::test {

/// What a child run sends back: fixed counters, then a byte log.
struct ChildResult {
    std::vector<std::uint64_t> counts;
    std::vector<std::uint8_t> log;
};

/// Runs `body` in a child process and returns what it returned. The child's own failure (an
/// exception, a short write, a crash) fails the calling test and gives an empty result.
inline ChildResult run_in_child(const std::function<ChildResult()>& body) {
    int fd[2];
    if (pipe(fd) != 0) throw std::runtime_error("pipe() failed");
    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error("fork() failed");
    if (pid == 0) {
        close(fd[0]);
        bool ok = false;
        try {
            const ChildResult r = body();
            const std::uint64_t head[2] = {r.counts.size(), r.log.size()};
            const auto put = [&](const void* p, std::size_t n) { return write(fd[1], p, n) == ssize_t(n); };
            ok = put(head, sizeof head) && put(r.counts.data(), r.counts.size() * sizeof(std::uint64_t)) &&
                 put(r.log.data(), r.log.size());
        } catch (...) {
        }
        _exit(ok ? 0 : 1);
    }
    close(fd[1]);
    std::string bytes;
    char buf[4096];
    for (ssize_t n; (n = read(fd[0], buf, sizeof buf)) > 0;) bytes.append(buf, std::size_t(n));
    close(fd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    const bool child_ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    EXPECT_TRUE(child_ok) << "the child run failed";
    ChildResult r;
    std::uint64_t head[2] = {};
    if (!child_ok || bytes.size() < sizeof head) return r;
    std::memcpy(head, bytes.data(), sizeof head);
    const std::size_t counts_bytes = head[0] * sizeof(std::uint64_t);
    if (bytes.size() != sizeof head + counts_bytes + head[1]) {
        ADD_FAILURE() << "the child run sent " << bytes.size() << " bytes, not the ones it announced";
        return r;
    }
    r.counts.resize(head[0]);
    std::memcpy(r.counts.data(), bytes.data() + sizeof head, counts_bytes);
    r.log.assign(bytes.begin() + std::ptrdiff_t(sizeof head + counts_bytes), bytes.end());
    return r;
}

} // namespace rcsim::test
