// rcsim — a symbol-only ELF file that gdb loads (`symbol-file FILE`) for a ROM without debug info.
//
// ELF32, little-endian, EM_NONE, type EXEC, no program headers and no contents: two address-only (SHT_NOBITS) sections, `.text` over
// the ROM (F0000-FFFFF, code symbols as STT_FUNC) and `.data` over everything below it (data
// symbols as STT_OBJECT), a `.symtab` with every symbol of the table at its linear address —
// the addresses the gdb stub reports (docs/tools.md "gdb") — and `.debug_abbrev`/`.debug_info`
// with the data symbols as typed variables (dwarf_types.h), for `print` and `watch` by name.
//
// EM_NONE, not EM_386: gdb picks, of the file's architecture and the target description's
// (i8086, gdb_protocol.cpp), the "more capable" when both are of the i386 family, so an EM_386 file
// made it disassemble the 8086's code as 32-bit i386 unless told `set architecture i8086`. A file
// of no machine leaves the choice to the target description.
#pragma once

#include "scenarios/debug/c_declarations.h"
#include "scenarios/debug/symbols.h"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace rcsim::debug {

/// The file's bytes; `declarations` type the data symbols (dwarf_types.h), the others are typed
/// by their size.
std::vector<std::uint8_t> elf_image(const SymbolTable& table, const std::map<std::string, CType>& declarations = {});
/// Writes elf_image() to `path`; throws SymbolError when the file cannot be written.
void write_elf(const SymbolTable& table, const std::string& path, const std::map<std::string, CType>& declarations = {});

} // namespace rcsim::debug
