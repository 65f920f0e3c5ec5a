// rcsim — where the instructions of a ROM come from: the source line of each instruction and the
// functions, the static half of coverage (the counts are coverage_counters.h's).
//
// Two kinds of map:
//   - the built communication firmware (firmware_code_map): as86 listings of its assembly files
//     (isr.s, crt0.s) place every instruction on its source line, the ld86 map places each
//     listing in the ROM; the C files (main.c, hw.c) get their functions from the map and their
//     definition lines from the source (bcc gives no line table: the one line record of a C
//     function is its definition line, counting its first instruction);
//   - any ROM with a symbol table (symbol_code_map: a user's ROM with --symbols): its code
//     symbols as functions and address ranges, a "line" per 16-byte paragraph of a symbol, listed
//     in a text file that the tracefile names as the source.
#pragma once

#include "scenarios/debug/symbols.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace rcsim::coverage {

struct CodeSite {
    std::uint32_t linear = 0; // where the instruction starts
    std::uint32_t end = 0;    // ranges: the end of the address range of this line; else linear + 1
    std::size_t file = 0;     // index into CodeMap::files
    unsigned line = 0;
    bool leads_line = true;   // its count is the line's (see ListedInstruction::leads_line)
};

struct CodeFunction {
    std::size_t file = 0;
    std::string name;
    unsigned line = 0;
    std::uint32_t linear = 0; // the entry: FNDA counts the instructions executed here
};

struct CodeMap {
    std::vector<std::string> files;       // SF paths (absolute)
    std::vector<CodeSite> sites;          // sorted by linear
    std::vector<CodeFunction> functions;
    /// Sites are address ranges (symbol_code_map): a line counts every instruction started in
    /// [linear, end), and branches are those seen executing.
    bool ranges = false;
};

/// One assembly module of the firmware: its source and its as86 listing.
struct AsmModule {
    std::filesystem::path source, listing;
};

/// The built firmware's map. `symbols` is its ld86 map's table; `c_sources` the C files whose
/// functions are looked up by name. A listing none of whose labels is in the map is a ConfigError.
CodeMap firmware_code_map(const std::vector<AsmModule>& asm_modules, const std::vector<std::filesystem::path>& c_sources,
                          const debug::SymbolTable& symbols);

/// A ROM known by its symbols: writes `listing` (one row per line: "ADDRESS  SYMBOL+OFFSET") and
/// returns the map naming it. A table with no code symbol in [base, end) is a ConfigError.
CodeMap symbol_code_map(const debug::SymbolTable& symbols, std::uint32_t base, std::uint32_t end,
                        const std::filesystem::path& listing);

} // namespace rcsim::coverage
