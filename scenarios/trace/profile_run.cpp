#include "scenarios/trace/profile_run.h"

#include "models/plumbing/output_file.h"
#include "scenarios/world/world.h"
#include "scenarios/trace/flame_graph.h"

#include <cstdio>

namespace rcsim::trace {

namespace {

/// A frame's function: the code symbol starting at `linear`; an entry point inside a symbol (an
/// assembly routine's local label called as a helper: symbol tables from ld86 maps leave those
/// labels out) is "symbol+0xOFF"; an address no code symbol holds is its linear address "F1234".
std::string function_name(const debug::SymbolTable& symbols, std::uint32_t linear) {
    char buf[24];
    const debug::Symbol* s = symbols.containing(linear);
    if (!s || s->kind != debug::Symbol::Kind::code) {
        std::snprintf(buf, sizeof buf, "%05X", static_cast<unsigned>(linear));
        return buf;
    }
    if (s->address == linear) return s->name;
    std::snprintf(buf, sizeof buf, "+0x%X", static_cast<unsigned>(linear - s->address));
    return s->name + buf;
}

/// Writes `body` into `file` (models/plumbing/output_file.h).
template <class F>
void write_with(const std::filesystem::path& file, F body) {
    OutputFile out(file);
    body(out.stream());
    out.close();
}

} // namespace

ProfileRun::ProfileRun(World& world, debug::SymbolTable symbols)
    : world_(world), symbols_(std::move(symbols)),
      profiler_([this](std::uint32_t linear) { return function_name(symbols_, linear); }) {
    world.ctl.comm.cpu.set_step_observer(&ProfileRun::on_step, this);
    world.probe.forward_cycles(&ProfileRun::on_bus, this);
}

bool ProfileRun::on_step(void* self, const i8086::Cpu& cpu) {
    static_cast<ProfileRun*>(self)->profiler_.step(cpu);
    return false; // never stops the CPU
}

void ProfileRun::on_bus(void* self, const i8086::BusRecord& r) { static_cast<ProfileRun*>(self)->profiler_.bus(r); }

std::string ProfileRun::finish(const std::filesystem::path& dir) {
    profiler_.finish(world_.ctl.comm.cpu.cycles());
    const double hz = world_.scenario().board.comm.cpu_hz;
    write_with(dir / "profile.txt", [&](std::ostream& o) { profiler_.write_table(o, hz); });
    write_with(dir / "profile.folded", [&](std::ostream& o) { profiler_.write_folded(o); });
    return flame_graph_svg(profiler_, hz);
}

} // namespace rcsim::trace
