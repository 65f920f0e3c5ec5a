// rcsim — an as86 listing (`as86 -l FILE`) read back: which source line each instruction of the
// text segment comes from.
//
// A numbered row is "LLLLL AAAA  BYTES...  SOURCE" (the source text from column 48), a row of a
// macro expansion " +a   AAAA  BYTES...  SOURCE" with the macro's parameters substituted. An
// expansion's instruction is given the line of the macro's body it was written on (found by its
// text, in order); one whose body line cannot be told (a body line written twice) falls back to
// the line of the macro call. Rows of the data and bss segments, directives (`.word`, `.even`)
// and rows without code bytes are not instructions. Offsets are relative to the module's text
// segment; the linker's map gives its base (as86_module_base).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace rcsim::coverage {

struct ListedInstruction {
    std::uint32_t offset = 0; // in the module's text segment
    unsigned line = 0;        // 1-based line of the source file
    /// The first instruction of its line in this expansion (the one a line's count is taken
    /// from); false for the second instruction of a macro call that fell back to the call's line.
    bool leads_line = true;
};

struct As86Listing {
    std::vector<ListedInstruction> instructions; // in listing order
    std::map<std::string, std::uint32_t> labels; // text-segment labels: offset
};

/// Reads the listing; a file that is not an as86 listing is a ConfigError naming it.
As86Listing read_as86_listing(const std::filesystem::path& file);

} // namespace rcsim::coverage
