// rcsim — symbol tables from ld86 and nasm maps and from the simple text format (symbols.h).
#include "scenarios/debug/symbols.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

namespace rcsim::debug {

namespace {

std::string at(const std::string& path, int line) { return path + ":" + std::to_string(line); }

std::ifstream open(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw SymbolError(path + ": cannot open the symbol file");
    return in;
}

std::vector<std::string> tokens(const std::string& line) {
    std::istringstream ss(line);
    std::vector<std::string> out;
    for (std::string t; ss >> t;) out.push_back(t);
    return out;
}

bool is_hex(const std::string& s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isxdigit(c) != 0; });
}

/// Hex digits without a prefix, at most `max` (throws with `where` otherwise).
std::uint32_t parse_hex(const std::string& s, const std::string& where, const char* what) {
    if (!is_hex(s) || s.size() > 8) throw SymbolError(where + ": bad " + what + " '" + s + "' (hex digits)");
    return static_cast<std::uint32_t>(std::stoul(s, nullptr, 16));
}

bool valid_name(const std::string& s) {
    auto first = [](unsigned char c) { return std::isalpha(c) || c == '_' || c == '.' || c == '$' || c == '@'; };
    auto rest = [&](unsigned char c) { return first(c) || std::isdigit(c); };
    return !s.empty() && first(s[0]) && std::all_of(s.begin() + 1, s.end(), rest);
}

/// nasm's identifiers: letters, digits and _ $ # @ ~ . ? (a digit, $ or # not first).
bool valid_nasm_name(const std::string& s) {
    auto first = [](unsigned char c) { return std::isalpha(c) || std::strchr("_.?@", c) != nullptr; };
    auto rest = [](unsigned char c) { return std::isalnum(c) || std::strchr("_$#@~.?", c) != nullptr; };
    return !s.empty() && first(s[0]) && std::all_of(s.begin() + 1, s.end(), rest);
}

std::string plain(const std::string& name) { return name.size() > 1 && name[0] == '_' ? name.substr(1) : name; }

} // namespace

// ---- the table ----

void SymbolTable::add(Symbol symbol, const std::string& where) {
    if (by_name_.count(symbol.name))
        throw SymbolError((where.empty() ? std::string("symbol table") : where) + ": duplicate symbol '" +
                          symbol.name + "'");
    by_name_.emplace(symbol.name, symbols_.size());
    symbols_.push_back(std::move(symbol));
    sort();
}

void SymbolTable::sort() {
    std::sort(symbols_.begin(), symbols_.end(), [](const Symbol& a, const Symbol& b) {
        return a.address != b.address ? a.address < b.address : a.name < b.name;
    });
    by_name_.clear();
    by_map_name_.clear();
    max_size_ = 0;
    for (std::size_t i = 0; i < symbols_.size(); ++i) {
        by_name_[symbols_[i].name] = i;
        if (!symbols_[i].map_name.empty()) by_map_name_[symbols_[i].map_name] = i;
        max_size_ = std::max(max_size_, symbols_[i].size);
    }
}

void SymbolTable::fill_sizes(std::uint32_t code_end, std::uint32_t data_end) {
    for (std::size_t i = 0; i < symbols_.size(); ++i) {
        Symbol& s = symbols_[i];
        if (s.size != 0) continue;
        std::uint32_t end = s.kind == Symbol::Kind::code ? code_end : data_end;
        for (std::size_t j = i + 1; j < symbols_.size(); ++j) {
            if (symbols_[j].kind == s.kind && symbols_[j].address > s.address) {
                end = symbols_[j].address;
                break;
            }
        }
        s.size = end > s.address ? end - s.address : 0;
    }
    sort();
}

const Symbol* SymbolTable::find(std::string_view name) const {
    auto it = by_name_.find(std::string(name));
    if (it != by_name_.end()) return &symbols_[it->second];
    it = by_map_name_.find(std::string(name));
    return it == by_map_name_.end() ? nullptr : &symbols_[it->second];
}

void SymbolTable::add_constant(Constant constant, const std::string& where) {
    if (this->constant(constant.name))
        throw SymbolError((where.empty() ? std::string("symbol table") : where) + ": duplicate constant '" +
                          constant.name + "'");
    constants_.push_back(std::move(constant));
}

