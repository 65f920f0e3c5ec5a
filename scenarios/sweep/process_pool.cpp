#include "scenarios/sweep/process_pool.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <utility>

extern char** environ;

namespace rcsim::sweep {

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

/// Waits for one child to end: its pid, or 0 when `stop` asked to stop first. With a `stop` to
/// watch it polls: a blocking wait would miss a signal that came just before it began, until a
/// job ended on its own.
pid_t wait_child(int& status, const StopRequest& stop) {
    if (!stop) return waitpid(-1, &status, 0);
    for (;;) {
        const pid_t pid = waitpid(-1, &status, WNOHANG);
        if (pid != 0) return pid;
        if (stop() != 0) return 0;
        usleep(50 * 1000);
    }
}

} // namespace

std::vector<JobResult> run_jobs(const std::vector<Job>& jobs, unsigned parallel, const JobDone& done,
                                const StopRequest& stop) {
    std::vector<JobResult> results(jobs.size());
    std::map<pid_t, std::pair<std::size_t, Clock::time_point>> running;
    std::size_t next = 0, finished = 0;
    int stop_sent = 0; // the signal passed on to the running jobs, once
    if (parallel == 0) parallel = 1;
    auto complete = [&](std::size_t i, int code, Clock::time_point t0) {
        results[i].exit_code = code;
        results[i].wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
        done(i, results[i], ++finished);
    };
    while (finished < jobs.size()) {
        const int stop_now = stop_sent == 0 && stop ? stop() : 0;
        if (stop_now != 0) {
            stop_sent = stop_now;
            // On a terminal the jobs had Ctrl-C's SIGINT too (one process group); a SIGTERM sent
            // to the pool alone reaches them only this way. A second copy changes nothing.
            for (const auto& r : running) kill(r.first, stop_sent);
        }
        while (stop_sent == 0 && next < jobs.size() && running.size() < parallel) {
            const auto t0 = Clock::now();
            results[next].started = true;
            const pid_t pid = spawn(jobs[next]);
            if (pid < 0) complete(next, 127, t0);
            else running[pid] = {next, t0};
            ++next;
        }
        if (running.empty()) {
            if (stop_sent != 0) break;
            continue;
        }
        int status = 0;
        const pid_t pid = wait_child(status, stop_sent == 0 ? stop : StopRequest());
        if (pid == 0) continue; // stop requested: pass it on above
        if (pid < 0 && errno == EINTR) continue;
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

Progress::Progress(std::size_t total, bool interactive, std::string what)
    : total_(total), line_(interactive), what_(std::move(what)) {}

void Progress::update(std::size_t done, std::size_t failed, double elapsed_s) {
    const double eta = done ? elapsed_s / static_cast<double>(done) * static_cast<double>(total_ - done) : 0;
    line_.show(what_ + " " + std::to_string(done) + "/" + std::to_string(total_) + "  " + std::to_string(failed) +
               " failed  ETA " + minutes_seconds(eta));
}

void Progress::note(const std::string& line) {
    line_.clear();
    std::fprintf(stderr, "%s\n", line.c_str());
}

void Progress::finish(std::size_t failed, double elapsed_s) {
    line_.clear();
    std::fprintf(stderr, "%s: %zu runs, %zu failed, %.1f s\n", what_.c_str(), total_, failed, elapsed_s);
}

void Progress::interrupted(const char* signal_name, std::size_t completed, std::size_t interrupted, std::size_t failed,
                           double elapsed_s) {
    line_.clear();
    const std::size_t not_run = total_ - completed - interrupted;
    std::fprintf(stderr, "%s: stopped by %s: %zu of %zu runs completed, %zu interrupted, %zu not run, %zu failed, %.1f s\n",
                 what_.c_str(), signal_name, completed, total_, interrupted, not_run, failed, elapsed_s);
}

} // namespace rcsim::sweep
