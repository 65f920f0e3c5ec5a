// rcsim — the symbols of the ROM a run executes, decided in one place for everything that names
// its addresses: the latency causes (run/cause_symbols.h), the profiler (trace/profile_run.h),
// coverage (coverage/coverage_run.h), gdb (cli/gdb_run.h) and report.json "symbols"
// (docs/tools.md "Symbols").
//
// The user's `--symbols FILE[@SEG]` wins whatever the ROM; without it the built firmware's ld86
// map names the built firmware's ROM (build/comm_fw.rom, RCSIM_COMM_FW_ROM), and any other ROM
// has none: its addresses stay addresses.
#pragma once

#include "models/rom_image.h"
#include "scenarios/debug/c_declarations.h"
#include "scenarios/debug/symbols.h"

#include <string>

namespace rcsim::debug {

struct RomSymbols {
    enum class Origin { none, user, built_firmware };
    Origin origin = Origin::none;
    std::string file; // what was read: the --symbols argument, or the built firmware's map
    SymbolTable table;
    /// The types of the C variables, for gdb (dwarf_types.h): the built firmware's, from its
    /// sources (fw.h, main.c, hw.c); none for a user's map.
    std::map<std::string, CType> declarations;
    /// The ROM is the built firmware and these are its map's symbols: coverage can add the
    /// firmware's listings and C sources to them.
    bool built_firmware() const { return origin == Origin::built_firmware; }
};

/// Whether `rom` is the firmware this build made: no file at all (a run's default), the built
/// ROM's file, or any ROM whose 64 KB the CPU sees are the built ROM's bytes (a copy, an Intel HEX
/// of it, its even/odd EPROM pair). Throws ConfigError when `rom` cannot be read.
bool is_built_firmware(const RomSource& rom);

/// The ROM's symbols: `symbols` (FILE or FILE@SEG, SymbolTable::load) when not empty; else the
/// built firmware's ld86 map when is_built_firmware(rom); else none. A symbol file that cannot
/// be read or parsed is a ConfigError naming it ("--symbols: FILE:LINE: reason").
RomSymbols rom_symbols(const RomSource& rom, const std::string& symbols);

/// report.json "symbols": {"origin": "--symbols" | "built firmware" | "none", "file": its file
/// name (no folder, so that reports compare across machines), "count": how many symbols}.
struct RomSymbolsSummary {
    std::string origin, file;
    std::size_t count = 0;
};
RomSymbolsSummary summary(const RomSymbols& symbols);

} // namespace rcsim::debug