const Constant* SymbolTable::constant(std::string_view name) const {
    auto it = std::find_if(constants_.begin(), constants_.end(), [&](const Constant& c) { return c.name == name; });
    return it == constants_.end() ? nullptr : &*it;
}

const Symbol* SymbolTable::containing(std::uint32_t linear) const {
    // The last symbol starting at or below `linear`, walking back no further than the longest
    // symbol could reach (symbols of the two kinds may interleave).
    auto it = std::upper_bound(symbols_.begin(), symbols_.end(), linear,
                               [](std::uint32_t a, const Symbol& s) { return a < s.address; });
    while (it != symbols_.begin()) {
        --it;
        const std::uint32_t offset = linear - it->address;
        if (offset < it->size) return &*it;
        if (offset >= max_size_) break;
    }
    return nullptr;
}

// ---- ld86 -M ----

// Lines: "module name segment value flags" with an 8-digit hex value and flags R (global),
// r (local), a (absolute), and a trailing C for a common symbol; "Total memory used: N" ends it.
SymbolTable SymbolTable::load_ld86_map(const std::string& path, const Ld86Layout& layout) {
    auto in = open(path);
    struct Entry { std::string module, name; int segment; std::uint32_t value; bool local; std::string where; };
    std::vector<Entry> entries;
    std::map<std::string, std::uint32_t> absolute;
    std::string line;
    int n = 0;
    while (std::getline(in, line)) {
        ++n;
        const auto t = tokens(line);
        if (t.empty() || (t.size() >= 3 && t[0] == "Total" && t[1] == "memory")) continue;
        if (t.size() < 5 || t.size() > 6 || (t.size() == 6 && t[5] != "C"))
            throw SymbolError(at(path, n) + ": not an ld86 -M line (module name segment value flags)");
        if (t[2].size() != 1 || !std::isdigit(static_cast<unsigned char>(t[2][0])))
            throw SymbolError(at(path, n) + ": bad segment '" + t[2] + "' (one digit)");
        const std::uint32_t value = parse_hex(t[3], at(path, n), "value");
        if (t[4] == "a") {
            absolute[t[1]] = value;
        } else if (t[4] == "R") {
            entries.push_back({t[0], t[1], t[2][0] - '0', value, false, at(path, n)});
        } else if (t[4] == "r") {
            // A C static (bcc's `_name`) in the firmware's segments; an as86 label stays out.
            const int segment = t[2][0] - '0';
            if (t[1].size() > 1 && t[1][0] == '_' && t[1][1] != '_' && (segment == 0 || segment == 3))
                entries.push_back({t[0], t[1], segment, value, true, at(path, n)});
        } else {
            throw SymbolError(at(path, n) + ": bad flags '" + t[4] + "' (R, r or a)");
        }
    }
    std::int64_t data_base = layout.data_base;
    if (data_base < 0 && absolute.count("DATA_SEG")) data_base = std::int64_t(absolute["DATA_SEG"]) * 16;

    // Statics of different modules may share a name, and a static may share a global's.
    std::map<std::string, int> uses;
    for (const auto& e : entries) ++uses[plain(e.name)];

    SymbolTable table;
    std::uint32_t code_end = rom_end, data_end = 0;
    for (const auto& e : entries) {
        // The linker's own symbols bound the regions instead of naming code or data.
        if (e.name == "__segoff" && e.segment == 0) code_end = layout.code_base + e.value * 16;
        if (e.name == "__end" && e.segment == 3 && data_base >= 0) data_end = std::uint32_t(data_base) + e.value;
        if (e.name.rfind("__", 0) == 0) continue;
        Symbol s;
        s.name = e.local && uses[plain(e.name)] > 1 ? e.module + ":" + plain(e.name) : plain(e.name);
        s.local = e.local;
        if (e.segment == 0) {
            s.address = layout.code_base + e.value;
        } else if (e.segment == 3) {
            if (data_base < 0) continue;
            s.address = std::uint32_t(data_base) + e.value;
            s.kind = Symbol::Kind::data;
        } else {
            throw SymbolError(e.where + ": symbol '" + e.name + "' in segment " + std::to_string(e.segment) +
                              " (the firmware links code in 0 and data in 3)");
        }
        table.add(std::move(s), e.where);
    }
    table.fill_sizes(code_end, data_end);
    return table;
}

// ---- nasm [map all FILE] ----

