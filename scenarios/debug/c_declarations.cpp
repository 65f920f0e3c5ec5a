// rcsim — file-scope C declarations (c_declarations.h).
#include "scenarios/debug/c_declarations.h"

#include <cctype>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

namespace rcsim::debug {

std::uint32_t CType::size() const {
    std::uint32_t n = pointer ? 2 : base_size;
    for (auto d : dims) n *= d;
    return n;
}

namespace {

/// The text without comments, string and character literals (each becomes a space), and
/// preprocessor lines (bcc's #asm .. #endasm blocks included); the #defines of integer
/// constants go to `defines`.
std::string strip(const std::string& text, std::map<std::string, std::int64_t>& defines) {
    std::string code;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
            const auto end = text.find("*/", i + 2);
            i = end == std::string::npos ? text.size() : end + 1;
            code += ' ';
        } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '/') {
            while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
        } else if (c == '"' || c == '\'') {
            for (++i; i < text.size() && text[i] != c; ++i)
                if (text[i] == '\\') ++i;
            code += ' ';
        } else {
            code += c;
        }
    }
    std::istringstream in(code);
    std::string out, line;
    bool in_asm = false;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string first, name, value;
        words >> first;
        if (in_asm) {
            in_asm = first != "#endasm";
        } else if (first == "#asm") {
            in_asm = true;
        } else if (!first.empty() && first[0] == '#') {
            // Continuation lines of a macro are skipped with it.
            while (!line.empty() && line.back() == '\\' && std::getline(in, line)) {}
            if (first == "#define" && (words >> name >> value)) {
                std::string rest;
                std::getline(words, rest);
                while (value.size() > 2 && value.front() == '(' && value.back() == ')') value = value.substr(1, value.size() - 2);
                while (!value.empty() && (value.back() == 'u' || value.back() == 'U' || value.back() == 'l' || value.back() == 'L'))
                    value.pop_back();
                if (rest.find_first_not_of(" \t") == std::string::npos && !value.empty() && std::isdigit(static_cast<unsigned char>(value[0]))) {
                    std::size_t used = 0;
                    try {
                        const long long v = std::stoll(value, &used, 0);
                        if (used == value.size()) defines[name] = v;
                    } catch (const std::exception&) {
                    }
                }
            }
        } else {
            out += line;
            out += '\n';
        }
    }
    return out;
}

/// Identifiers, numbers and single punctuation characters.
std::vector<std::string> tokens(const std::string& s) {
    std::vector<std::string> t;
    for (std::size_t i = 0; i < s.size();) {
        const auto c = static_cast<unsigned char>(s[i]);
        if (std::isspace(c)) {
            ++i;
        } else if (std::isalnum(c) || c == '_') {
            std::size_t j = i;
            while (j < s.size() && (std::isalnum(static_cast<unsigned char>(s[j])) || s[j] == '_')) ++j;
            t.push_back(s.substr(i, j - i));
            i = j;
        } else {
            t.push_back(std::string(1, s[i++]));
        }
    }
    return t;
}

std::optional<std::uint32_t> bound(const std::string& word, const std::map<std::string, std::int64_t>& defines) {
    std::int64_t v = -1;
    if (const auto d = defines.find(word); d != defines.end()) {
        v = d->second;
    } else if (!word.empty() && std::isdigit(static_cast<unsigned char>(word[0]))) {
        try {
            std::size_t used = 0;
            v = std::stoll(word, &used, 0);
            if (used != word.size()) return std::nullopt;
        } catch (const std::exception&) {
            return std::nullopt;
        }
    }
    if (v <= 0 || v > 0x100000) return std::nullopt; // no object outgrows the 8086's megabyte
    return std::uint32_t(v);
}

