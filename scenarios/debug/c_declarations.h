// rcsim — the types of a C program's file-scope variables, read from its sources, so that gdb can
// `print` and `watch` them by name (symbols.elf's DWARF, dwarf_types.h; issue #51 item 4).
//
// The firmware's C (comm_cpu/firmware, bcc's 16-bit ints) declares its globals in the plain forms
// read here: `[static|extern] [const|volatile] [unsigned|signed] char|short|int|long NAME`, each
// declarator with an optional `*` and array bounds `[N]` (a number or an object-like #define of
// one), several declarators a line, initialisers skipped. Function bodies, prototypes, typedefs,
// struct/union/enum and what is not understood are skipped: their variables get a type from
// their size in the map instead (dwarf_types.h), never a wrong one.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace rcsim::debug {

struct CType {
    std::string base;                  // "unsigned int", "char", ... (as DWARF names a base type)
    unsigned base_size = 2;            // bytes, bcc's: char 1, short and int 2, long 4
    bool is_signed = false;
    bool pointer = false;              // a near pointer: 2 bytes, a DS offset
    std::vector<std::uint32_t> dims;   // array bounds, outermost first
    std::uint32_t size() const;        // bytes of the whole object
};

/// The variables declared at file scope in `files` (read in order; a later declaration of a name
/// replaces an earlier one, as a definition in main.c repeats its extern in fw.h). A file that
/// cannot be read is skipped: the types are an aid, a run without them still debugs.
std::map<std::string, CType> read_c_declarations(const std::vector<std::string>& files);

/// The same from one text (for the tests); `defines` gives and gets the #define constants.
void parse_c_declarations(const std::string& text, std::map<std::string, std::int64_t>& defines,
                          std::map<std::string, CType>& out);

} // namespace rcsim::debug