// The parts read: "-- Program origin --" (the origin, hex), "-- Sections (summary) --" (Vstart
// Start Stop Length Class Name rows) and "-- Symbols --" with a "---- Section NAME ----" heading
// per section and "Real Virtual Name" rows. The constants (`equ`, struc offsets, `absolute`
// labels) come first under "---- No Section ----" as "Value Name" rows. A progbits symbol sits in the image at Real - origin,
// so at `base + Real - origin` whatever CS the code runs with; a nobits symbol (a RAM variable,
// `section .bss nobits vstart=0x400`) at its Virtual address taken as linear.
SymbolTable SymbolTable::load_nasm_map(const std::string& path, std::uint32_t base) {
    auto in = open(path);
    struct Section { std::uint32_t vstart = 0, start = 0, stop = 0; bool nobits = false; };
    std::map<std::string, Section> sections;
    std::string part, section, line;
    std::uint32_t origin = 0;
    int n = 0;
    bool header_seen = false, constants = false;
    SymbolTable table;
    std::uint32_t code_end = 0, data_end = 0;
    while (std::getline(in, line)) {
        ++n;
        const auto t = tokens(line);
        if (t.empty()) continue;
        if (!header_seen) {
            if (line.rfind("- NASM Map file", 0) != 0)
                throw SymbolError(at(path, n) + ": not a nasm map file (no '- NASM Map file' heading)");
            header_seen = true;
            continue;
        }
        if (t[0] == "--") { // "-- Program origin --", "-- Sections (summary) --", "-- Symbols --"
            part = t.size() > 2 ? t[1] + " " + t[2] : "";
            continue;
        }
        if (t[0] == "----") { // "---- Section NAME ----" or "---- No Section ----"
            section = t.size() > 2 && t[1] == "Section" ? t[2] : "";
            constants = t.size() > 2 && t[1] == "No" && t[2] == "Section";
            continue;
        }
        if (part == "Program origin") {
            origin = parse_hex(t[0], at(path, n), "origin");
        } else if (part == "Sections (summary)" && t[0] != "Vstart") {
            if (t.size() != 6) throw SymbolError(at(path, n) + ": not a 'Vstart Start Stop Length Class Name' line");
            Section s;
            s.vstart = parse_hex(t[0], at(path, n), "section vstart");
            s.start = parse_hex(t[1], at(path, n), "section start");
            s.stop = parse_hex(t[2], at(path, n), "section stop");
            s.nobits = t[4] == "nobits";
            sections[t[5]] = s;
        } else if (part.rfind("Symbols ", 0) == 0 && constants) {
            if (t[0] == "Value") continue;
            if (t.size() != 2) throw SymbolError(at(path, n) + ": not a 'Value Name' constant line");
            // 16 hex digits for a negative one (-1 is FFFFFFFFFFFFFFFF).
            if (!is_hex(t[0]) || t[0].size() > 16) throw SymbolError(at(path, n) + ": bad value '" + t[0] + "' (hex digits)");
            if (!valid_nasm_name(t[1])) throw SymbolError(at(path, n) + ": bad constant name '" + t[1] + "'");
            table.add_constant({t[1], std::stoull(t[0], nullptr, 16)}, at(path, n));
        } else if (part.rfind("Symbols ", 0) == 0 && t[0] != "Real") {
            if (t.size() != 3) throw SymbolError(at(path, n) + ": not a 'Real Virtual Name' symbol line");
            const std::uint32_t real = parse_hex(t[0], at(path, n), "address");
            const std::uint32_t virt = parse_hex(t[1], at(path, n), "address");
            if (!valid_nasm_name(t[2])) throw SymbolError(at(path, n) + ": bad symbol name '" + t[2] + "'");
            auto sec = sections.find(section);
            const bool nobits = sec != sections.end() && sec->second.nobits;
            Symbol s;
            s.name = t[2];
            if (nobits) {
                s.address = virt;
                s.kind = Symbol::Kind::data;
                data_end = std::max(data_end, sec->second.vstart + (sec->second.stop - sec->second.start));
            } else {
                if (real < origin) throw SymbolError(at(path, n) + ": address below the program origin");
                s.address = base + (real - origin);
                if (sec != sections.end()) code_end = std::max(code_end, base + (sec->second.stop - origin));
            }
            table.add(std::move(s), at(path, n));
        }
    }
    if (!header_seen) throw SymbolError(path + ": empty file, not a nasm map");
    table.fill_sizes(code_end ? code_end : rom_end, data_end);
    return table;
}

