#include "scenarios/coverage/code_map.h"

#include "models/plumbing/config_error.h"
#include "models/plumbing/output_file.h"
#include "scenarios/coverage/as86_listing.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <map>

namespace rcsim::coverage {

namespace {

/// The line of a C function's definition: a line that starts at column 0, names the function
/// followed by "(", and is not a declaration (no ";"). 0 when none.
unsigned definition_line(const std::filesystem::path& source, const std::string& name) {
    std::ifstream in(source);
    std::string text;
    unsigned n = 0;
    while (std::getline(in, text)) {
        ++n;
        if (text.empty() || std::isspace(static_cast<unsigned char>(text[0])) || text[0] == '#' || text[0] == '/' ||
            text.find(';') != std::string::npos)
            continue;
        for (std::size_t at = text.find(name); at != std::string::npos; at = text.find(name, at + 1)) {
            const bool starts = at == 0 || !(std::isalnum(static_cast<unsigned char>(text[at - 1])) || text[at - 1] == '_');
            std::size_t after = at + name.size();
            while (after < text.size() && text[after] == ' ') ++after;
            if (starts && after < text.size() && text[after] == '(') return n;
        }
    }
    return 0;
}

std::string absolute_path(const std::filesystem::path& p) { return std::filesystem::absolute(p).lexically_normal().string(); }

/// The module's base in the ROM: a label of the listing that the map has too.
std::uint32_t module_base(const As86Listing& listing, const debug::SymbolTable& symbols, const AsmModule& m) {
    for (const auto& [label, offset] : listing.labels) {
        // The table names a global without bcc's underscore (`isr_dpram` for `_isr_dpram`).
        const debug::Symbol* s = symbols.find(label);
        if (!s && label.size() > 1 && label[0] == '_') s = symbols.find(label.substr(1));
        if (s && s->kind == debug::Symbol::Kind::code) return s->address - offset;
    }
    throw ConfigError(m.listing.string() + ": none of its labels is in the firmware's map (a listing of another build?)");
}

} // namespace

CodeMap firmware_code_map(const std::vector<AsmModule>& asm_modules, const std::vector<std::filesystem::path>& c_sources,
                          const debug::SymbolTable& symbols) {
    CodeMap map;
    std::map<std::uint32_t, std::size_t> at; // linear -> site index, filled below
    for (const AsmModule& m : asm_modules) {
        const As86Listing listing = read_as86_listing(m.listing);
        const std::uint32_t base = module_base(listing, symbols, m);
        map.files.push_back(absolute_path(m.source));
        for (const ListedInstruction& ins : listing.instructions)
            map.sites.push_back({base + ins.offset, base + ins.offset + 1, map.files.size() - 1, ins.line, ins.leads_line});
    }
    std::sort(map.sites.begin(), map.sites.end(), [](const CodeSite& a, const CodeSite& b) { return a.linear < b.linear; });
    for (std::size_t i = 0; i < map.sites.size(); ++i) at[map.sites[i].linear] = i;
    for (const auto& c : c_sources) map.files.push_back(absolute_path(c));
    for (const debug::Symbol& s : symbols.symbols()) {
        if (s.kind != debug::Symbol::Kind::code) continue;
        const auto site = at.find(s.address);
        if (site != at.end()) { // an assembly routine
            const CodeSite& c = map.sites[site->second];
            map.functions.push_back({c.file, s.name, c.line, s.address});
            continue;
        }
        // A C function; a static another module shares the name of is MODULE__NAME.
        std::string name = s.name, module;
        if (const std::size_t sep = name.find("__"); sep != std::string::npos && sep > 0) {
            module = name.substr(0, sep);
            name = name.substr(sep + 2);
        }
        for (std::size_t k = 0; k < c_sources.size(); ++k) {
            if (!module.empty() && c_sources[k].stem() != module) continue;
            if (const unsigned line = definition_line(c_sources[k], name)) {
                map.functions.push_back({asm_modules.size() + k, s.name, line, s.address});
                // The definition line counts the function's first instruction: lcov drops a file
                // without line records, and this is the one line bcc's output can be tied to.
                map.sites.push_back({s.address, s.address + 1, asm_modules.size() + k, line, true});
                break;
            }
        }
    }
    std::sort(map.sites.begin(), map.sites.end(), [](const CodeSite& a, const CodeSite& b) { return a.linear < b.linear; });
    return map;
}

CodeMap symbol_code_map(const debug::SymbolTable& symbols, std::uint32_t base, std::uint32_t end,
                        const std::filesystem::path& listing) {
    CodeMap map;
    map.ranges = true;
    map.files.push_back(absolute_path(listing));
    OutputFile out(listing);
    unsigned line = 0;
    for (const debug::Symbol& s : symbols.symbols()) {
        if (s.kind != debug::Symbol::Kind::code || s.size == 0 || s.address < base || s.address >= end) continue;
        const std::uint32_t stop = std::min<std::uint64_t>(end, std::uint64_t{s.address} + s.size);
        map.functions.push_back({0, s.name, line + 1, s.address});
        // One line per paragraph the symbol touches: its first piece may start mid-paragraph.
        for (std::uint32_t a = s.address; a < stop; a = (a | 15u) + 1) {
            const std::uint32_t piece_end = std::min(stop, (a | 15u) + 1);
            char row[32];
            std::snprintf(row, sizeof row, "%05X  ", static_cast<unsigned>(a));
            out.stream() << row << s.name << "+0x" << std::hex << std::uppercase << (a - s.address) << std::dec << '\n';
            map.sites.push_back({a, piece_end, 0, ++line, true});
        }
    }
    out.close();
    if (map.functions.empty())
        throw ConfigError("--coverage: the symbol table has no code symbol in the ROM (" + listing.string() + " would be empty)");
    std::sort(map.sites.begin(), map.sites.end(), [](const CodeSite& a, const CodeSite& b) { return a.linear < b.linear; });
    return map;
}

} // namespace rcsim::coverage
