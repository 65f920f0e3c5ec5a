// rcsim — a streaming writer of the Trace Event Format (the JSON that ui.perfetto.dev and
// chrome://tracing open; docs/tools.md "Perfetto trace").
//
// The file is {"traceEvents":[ ... ]} with one event a line, written as the events come: nothing
// is kept, so a run of any length writes its trace in flat memory. Times are integer picoseconds
// here and microseconds with six decimals in the file (the format's unit is the microsecond; six
// decimals keep every picosecond, so a 125 ns clock edge is exact).
//
// A track is a (pid, tid) pair for slices and instants, a (pid, name) pair for a counter. The
// writer does not sort: each caller hands the events of one track in time order
// (scenarios/trace/perfetto_trace.h says how each source guarantees it).
//
// A failed write (a full disk) is remembered, not thrown: the writer stops writing, the run goes
// on, and close() throws ConfigError naming the file and the reason (exit code 2 at the CLI), so
// a truncated trace never passes as complete.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>

namespace rcsim::trace {

/// "123.456789": picoseconds as microseconds with six decimals.
std::string micros(std::uint64_t ps);
/// A JSON string literal (quotes included).
std::string quoted(const std::string& s);

class TraceEventWriter {
public:
    /// Opens `path` for writing; ConfigError if it cannot be created.
    explicit TraceEventWriter(const std::string& path);

    /// Metadata: the name of a process (a group of tracks) and of a thread track in it; `sort`
    /// orders the groups and tracks in the viewer.
    void process_name(unsigned pid, const std::string& name, int sort);
    void thread_name(unsigned pid, unsigned tid, const std::string& name, int sort);

    /// A slice [ts, ts + dur) (phase X). `args` is a JSON object's members without braces, or "".
    void complete(unsigned pid, unsigned tid, const std::string& name, std::uint64_t ts_ps, std::uint64_t dur_ps,
                  const std::string& args = "");
    /// An instant on a thread track (phase i, scope t).
    void instant(unsigned pid, unsigned tid, const std::string& name, std::uint64_t ts_ps);
    /// A counter sample (phase C): the track `name` of process `pid` holds `value` from ts on.
    void counter(unsigned pid, const std::string& name, std::uint64_t ts_ps, std::int64_t value);

    /// Ends the JSON document and closes the file; ConfigError if any write failed.
    void close();
    std::uint64_t events() const { return events_; }

private:
    std::string path_;
    std::ofstream out_;
    bool first_ = true, closed_ = false, failed_ = false;
    int error_ = 0;
    std::uint64_t events_ = 0;

    void event(const std::string& body);
};

} // namespace rcsim::trace
