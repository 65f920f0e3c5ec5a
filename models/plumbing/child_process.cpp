// rcsim — a function run in a child process (child_process.h).
#include "models/plumbing/child_process.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <exception>
#include <stdexcept>

namespace rcsim {

std::optional<std::string> run_in_child_process(const std::function<std::string()>& body, const std::string& who) {
    int fd[2];
    if (pipe(fd) != 0) throw std::runtime_error(who + ": pipe() failed");
    const pid_t pid = fork();
    if (pid < 0) {
        close(fd[0]);
        close(fd[1]);
        throw std::runtime_error(who + ": fork() failed");
    }
    if (pid == 0) {
        close(fd[0]);
        bool sent = false;
        try {
            const std::string out = body();
            sent = write(fd[1], out.data(), out.size()) == ssize_t(out.size());
        } catch (const std::exception& e) {
            std::fprintf(stderr, "%s: %s\n", who.c_str(), e.what());
        } catch (...) {
            std::fprintf(stderr, "%s: the child run failed\n", who.c_str());
        }
        std::fflush(stderr);
        _exit(sent ? 0 : 1);
    }
    close(fd[1]);
    std::string bytes;
    char buf[4096];
    for (ssize_t n; (n = read(fd[0], buf, sizeof buf)) > 0;) bytes.append(buf, std::size_t(n));
    close(fd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return std::nullopt;
    return bytes;
}

} // namespace rcsim
