// rcsim — lcov tracefiles (the `.info` format of lcov's geninfo(1), read by lcov and genhtml):
// the model, a reader, lcov's merge and a writer.
//
// The records rcsim writes and reads: TN (test name), SF (source file), FN/FNDA (a function's
// first line and entry count), BRDA (LINE,BLOCK,BRANCH,TAKEN with "-" for a branch whose line
// never ran), DA (LINE,COUNT), and end_of_record; the summary records FNF/FNH/BRF/BRH/LF/LH are
// written from the counts and skipped on reading (they are derived). VER and LN-style records of
// newer lcov versions are skipped too. Anything else is an error naming the file and line.
//
// Merging follows `lcov -a`: counts of the same line, function or branch add up; a branch "-"
// (not evaluated) plus a count is the count. Output is sorted by file, line and name, so the
// bytes depend only on the counts.
#pragma once

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace rcsim::coverage {

struct FileCoverage {
    struct Function {
        unsigned line = 0;
        std::uint64_t count = 0;
    };
    using BranchKey = std::tuple<unsigned, unsigned, unsigned>; // line, block, branch
    std::map<unsigned, std::uint64_t> lines;                      // DA
    std::map<std::string, Function> functions;                    // FN, FNDA
    std::map<BranchKey, std::optional<std::uint64_t>> branches;   // BRDA; nullopt = "-"
};

struct Tracefile {
    std::map<std::string, FileCoverage> files; // by SF path
};

/// Reads `file`; a malformed record is a ConfigError "FILE:LINE: reason".
Tracefile read_tracefile(const std::filesystem::path& file);
/// Adds `more` into `into` (lcov -a).
void merge_into(Tracefile& into, const Tracefile& more);
/// The tracefiles named merged into one (lcov -a FILE -a FILE ...).
Tracefile merge_tracefiles(const std::vector<std::filesystem::path>& files);
/// Writes the tracefile (TN empty, as lcov does for an unnamed test).
void write_tracefile(std::ostream& os, const Tracefile& t);
/// Writes `t` to `file` (ConfigError naming it when it cannot).
void write_tracefile_to(const std::filesystem::path& file, const Tracefile& t);

/// Totals over all files: found and hit, for lines, functions and branches (lcov --summary).
struct Summary {
    std::uint64_t lines_found = 0, lines_hit = 0;
    std::uint64_t functions_found = 0, functions_hit = 0;
    std::uint64_t branches_found = 0, branches_hit = 0;
};
Summary summarize(const Tracefile& t);
Summary summarize(const FileCoverage& f);

} // namespace rcsim::coverage
