// rcsim — the DWARF of symbols.elf: the data symbols as typed variables, so that gdb's `print`
// and `watch` take them by name (issue #51 item 4; docs/tools.md "gdb").
//
// DWARF 4 ("DWARF Debugging Information Format", version 4: 7.5 the unit header and abbreviations,
// 7.5.4 the forms, 7.8 base type encodings), 32-bit format, 4-byte addresses (the ELF file's):
// one compile unit of base types, array types and a DW_TAG_variable per data symbol at its linear
// address (DW_OP_addr). A variable's type is its C declaration's (c_declarations.h) when one is
// given and fits the symbol's size in the map; otherwise the size says it: 1 byte unsigned char,
// 2 bytes unsigned int (bcc's 16-bit int), N bytes unsigned char[N]. A near pointer is the base
// type `near_ptr`, 16-bit unsigned (a DS offset): gdb would take a DW_TAG_pointer_type at its own
// architecture's pointer size, 4 or 8 bytes. Code symbols stay ELF symbols only (gdb's minimal
// symbols: break, bt and x/i need no more).
#pragma once

#include "scenarios/debug/c_declarations.h"
#include "scenarios/debug/symbols.h"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace rcsim::debug {

struct DwarfSections {
    std::vector<std::uint8_t> abbrev; // .debug_abbrev
    std::vector<std::uint8_t> info;   // .debug_info
};

/// The type a data symbol gets (the declaration's or one from its size); empty base for a label
/// of size 0, which gets no variable.
CType variable_type(const Symbol& symbol, const std::map<std::string, CType>& declarations);

DwarfSections dwarf_variables(const SymbolTable& table, const std::map<std::string, CType>& declarations);

} // namespace rcsim::debug
