// rcsim — `rcsim run --coverage`: coverage of the communication CPU's ROM over one run, written
// as DIR/coverage.info (an lcov tracefile) and rendered by genhtml into DIR/coverage/ when genhtml
// is installed (docs/tools.md "Coverage").
//
// The counters sit on the CPU's instruction-boundary hook, in front of any observer already there
// (the profiler, the gdb stub), which is called after them: coverage adds no bus observer and
// changes no timing, so every figure of the run is the same with and without it. Alone on the
// hook they are a counter: the core's idle fast-forward stays on and tells them the boundaries it
// went past (i8086::SkipHook), so the counts are those of executing every instruction at a
// fraction of the cost; in front of the profiler or the gdb stub, which need every boundary, the
// fast-forward is off as for them alone (docs/performance.md).
#pragma once

#include "scenarios/coverage/code_map.h"
#include "scenarios/coverage/counters.h"
#include "scenarios/coverage/tracefile.h"
#include "scenarios/debug/rom_symbols.h"

#include <filesystem>
#include <string>
#include <utility>

namespace rcsim {

class World;

namespace coverage {

class CoverageRun {
public:
    /// Hooks the counters onto `world`'s comm CPU (ROM loaded, before sc_start).
    CoverageRun(World& world, CodeMap map);
    CoverageRun(const CoverageRun&) = delete;
    CoverageRun& operator=(const CoverageRun&) = delete;

    /// After the run: writes dir/coverage.info, runs genhtml into dir/coverage/ when it is on PATH,
    /// and returns report.html's coverage section.
    std::string finish(const std::filesystem::path& dir);

    const Counters& counters() const { return counters_; }

private:
    static bool on_step(void* self, const i8086::Cpu& cpu);
    static void on_skipped(void* self, const i8086::Boundary* b, std::size_t n, std::uint64_t times);

    CodeMap map_;
    Counters counters_;
    std::pair<i8086::StepHook, void*> next_; // the observer that was there before
};

/// The code map of the run's ROM `rom` from its symbols (debug::rom_symbols): the built firmware's
/// (listings, ld86 map, C sources) when they are the built firmware's map; else the symbols as
/// address ranges, described in dir/coverage_rom.txt. A ROM without symbols is a ConfigError.
CodeMap run_code_map(const debug::RomSymbols& symbols, const std::string& rom, const std::filesystem::path& dir);

/// genhtml on PATH renders `info` into `html_dir` (its index.html); false when genhtml is absent
/// or fails (its messages go to html_dir/genhtml.log).
bool run_genhtml(const std::filesystem::path& info, const std::filesystem::path& html_dir);

/// report.html's coverage section: per file lines, functions and branches hit; the interrupt
/// handlers (functions named isr_* or *_isr) with their entry counts; a link to `genhtml_index`
/// (relative to report.html) when not empty.
std::string coverage_section_html(const Tracefile& t, const std::string& genhtml_index);

} // namespace coverage
} // namespace rcsim