// ---- the simple text format ----

// NAME ADDRESS [SIZE [code|data]]; `#` starts a comment. ADDRESS: 0x-prefixed hex linear address
// or SEGMENT:OFFSET in hex (F000:024C); SIZE decimal or 0x-hex. Without a kind, an address in the
// ROM (F0000-FFFFF) is code and any other data.
SymbolTable SymbolTable::load_text(const std::string& path) {
    auto in = open(path);
    SymbolTable table;
    std::string line;
    int n = 0;
    while (std::getline(in, line)) {
        ++n;
        const auto hash = line.find('#');
        const auto t = tokens(hash == std::string::npos ? line : line.substr(0, hash));
        if (t.empty()) continue;
        const std::string where = at(path, n);
        if (t.size() > 4) throw SymbolError(where + ": too many fields (NAME ADDRESS [SIZE [code|data]])");
        if (t.size() < 2) throw SymbolError(where + ": missing ADDRESS (NAME ADDRESS [SIZE [code|data]])");
        if (!valid_name(t[0])) throw SymbolError(where + ": bad symbol name '" + t[0] + "'");
        Symbol s;
        s.name = t[0];
        const std::string& a = t[1];
        const auto colon = a.find(':');
        if (colon != std::string::npos) {
            const std::string seg = a.substr(0, colon), off = a.substr(colon + 1);
            if (seg.size() > 4 || off.size() > 4 || !is_hex(seg) || !is_hex(off))
                throw SymbolError(where + ": bad address '" + a + "' (SEGMENT:OFFSET, 4 hex digits each)");
            s.address = (std::uint32_t(std::stoul(seg, nullptr, 16)) << 4) + std::uint32_t(std::stoul(off, nullptr, 16));
        } else if (a.size() > 2 && a.size() <= 8 && a[0] == '0' && (a[1] == 'x' || a[1] == 'X') && is_hex(a.substr(2))) {
            s.address = std::uint32_t(std::stoul(a.substr(2), nullptr, 16));
        } else {
            throw SymbolError(where + ": bad address '" + a + "' (0x12345 or F000:0123)");
        }
        if (s.address >= 0x110000)  // FFFF:FFFF = 10FFEF is the highest an 8086 can form
            throw SymbolError(where + ": address '" + a + "' beyond the 8086's address space");
        if (t.size() >= 3) {
            const std::string& z = t[2];
            const bool hex = z.size() > 2 && z[0] == '0' && (z[1] == 'x' || z[1] == 'X');
            const std::string digits = hex ? z.substr(2) : z;
            const bool ok = !digits.empty() && digits.size() <= (hex ? 5u : 7u) &&
                            std::all_of(digits.begin(), digits.end(), [&](unsigned char c) {
                                return hex ? std::isxdigit(c) != 0 : std::isdigit(c) != 0;
                            });
            if (!ok || std::stoul(digits, nullptr, hex ? 16 : 10) > 0x100000)
                throw SymbolError(where + ": bad size '" + z + "' (bytes, decimal or 0x-hex, at most 1 MB)");
            s.size = std::uint32_t(std::stoul(digits, nullptr, hex ? 16 : 10));
        }
        if (t.size() == 4) {
            if (t[3] != "code" && t[3] != "data") throw SymbolError(where + ": bad kind '" + t[3] + "' (code or data)");
            s.kind = t[3] == "code" ? Symbol::Kind::code : Symbol::Kind::data;
        } else {
            s.kind = s.address >= rom_base && s.address < rom_end ? Symbol::Kind::code : Symbol::Kind::data;
        }
        table.add(std::move(s), where);
    }
    table.fill_sizes(rom_end, 0);
    return table;
}

SymbolTable SymbolTable::load(const std::string& path) {
    auto in = open(path);
    std::string line;
    while (std::getline(in, line)) {
        const auto t = tokens(line);
        if (t.empty()) continue;
        if (line.rfind("- NASM Map file", 0) == 0) return load_nasm_map(path);
        if (t.size() >= 5 && t[0][0] != '#') return load_ld86_map(path);
        break;
    }
    return load_text(path);
}

} // namespace rcsim::debug