/// The base type of the specifier words, or nullopt when they name none this reader knows.
std::optional<CType> base_type(const std::multiset<std::string>& w) {
    CType t;
    const bool is_unsigned = w.count("unsigned") > 0;
    if (w.count("char")) {
        t.base = is_unsigned ? "unsigned char" : w.count("signed") ? "signed char" : "char";
        t.base_size = 1;
    } else if (w.count("short")) {
        t.base = is_unsigned ? "unsigned short" : "short";
    } else if (w.count("long")) {
        t.base = is_unsigned ? "unsigned long" : "long";
        t.base_size = 4;
    } else if (w.count("int") || w.count("unsigned") || w.count("signed")) {
        t.base = is_unsigned ? "unsigned int" : "int";
    } else {
        return std::nullopt;
    }
    t.is_signed = !is_unsigned; // plain char is signed in bcc, as in most 8086 compilers
    return t;
}

/// One statement at file scope ("static unsigned char a[3], *b = 0"), without its ';'.
void declaration(const std::string& statement, const std::map<std::string, std::int64_t>& defines,
                 std::map<std::string, CType>& out) {
    static const std::set<std::string> kSpecifiers = {"static", "extern", "const", "volatile", "register", "auto",
                                                      "unsigned", "signed", "char", "short", "int", "long"};
    const auto t = tokens(statement);
    std::size_t i = 0;
    std::multiset<std::string> spec;
    while (i < t.size() && kSpecifiers.count(t[i])) spec.insert(t[i++]);
    const auto base = base_type(spec);
    if (!base) return; // typedef, struct, a type name of its own: not read
    while (i < t.size()) {
        // One declarator: '*'s, the name, bounds; then '=' and its initialiser up to a ',' at
        // depth 0.
        CType type = *base;
        while (i < t.size() && (t[i] == "*" || t[i] == "const" || t[i] == "volatile")) type.pointer |= t[i++] == "*";
        if (i >= t.size() || !(std::isalpha(static_cast<unsigned char>(t[i][0])) || t[i][0] == '_')) return;
        const std::string name = t[i++];
        bool ok = true;
        while (i + 2 < t.size() && t[i] == "[" && t[i + 2] == "]") {
            const auto n = bound(t[i + 1], defines);
            if (!n) ok = false;
            else type.dims.push_back(*n);
            i += 3;
        }
        if (i < t.size() && t[i] != "," && t[i] != "=") return; // a function, [] without a bound, ...
        int depth = 0;
        while (i < t.size() && !(depth == 0 && t[i] == ",")) {
            if (t[i] == "(" || t[i] == "{" || t[i] == "[") ++depth;
            if (t[i] == ")" || t[i] == "}" || t[i] == "]") --depth;
            ++i;
        }
        ++i; // the ','
        if (ok) out[name] = type;
    }
}

} // namespace

void parse_c_declarations(const std::string& text, std::map<std::string, std::int64_t>& defines,
                          std::map<std::string, CType>& out) {
    const std::string code = strip(text, defines);
    std::string statement;
    int depth = 0;
    bool body = false; // inside a function body or a struct: not file scope
    for (const char c : code) {
        if (c == '{') {
            // At depth 0 a '{' opens an initialiser (after '=') or a body (anything else).
            if (depth == 0) body = statement.find('=') == std::string::npos;
            ++depth;
        } else if (c == '}') {
            if (depth > 0 && --depth == 0 && body) {
                body = false;
                statement.clear();
                continue;
            }
        } else if (c == ';' && depth == 0) {
            declaration(statement, defines, out);
            statement.clear();
            continue;
        }
        if (!body) statement += c;
    }
}

std::map<std::string, CType> read_c_declarations(const std::vector<std::string>& files) {
    std::map<std::string, std::int64_t> defines;
    std::map<std::string, CType> out;
    for (const auto& f : files) {
        std::ifstream in(f);
        if (!in) continue;
        std::ostringstream text;
        text << in.rdbuf();
        parse_c_declarations(text.str(), defines, out);
    }
    return out;
}

} // namespace rcsim::debug
