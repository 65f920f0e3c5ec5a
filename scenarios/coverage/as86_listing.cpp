#include "scenarios/coverage/as86_listing.h"

#include "models/plumbing/config_error.h"

#include <cctype>
#include <fstream>

namespace rcsim::coverage {

namespace {

constexpr std::size_t kSourceColumn = 48; // where as86 puts the source text of a row

bool all_of(const std::string& s, std::size_t from, std::size_t n, int (*pred)(int)) {
    if (s.size() < from + n) return false;
    for (std::size_t i = from; i < from + n; ++i)
        if (!pred(static_cast<unsigned char>(s[i]))) return false;
    return true;
}

std::string trim(const std::string& s) {
    std::size_t a = 0, b = s.size();
    while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
    while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
    return s.substr(a, b - a);
}

/// The statement without its comment, whitespace runs made one space: the key an expansion row is
/// matched to its body line by.
std::string statement(const std::string& text) {
    std::string out;
    bool space = false;
    for (char c : text) {
        if (c == '!' || c == ';') break;
        if (std::isspace(static_cast<unsigned char>(c))) {
            space = !out.empty();
            continue;
        }
        if (space) out += ' ';
        space = false;
        out += c;
    }
    return out;
}

std::string upper(std::string s) {
    for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return s;
}

/// The first word of a statement after a leading "label:".
std::string first_word(const std::string& st) {
    std::string s = st;
    const std::size_t colon = s.find(':');
    if (colon != std::string::npos && s.find(' ') > colon) s = trim(s.substr(colon + 1));
    return s.substr(0, s.find_first_of(" (\t"));
}

struct Macro {
    std::vector<std::pair<unsigned, std::string>> body; // line, text
};

struct Expansion {
    const Macro* macro = nullptr;
    unsigned call_line = 0;
    std::vector<std::string> args;
    std::size_t cursor = 0;       // the next body line to match
    bool call_line_used = false;  // an instruction already counts the call's line
};

std::string substitute(const std::string& text, const std::vector<std::string>& args) {
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] == '?' && i + 1 < text.size() && text[i + 1] >= '1' && text[i + 1] <= '9') {
            const std::size_t k = static_cast<std::size_t>(text[i + 1] - '1');
            out += k < args.size() ? args[k] : std::string();
            ++i;
        } else {
            out += text[i];
        }
    }
    return out;
}

/// "NAME(a,b,c)": the arguments, trimmed.
std::vector<std::string> call_args(const std::string& st) {
    std::vector<std::string> args;
    const std::size_t open = st.find('('), close = st.rfind(')');
    if (open == std::string::npos || close == std::string::npos || close < open) return args;
    std::string cur;
    for (std::size_t i = open + 1; i < close; ++i) {
        if (st[i] == ',') {
            args.push_back(trim(cur));
            cur.clear();
        } else {
            cur += st[i];
        }
    }
    args.push_back(trim(cur));
    return args;
}

/// The body line an expansion row was written on, or 0.
unsigned body_line(Expansion& e, const std::string& row) {
    const std::string key = statement(row);
    for (std::size_t i = e.cursor; i < e.macro->body.size(); ++i)
        if (statement(substitute(e.macro->body[i].second, e.args)) == key) {
            e.cursor = i + 1;
            return e.macro->body[i].first;
        }
    return 0;
}

} // namespace

As86Listing read_as86_listing(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) throw ConfigError(path.string() + ": cannot read the as86 listing");
    As86Listing out;
    std::map<std::string, Macro> macros;
    Macro* defining = nullptr;
    Expansion expansion;
    bool text_segment = true; // as86 starts in .text
    unsigned numbered = 0;
    std::string row;
    int n = 0;
    while (std::getline(in, row)) {
        ++n;
        const bool is_numbered = all_of(row, 0, 5, isdigit) && (row.size() == 5 || row[5] == ' ');
        const bool in_expansion = row.size() > 2 && row[0] == ' ' && row[1] == '+';
        if (!is_numbered && !in_expansion) continue; // headers, the symbol table at the end
        const std::string text = row.size() > kSourceColumn ? row.substr(kSourceColumn) : std::string();
        const std::string st = statement(text);
        const std::string word = upper(first_word(st));
        unsigned line = 0;
        if (is_numbered) {
            line = static_cast<unsigned>(std::stoul(row.substr(0, 5)));
            // The summary after the symbol table ("00000 errors") ends the rows.
            if (numbered > 0 && row.find(" errors") == 5) break;
            if (line != numbered + 1) throw ConfigError(path.string(), n, "not an as86 listing (line numbers out of order)");
            numbered = line;
            expansion.macro = nullptr;
            if (defining) {
                if (word == "MEND") defining = nullptr;
                else defining->body.emplace_back(line, text);
                continue;
            }
            if (word == "MACRO") {
                const std::string rest = trim(st.substr(5));
                defining = &macros[upper(rest.substr(0, rest.find_first_of(" (")))];
                continue;
            }
            const auto m = macros.find(word);
            if (m != macros.end()) {
                expansion = Expansion{&m->second, line, call_args(st), 0, false};
                continue;
            }
        }
        if (word == ".TEXT") text_segment = true;
        if (word == ".DATA" || word == ".BSS") text_segment = false;
        if (!text_segment) continue;
        // A label row: "... 000003F1>   name:".
        if (!all_of(row, 6, 4, isxdigit) && row.size() > 37 && row[36] == '>' && all_of(row, 28, 8, isxdigit)) {
            const std::size_t colon = st.find(':');
            if (colon != std::string::npos) out.labels[st.substr(0, colon)] = static_cast<std::uint32_t>(std::stoul(row.substr(28, 8), nullptr, 16));
            continue;
        }
        if (!all_of(row, 6, 4, isxdigit) || word.empty() || word[0] == '.') continue;
        bool bytes = false;
        for (std::size_t i = 10; i < kSourceColumn && i < row.size(); ++i) bytes |= std::isxdigit(static_cast<unsigned char>(row[i])) != 0;
        if (!bytes) continue;
        ListedInstruction ins;
        ins.offset = static_cast<std::uint32_t>(std::stoul(row.substr(6, 4), nullptr, 16));
        ins.line = line;
        if (in_expansion) {
            if (!expansion.macro) continue; // an expansion row with no call seen: not ours to place
            ins.line = body_line(expansion, text);
            if (ins.line == 0) {
                ins.line = expansion.call_line;
                ins.leads_line = !expansion.call_line_used;
                expansion.call_line_used = true;
            }
        }
        out.instructions.push_back(ins);
    }
    if (numbered == 0) throw ConfigError(path.string() + ": not an as86 listing (no numbered rows)");
    return out;
}

} // namespace rcsim::coverage
