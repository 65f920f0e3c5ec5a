// rcsim — the annotations file of the static bound. See bound.h (Annotation).
#include "scenarios/bound/bound.h"

#include "models/plumbing/config_error.h"

#include <cctype>
#include <fstream>
#include <sstream>

namespace rcsim::bound {
namespace {

constexpr std::uint64_t kMaxIterations = 1u << 20; // more is a typo, not a loop of a handler
constexpr std::size_t kMaxLines = 100000;

bool parse_number(const std::string& s, std::uint64_t& v) {
    if (s.empty()) return false;
    const bool is_hex = s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X');
    const std::string digits = is_hex ? s.substr(2) : s;
    if (digits.empty() || digits.size() > 8) return false;
    v = 0;
    for (char c : digits) {
        const int d = std::isdigit(static_cast<unsigned char>(c)) ? c - '0'
                      : is_hex && std::isxdigit(static_cast<unsigned char>(c)) ? std::tolower(c) - 'a' + 10
                                                                                 : -1;
        if (d < 0) return false;
        v = v * (is_hex ? 16 : 10) + std::uint64_t(d);
    }
    return true;
}

/// SYMBOL, SYMBOL+OFFSET or a linear address.
bool parse_where(const std::string& s, const debug::SymbolTable& symbols, std::uint32_t& address, std::string& why) {
    std::uint64_t v = 0;
    if (parse_number(s, v)) {
        if (v > 0xFFFFF) return why = "address " + s + " is beyond 1 MB", false;
        address = std::uint32_t(v);
        return true;
    }
    const std::size_t plus = s.find('+');
    const std::string name = s.substr(0, plus);
    const debug::Symbol* sym = symbols.find(name);
    if (!sym) return why = "no symbol '" + name + "' (a name of the ROM's symbols, or an address 0x...)", false;
    std::uint64_t off = 0;
    if (plus != std::string::npos && !parse_number(s.substr(plus + 1), off))
        return why = "offset '" + s.substr(plus + 1) + "' is not a number", false;
    if (off > 0xFFFF) return why = "offset " + s.substr(plus + 1) + " is beyond 64 KB", false;
    address = std::uint32_t(sym->address + off);
    return true;
}

} // namespace

std::vector<Annotation> load_annotations(const std::string& path, const debug::SymbolTable& symbols) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw ConfigError(path, 0, "cannot read the annotations file");
    std::vector<Annotation> out;
    std::string line;
    int number = 0;
    while (std::getline(f, line)) {
        if (++number > int(kMaxLines)) throw ConfigError(path, number, "more than 100000 lines");
        auto bad = [&](const std::string& why) { throw ConfigError(path, number, why); };
        if (line.find('\0') != std::string::npos) bad("a NUL byte: not a text file");
        Annotation a;
        const std::size_t hash = line.find('#');
        if (hash != std::string::npos) {
            a.reason = line.substr(hash + 1);
            const std::size_t b = a.reason.find_first_not_of(" \t");
            a.reason = b == std::string::npos ? "" : a.reason.substr(b);
            line.resize(hash);
        }
        std::istringstream words(line);
        std::string where, kind;
        if (!(words >> where)) continue; // blank or a comment
        if (!(words >> kind)) bad("'" + where + "' needs a kind: iterations N, targets A ..., irq_save or irq_restore");
        std::string why;
        if (!parse_where(where, symbols, a.address, why)) bad(why);
        a.where = path + ":" + std::to_string(number);
        std::string word;
        if (kind == "iterations") {
            a.kind = Annotation::Kind::iterations;
            if (!(words >> word) || !parse_number(word, a.iterations) || a.iterations == 0 || a.iterations > kMaxIterations)
                bad("iterations needs a count 1 .. " + std::to_string(kMaxIterations));
            if (a.reason.empty()) bad("a loop bound needs its reason after '#'");
        } else if (kind == "targets") {
            a.kind = Annotation::Kind::targets;
            while (words >> word) {
                std::uint32_t t = 0;
                if (!parse_where(word, symbols, t, why)) bad(why);
                a.targets.push_back(t);
            }
            if (a.targets.empty()) bad("targets needs at least one address or symbol");
            if (a.reason.empty()) bad("targets need their reason after '#'");
        } else if (kind == "irq_save") {
            a.kind = Annotation::Kind::irq_save;
        } else if (kind == "irq_restore") {
            a.kind = Annotation::Kind::irq_restore;
        } else {
            bad("unknown kind '" + kind + "' (iterations, targets, irq_save, irq_restore)");
        }
        if (a.kind != Annotation::Kind::targets && (words >> word)) bad("unexpected '" + word + "'");
        out.push_back(std::move(a));
    }
    return out;
}

} // namespace rcsim::bound
