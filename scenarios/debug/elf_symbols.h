// rcsim — a symbol-only ELF file that gdb loads (`symbol-file FILE`) for a ROM without debug info.
//
// ELF32, little-endian, EM_386 (gdb's i8086 architecture is the i386 one with 16-bit code), type
// EXEC, no program headers and no contents: two address-only (SHT_NOBITS) sections, `.text` over
// the ROM (F0000-FFFFF, code symbols as STT_FUNC) and `.data` over everything below it (data
// symbols as STT_OBJECT), and a `.symtab` with every symbol of the table at its linear address —
// the addresses the gdb stub reports (docs/tools.md "gdb").
#pragma once

#include "scenarios/debug/symbols.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rcsim::debug {

/// The file's bytes.
std::vector<std::uint8_t> elf_image(const SymbolTable& table);
/// Writes elf_image() to `path`; throws SymbolError when the file cannot be written.
void write_elf(const SymbolTable& table, const std::string& path);

} // namespace rcsim::debug
