// rcsim — symbol tables from ld86, nasm and "Publics by Value" maps and from the simple text format (symbols.h).
#include "scenarios/debug/symbols.h"

#include "models/plumbing/hex.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
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

/// nasm's identifiers (letters, digits and _ $ # @ ~ . ?; a digit, $ or # not first), which also
/// covers the C and assembler names of a linker's map.
bool valid_map_name(const std::string& s) {
    // (strchr finds a NUL too: the terminator.)
    auto first = [](unsigned char c) { return std::isalpha(c) || (c != 0 && std::strchr("_.?@", c) != nullptr); };
    auto rest = [](unsigned char c) { return std::isalnum(c) || (c != 0 && std::strchr("_$#@~.?", c) != nullptr); };
    return !s.empty() && first(s[0]) && std::all_of(s.begin() + 1, s.end(), rest);
}

/// `s` with control bytes as \xNN: a NUL in a message would cut what() short.
std::string shown(const std::string& s) {
    std::string out;
    for (const unsigned char c : s) out += c >= 0x20 && c < 0x7F ? std::string(1, char(c)) : "\\x" + rcsim::hex(c);
    return out;
}

/// A line of a map or symbol file holds text: a NUL or another control byte (but the white space
/// of a text file) is refused where it is, not taken into a name (issue #48).
void check_text(const std::string& line, const std::string& where) {
    const auto bad = std::find_if(line.begin(), line.end(), [](unsigned char c) {
        return (c < 0x20 && c != '\t' && c != '\r' && c != '\v' && c != '\f') || c == 0x7F;
    });
    if (bad != line.end())
        throw SymbolError(where + ": byte " + rcsim::hex(static_cast<unsigned char>(*bad)) + (*bad == 0 ? " (NUL)" : "") +
                          " at column " + std::to_string(bad - line.begin() + 1) + ": a map or symbol file is text");
}

std::string plain(const std::string& name) { return name.size() > 1 && name[0] == '_' ? name.substr(1) : name; }

} // namespace

// ---- the table ----

void SymbolTable::add(Symbol symbol, const std::string& where) {
    append(std::move(symbol), where);
    sort();
}

// The loaders append every symbol of a map and sort once (fill_sizes): sorting after each one,
// as add() does, made loading a map quadratic in its symbols.
void SymbolTable::append(Symbol symbol, const std::string& where) {
    if (by_name_.count(symbol.name))
        throw SymbolError((where.empty() ? std::string("symbol table") : where) + ": duplicate symbol '" +
                          symbol.name + "'");
    by_name_.emplace(symbol.name, symbols_.size());
    symbols_.push_back(std::move(symbol));
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

// One walk from the last symbol back: for each kind, the address of the nearest symbol after
// the one at hand and the next higher address after that one, so aliases (many names at one
// address) find their end without a scan each (issue #48: 100 000 aliases took 27 s).
void SymbolTable::fill_sizes(std::uint32_t code_end, std::uint32_t data_end) {
    sort(); // (the symbols a loader appended)
    struct Ahead {
        bool seen = false;
        std::uint32_t nearest = 0; // the address of the closest symbol of the kind after this one
        std::uint32_t above = 0;   // the lowest address of the kind above `nearest`, if `higher`
        bool higher = false;
    };
    Ahead ahead[2];
    for (std::size_t i = symbols_.size(); i-- > 0;) {
        Symbol& s = symbols_[i];
        Ahead& k = ahead[s.kind == Symbol::Kind::code ? 0 : 1];
        if (s.size == 0) {
            std::uint32_t end = s.kind == Symbol::Kind::code ? code_end : data_end;
            if (k.seen && k.nearest > s.address) end = k.nearest;
            else if (k.seen && k.higher) end = k.above; // k.nearest == s.address: an alias
            s.size = end > s.address ? end - s.address : 0;
        }
        if (k.seen && k.nearest != s.address) k.above = k.nearest, k.higher = true;
        k.nearest = s.address, k.seen = true;
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
        check_text(line, at(path, n));
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
        // MODULE__NAME, not MODULE:NAME: gdb reads a colon in `break isr:send` as FILE:FUNCTION.
        s.name = e.local && uses[plain(e.name)] > 1 ? e.module + "__" + plain(e.name) : plain(e.name);
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
        table.append(std::move(s), e.where);
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
        check_text(line, at(path, n));
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
            if (!valid_map_name(t[1])) throw SymbolError(at(path, n) + ": bad constant name '" + shown(t[1]) + "'");
            table.add_constant({t[1], std::stoull(t[0], nullptr, 16)}, at(path, n));
        } else if (part.rfind("Symbols ", 0) == 0 && t[0] != "Real") {
            if (t.size() != 3) throw SymbolError(at(path, n) + ": not a 'Real Virtual Name' symbol line");
            const std::uint32_t real = parse_hex(t[0], at(path, n), "address");
            const std::uint32_t virt = parse_hex(t[1], at(path, n), "address");
            if (!valid_map_name(t[2])) throw SymbolError(at(path, n) + ": bad symbol name '" + shown(t[2]) + "'");
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
            table.append(std::move(s), at(path, n));
        }
    }
    if (!header_seen) throw SymbolError(path + ": empty file, not a nasm map");
    table.fill_sizes(code_end ? code_end : rom_end, data_end);
    return table;
}

