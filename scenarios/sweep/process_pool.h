// rcsim — runs commands as child processes, at most N at a time (a sweep's runs: SystemC cannot
// elaborate a second design in one process, so every run is its own `rcsim run`).
#pragma once

#include "models/plumbing/progress_line.h"

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace rcsim::sweep {

struct Job {
    std::vector<std::string> argv; // argv[0] is the executable's path
    std::string log;               // stdout and stderr go here
};

struct JobResult {
    bool started = false; // false: the pool was stopped (StopRequest) before this job's turn
    int exit_code = 0; // the child's exit status; 128 + signal when it died of one; 127 spawn failed
    double wall_s = 0;
};

/// Called after each job ends: (job index, its result, jobs done so far).
using JobDone = std::function<void(std::size_t, const JobResult&, std::size_t)>;

/// Polled while jobs run (a few times a second): the signal to stop with, 0 to go on.
using StopRequest = std::function<int()>;

/// Runs every job, `parallel` at a time (>= 1), in index order of start. Returns one result per job.
/// Once `stop` returns a signal, no job starts any more, every running job is sent that signal
/// (once) and the pool returns when they have ended; `done` is called for those only.
std::vector<JobResult> run_jobs(const std::vector<Job>& jobs, unsigned parallel, const JobDone& done,
                                const StopRequest& stop = {});

/// The path of the running executable (/proc/self/exe), for children of the same build.
std::string self_executable();

/// Progress on a terminal: "sweep 12/40  1 failed  ETA 0:31" rewritten in place on stderr
/// (models/plumbing/progress_line.h); in CI (stderr not a terminal, or CI set) nothing but the failures and
/// the final line.
class Progress {
public:
    /// `what` names the command on its lines: "sweep 12/40 ...", "search 12/64 ...".
    Progress(std::size_t total, bool interactive, std::string what = "sweep");
    void update(std::size_t done, std::size_t failed, double elapsed_s);
    /// A line that must stay (a failure), printed above the progress line.
    void note(const std::string& line);
    void finish(std::size_t failed, double elapsed_s);
    /// The last line of a sweep a signal stopped: the runs that completed, those it interrupted,
    /// the rest not run.
    void interrupted(const char* signal_name, std::size_t completed, std::size_t interrupted, std::size_t failed,
                     double elapsed_s);
    static bool interactive_default() { return ProgressLine::interactive_default(); }

private:
    std::size_t total_;
    ProgressLine line_;
    std::string what_;
};

} // namespace rcsim::sweep
