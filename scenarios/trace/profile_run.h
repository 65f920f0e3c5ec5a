// rcsim — `rcsim run --profile`: the cycle profiler (scenarios/trace/profiler.h) on the run's
// communication CPU, and its outputs in the run's directory (docs/tools.md "Profiler"):
//   profile.txt     the table of functions by self clocks, per context;
//   profile.folded  collapsed stacks for flamegraph.pl and speedscope;
//   the flame graph (flame_graph.h), which report.html embeds.
//
// The profiler sees the CPU through its instruction-boundary hook and the bus cycles the
// interrupt probe already observes (InterruptProbe::forward_cycles): it adds no bus observer and
// changes no timing, so the report is the same with and without --profile.
#pragma once

#include "scenarios/debug/symbols.h"
#include "scenarios/trace/profiler.h"

#include <filesystem>
#include <string>

namespace rcsim {

class World;

namespace trace {

class ProfileRun {
public:
    /// Hooks the profiler onto `world`'s comm CPU (before sc_start); functions are named from
    /// `symbols` (the run's, debug::rom_symbols): "name", "name+0x1C" for an entry point inside a symbol (a called local label),
    /// "F1234" (the linear address) where no code symbol is.
    ProfileRun(World& world, debug::SymbolTable symbols);
    ProfileRun(const ProfileRun&) = delete;
    ProfileRun& operator=(const ProfileRun&) = delete;

    /// After the run: writes dir/profile.txt and dir/profile.folded (ConfigError naming a file
    /// that cannot be written) and returns the flame graph's SVG.
    std::string finish(const std::filesystem::path& dir);

    const CycleProfiler& profiler() const { return profiler_; }

private:
    World& world_;
    debug::SymbolTable symbols_;
    CycleProfiler profiler_;

    static bool on_step(void* self, const i8086::Cpu& cpu);
    static void on_bus(void* self, const i8086::BusRecord& r);
};

} // namespace trace
} // namespace rcsim
