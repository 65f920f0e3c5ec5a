// rcsim — a file a run writes: written completely or reported. Every failure to create it or to
// write any of it is a ConfigError naming the file, what it is and the system's reason (exit 2 at
// the command line), never a silently missing or truncated file. The one file writer of the tree:
// reports, logs, traces, summaries.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace rcsim {

class OutputFile {
public:
    /// Creates (truncates) `path`; throws ConfigError "PATH: cannot write WHAT: reason" when it
    /// cannot. `what` names the file for the message ("the report", "the host log").
    explicit OutputFile(std::filesystem::path path, std::string what = "the file");

    std::ostream& stream() { return out_; }
    const std::filesystem::path& path() const { return path_; }
    /// Throws as above when an earlier write failed (a full disk), without closing.
    void check();
    /// Flushes and closes; throws as above when anything written was lost. Call once, at the end:
    /// a file whose close() is not called is still closed, but its errors go unreported.
    void close();

private:
    std::filesystem::path path_;
    std::string what_;
    std::ofstream out_;

    [[noreturn]] void fail(int err) const;
};

/// Writes `text` into `path` whole (binary, no newline translation); errors as OutputFile.
void write_file(const std::filesystem::path& path, std::string_view text, std::string what = "the file");

} // namespace rcsim