// ---- "Publics by Value" maps (MS LINK, Borland TLINK, Paradigm LOCATE) ----

namespace {

/// A segment of the map's head, "00000H 0001FH 00020H _TEXT CODE" (Start Stop Length Name Class):
/// linear addresses relative to the map's segment 0000.
struct MapSegment {
    std::uint32_t start = 0, length = 0;
    bool code = false; // its class is CODE (or ends so: FAR_CODE)
};

bool parse_hex_h(const std::string& s, std::uint32_t& value) {
    if (s.size() < 2 || s.size() > 9 || std::toupper(static_cast<unsigned char>(s.back())) != 'H') return false;
    const std::string digits = s.substr(0, s.size() - 1);
    if (!is_hex(digits)) return false;
    value = static_cast<std::uint32_t>(std::stoul(digits, nullptr, 16));
    return true;
}

bool read_segment_row(const std::vector<std::string>& t, MapSegment& segment, const std::string& where) {
    std::uint32_t stop = 0;
    if (t.size() < 4 || !parse_hex_h(t[0], segment.start) || !parse_hex_h(t[1], stop) ||
        !parse_hex_h(t[2], segment.length))
        return false;
    // Start, stop and length are linear addresses and a size in the 8086's 1 MB: more does not fit
    // (and start + length would wrap the arithmetic of the regions' ends).
    if (segment.start > 0xFFFFF || stop > 0xFFFFF || segment.length > 0x100000 ||
        segment.start + segment.length > 0x100000)
        throw SymbolError(where + ": segment '" + shown(t[3]) + "' " + t[0] + " " + t[1] + " " + t[2] +
                          " does not fit in the 8086's 1 MB (start + length at most 100000H)");
    std::string cls = t.size() >= 5 ? t[4] : "";
    std::transform(cls.begin(), cls.end(), cls.begin(), [](unsigned char c) { return char(std::toupper(c)); });
    segment.code = cls.size() >= 4 && cls.compare(cls.size() - 4, 4, "CODE") == 0;
    return true;
}

bool is_publics_heading(const std::vector<std::string>& t) {
    return t.size() == 4 && t[0] == "Address" && t[1] == "Publics" && t[2] == "by" && (t[3] == "Value" || t[3] == "Name");
}

/// A row of a Publics section: "SSSS:OOOO [Abs|Idle|Res|...] NAME".
struct PublicRow {
    std::string name, where;
    std::uint32_t segment = 0, offset = 0;
    bool absolute = false;
};

PublicRow read_public_row(const std::vector<std::string>& t, const std::string& where) {
    PublicRow row;
    row.where = where;
    const auto colon = t[0].find(':');
    const std::string seg = t[0].substr(0, colon), off = colon == std::string::npos ? "" : t[0].substr(colon + 1);
    if (seg.size() > 4 || off.size() > 4 || !is_hex(seg) || !is_hex(off))
        throw SymbolError(where + ": bad address '" + t[0] + "' (SSSS:OOOO, 4 hex digits each)");
    if (t.size() < 2) throw SymbolError(where + ": missing the name after the address (SSSS:OOOO NAME)");
    row.segment = std::uint32_t(std::stoul(seg, nullptr, 16));
    row.offset = std::uint32_t(std::stoul(off, nullptr, 16));
    row.name = t.back();
    if (!valid_map_name(row.name)) throw SymbolError(where + ": bad symbol name '" + shown(row.name) + "'");
    // Between address and name, a linker's remarks: Abs (an absolute value), Idle, Res, a type.
    for (std::size_t i = 1; i + 1 < t.size(); ++i)
        if (t[i] == "Abs" || t[i] == "ABS" || t[i] == "abs") row.absolute = true;
    return row;
}

} // namespace

