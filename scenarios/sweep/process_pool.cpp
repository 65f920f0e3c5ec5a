#include "scenarios/sweep/process_pool.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>

extern char** environ;

namespace rcsim::regress {

namespace {

using Clock = std::chrono::steady_clock;

/// Starts one job; -1 when it could not be spawned.
pid_t spawn(const Job& job) {
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, job.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, STDOUT_FILENO, STDERR_FILENO);
    posix_spawn_file_actions_addopen(&fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    std::vector<char*> argv;
    for (const auto& a : job.argv) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    return rc == 0 ? pid : -1;
}

int exit_code_of(int status) {
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
    return 127;
}

} // namespace

std::vector<JobResult> run_jobs(const std::vector<Job>& jobs, unsigned parallel, const JobDone& done) {
    std::vector<JobResult> results(jobs.size());
    std::map<pid_t, std::pair<std::size_t, Clock::time_point>> running;
    std::size_t next = 0, finished = 0;
    if (parallel == 0) parallel = 1;
    auto complete = [&](std::size_t i, int code, Clock::time_point t0) {
        results[i].exit_code = code;
        results[i].wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
        done(i, results[i], ++finished);
    };
    while (finished < jobs.size()) {
        while (next < jobs.size() && running.size() < parallel) {
            const auto t0 = Clock::now();
            const pid_t pid = spawn(jobs[next]);
            if (pid < 0) complete(next, 127, t0);
            else running[pid] = {next, t0};
            ++next;
        }
        if (running.empty()) continue;
        int status = 0;
        const pid_t pid = waitpid(-1, &status, 0);
        if (pid < 0) break; // no child left: cannot happen while `running` holds one
        const auto it = running.find(pid);
        if (it == running.end()) continue; // not one of ours
        complete(it->second.first, exit_code_of(status), it->second.second);
        running.erase(it);
    }
    return results;
}

std::string self_executable() {
    std::error_code ec;
    const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
    return ec ? std::string("rcsim") : p.string();
}

Progress::Progress(std::size_t total, bool interactive) : total_(total), interactive_(interactive) {}

bool Progress::interactive_default() {
    const char* ci = std::getenv("CI");
    return isatty(STDERR_FILENO) && !(ci && *ci);
}

void Progress::update(std::size_t done, std::size_t failed, double elapsed_s) {
    if (!interactive_) return;
    const double eta = done ? elapsed_s / static_cast<double>(done) * static_cast<double>(total_ - done) : 0;
    const long s = static_cast<long>(eta + 0.5);
    std::fprintf(stderr, "\r\033[Ksweep %zu/%zu  %zu failed  ETA %ld:%02ld", done, total_, failed, s / 60, s % 60);
    std::fflush(stderr);
}

void Progress::note(const std::string& line) {
    if (interactive_) std::fprintf(stderr, "\r\033[K");
    std::fprintf(stderr, "%s\n", line.c_str());
}

void Progress::finish(std::size_t failed, double elapsed_s) {
    if (interactive_) std::fprintf(stderr, "\r\033[K");
    std::fprintf(stderr, "sweep: %zu runs, %zu failed, %.1f s\n", total_, failed, elapsed_s);
}

} // namespace rcsim::regress