// The segment list at the head (rows of five columns with H-suffixed hex), then one or two
// Publics sections (by Name, by Value: the same symbols twice) whose rows start with SSSS:OOOO;
// a line starting otherwise ("Program entry point at ...") ends a section.
SymbolTable SymbolTable::load_publics_map(const std::string& path, std::uint16_t load_segment) {
    auto in = open(path);
    std::vector<MapSegment> segments;
    std::vector<PublicRow> rows;
    std::map<std::string, std::size_t> first_row; // name -> index into rows
    std::string line;
    int n = 0;
    bool in_publics = false, heading_seen = false;
    while (std::getline(in, line)) {
        ++n;
        check_text(line, at(path, n));
        const auto t = tokens(line);
        if (t.empty()) continue;
        if (is_publics_heading(t)) {
            in_publics = heading_seen = true;
            continue;
        }
        MapSegment segment;
        if (!in_publics) {
            if (read_segment_row(t, segment, at(path, n))) segments.push_back(segment);
            continue;
        }
        if (!std::isxdigit(static_cast<unsigned char>(t[0][0])) ||
            (t[0].find(':') == std::string::npos && !is_hex(t[0]))) {
            in_publics = false;
            continue;
        }
        PublicRow row = read_public_row(t, at(path, n));
        const auto seen = first_row.find(row.name);
        if (seen == first_row.end()) {
            first_row.emplace(row.name, rows.size());
            rows.push_back(std::move(row));
        } else if (rows[seen->second].segment * 16 + rows[seen->second].offset != row.segment * 16 + row.offset) {
            throw SymbolError(row.where + ": '" + row.name + "' listed at " + t[0] + " here and elsewhere at " +
                              rows[seen->second].where);
        }
    }
    if (!heading_seen) throw SymbolError(path + ": no 'Address  Publics by Value' (or by Name) heading");

    const std::uint32_t base = std::uint32_t(load_segment) * 16;
    std::uint32_t code_end = 0, data_end = 0;
    for (const auto& s : segments) {
        std::uint32_t& end = s.code ? code_end : data_end;
        end = std::max(end, base + s.start + s.length);
    }
    SymbolTable table;
    for (const auto& row : rows) {
        // gdb gets C's name (`main`, not `_main`) unless the map has that name as well.
        const std::string name = row.name[0] == '_' && !first_row.count(plain(row.name)) ? plain(row.name) : row.name;
        const std::uint32_t relative = row.segment * 16 + row.offset;
        if (row.absolute) {
            table.add_constant({name, relative}, row.where);
            continue;
        }
        Symbol s;
        s.name = name;
        if (name != row.name) s.map_name = row.name;
        if (row.segment + load_segment > 0xFFFF)
            throw SymbolError(row.where + ": '" + row.name + "' beyond the 8086's segments (load segment + its segment > FFFF)");
        s.address = base + relative;
        auto in_segment = std::find_if(segments.begin(), segments.end(), [&](const MapSegment& m) {
            return relative >= m.start && relative - m.start < m.length;
        });
        const bool code = in_segment != segments.end() ? in_segment->code : s.address >= rom_base && s.address < rom_end;
        s.kind = code ? Symbol::Kind::code : Symbol::Kind::data;
        table.append(std::move(s), row.where);
    }
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
        check_text(line, at(path, n));
        const auto hash = line.find('#');
        const auto t = tokens(hash == std::string::npos ? line : line.substr(0, hash));
        if (t.empty()) continue;
        const std::string where = at(path, n);
        if (t.size() > 4) throw SymbolError(where + ": too many fields (NAME ADDRESS [SIZE [code|data]])");
        if (t.size() < 2) throw SymbolError(where + ": missing ADDRESS (NAME ADDRESS [SIZE [code|data]])");
        if (!valid_name(t[0])) throw SymbolError(where + ": bad symbol name '" + shown(t[0]) + "'");
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
        table.append(std::move(s), where);
    }
    table.fill_sizes(rom_end, 0);
    return table;
}

namespace {

/// FILE@SEG -> FILE and SEG (1-4 hex digits after the last '@'); FILE alone -> no segment.
std::pair<std::string, std::optional<std::uint16_t>> split_load_segment(const std::string& spec) {
    const auto at_sign = spec.rfind('@');
    if (at_sign == std::string::npos) return {spec, std::nullopt};
    const std::string seg = spec.substr(at_sign + 1);
    if (seg.empty() || seg.size() > 4 || !is_hex(seg))
        throw SymbolError(spec + ": bad load segment '" + seg + "' after '@' (FILE@SEG, SEG 1-4 hex digits: F000)");
    return {spec.substr(0, at_sign), std::uint16_t(std::stoul(seg, nullptr, 16))};
}

enum class MapFormat { nasm, publics, ld86, text };

/// nasm's heading on the first line, a Publics heading anywhere (MS LINK and TLINK maps start
/// with the segment list, whose lines look like ld86's five columns), five-column lines of ld86.
MapFormat detect_format(const std::string& path) {
    auto in = open(path);
    std::string line;
    std::optional<MapFormat> by_first_line;
    while (std::getline(in, line)) {
        const auto t = tokens(line);
        if (t.empty()) continue;
        if (is_publics_heading(t)) return MapFormat::publics;
        if (by_first_line) continue;
        if (line.rfind("- NASM Map file", 0) == 0) return MapFormat::nasm;
        by_first_line = t.size() >= 5 && t[0][0] != '#' ? MapFormat::ld86 : MapFormat::text;
    }
    return by_first_line.value_or(MapFormat::text);
}

} // namespace

SymbolTable SymbolTable::load(const std::string& spec) {
    const auto [path, segment] = split_load_segment(spec);
    switch (detect_format(path)) {
    case MapFormat::nasm:
        return load_nasm_map(path, segment ? std::uint32_t(*segment) * 16 : rom_base);
    case MapFormat::publics:
        return load_publics_map(path, segment.value_or(0));
    case MapFormat::ld86: {
        Ld86Layout layout;
        if (segment) layout.code_base = std::uint32_t(*segment) * 16;
        return load_ld86_map(path, layout);
    }
    case MapFormat::text:
        break;
    }
    if (segment) throw SymbolError(spec + ": a load segment (@SEG) places a map; NAME ADDRESS lines are absolute");
    return load_text(path);
}

} // namespace rcsim::debug
