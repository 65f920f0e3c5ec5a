#include "scenarios/coverage/tracefile.h"

#include "models/plumbing/config_error.h"
#include "models/plumbing/output_file.h"

#include <charconv>
#include <fstream>
#include <ostream>
#include <vector>

namespace rcsim::coverage {

namespace {

/// The comma-separated fields of a record's value; an error when there are not `n`.
std::vector<std::string> fields(const std::string& value, std::size_t n, const std::string& file, int line,
                                const std::string& key) {
    std::vector<std::string> out;
    std::size_t start = 0;
    // A function's name may hold commas (C++ signatures): the last field takes the rest.
    while (out.size() + 1 < n) {
        const std::size_t comma = value.find(',', start);
        if (comma == std::string::npos) break;
        out.push_back(value.substr(start, comma - start));
        start = comma + 1;
    }
    out.push_back(value.substr(start));
    if (out.size() != n)
        throw ConfigError(file, line, key + ":" + value + ": expected " + std::to_string(n) + " comma-separated fields");
    return out;
}

std::uint64_t number(const std::string& text, const std::string& file, int line, const std::string& what) {
    std::uint64_t v = 0;
    const char* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, v);
    if (text.empty() || r.ec != std::errc() || r.ptr != end)
        throw ConfigError(file, line, what + " '" + text + "' is not a count 0 .. 18446744073709551615");
    return v;
}

unsigned line_number(const std::string& text, const std::string& file, int line, const std::string& what) {
    const std::uint64_t v = number(text, file, line, what);
    if (v == 0 || v > 0xFFFFFFFFu) throw ConfigError(file, line, what + " '" + text + "' is not a line number 1 .. 4294967295");
    return static_cast<unsigned>(v);
}

std::uint64_t add(std::uint64_t a, std::uint64_t b) { return a + b < a ? UINT64_MAX : a + b; } // saturating

} // namespace

Tracefile read_tracefile(const std::filesystem::path& path) {
    const std::string file = path.string();
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ConfigError(file + ": cannot read the tracefile");
    Tracefile t;
    FileCoverage* cur = nullptr;
    std::string text;
    int n = 0;
    while (std::getline(in, text)) {
        ++n;
        if (!text.empty() && text.back() == '\r') text.pop_back();
        if (text.empty()) continue;
        if (text == "end_of_record") {
            if (!cur) throw ConfigError(file, n, "end_of_record without SF");
            cur = nullptr;
            continue;
        }
        const std::size_t colon = text.find(':');
        if (colon == std::string::npos) throw ConfigError(file, n, "'" + text.substr(0, 60) + "' is not an lcov record (KEY:VALUE)");
        const std::string key = text.substr(0, colon), value = text.substr(colon + 1);
        if (key == "TN" || key == "VER") continue;
        if (key == "SF") {
            if (cur) throw ConfigError(file, n, "SF before the end_of_record of the previous file");
            if (value.empty()) throw ConfigError(file, n, "SF: an empty path");
            cur = &t.files[value];
            continue;
        }
        if (!cur) throw ConfigError(file, n, key + ": a record outside SF ... end_of_record");
        if (key == "DA") {
            // DA:LINE,COUNT[,CHECKSUM]
            std::string v = value;
            const std::size_t c2 = v.find(',', v.find(',') + 1);
            if (v.find(',') != std::string::npos && c2 != std::string::npos) v.resize(c2);
            const auto f = fields(v, 2, file, n, key);
            std::uint64_t& c = cur->lines[line_number(f[0], file, n, "DA line")];
            c = add(c, number(f[1], file, n, "DA count"));
        } else if (key == "FN") {
            const auto f = fields(value, 2, file, n, key);
            cur->functions[f[1]].line = line_number(f[0], file, n, "FN line");
        } else if (key == "FNDA") {
            const auto f = fields(value, 2, file, n, key);
            auto& fn = cur->functions[f[1]];
            fn.count = add(fn.count, number(f[0], file, n, "FNDA count"));
        } else if (key == "BRDA") {
            const auto f = fields(value, 4, file, n, key);
            const FileCoverage::BranchKey k{line_number(f[0], file, n, "BRDA line"),
                                            static_cast<unsigned>(number(f[1], file, n, "BRDA block")),
                                            static_cast<unsigned>(number(f[2], file, n, "BRDA branch"))};
            auto& b = cur->branches[k];
            if (f[3] != "-") b = add(b.value_or(0), number(f[3], file, n, "BRDA taken"));
        } else if (key == "FNF" || key == "FNH" || key == "BRF" || key == "BRH" || key == "LF" || key == "LH") {
            number(value, file, n, key);
        } else {
            throw ConfigError(file, n, "unknown lcov record '" + key + "'");
        }
    }
    if (cur) throw ConfigError(file, n, "the file ends inside a record (no end_of_record)");
    for (const auto& [sf, f] : t.files)
        for (const auto& [name, fn] : f.functions)
            if (fn.line == 0) throw ConfigError(file + ": FNDA for '" + name + "' of " + sf + " without its FN record");
    return t;
}

void merge_into(Tracefile& into, const Tracefile& more) {
    for (const auto& [sf, f] : more.files) {
        FileCoverage& to = into.files[sf];
        for (const auto& [line, count] : f.lines) to.lines[line] = add(to.lines[line], count);
        for (const auto& [name, fn] : f.functions) {
            auto [it, fresh] = to.functions.try_emplace(name, fn);
            if (!fresh) it->second.count = add(it->second.count, fn.count);
        }
        for (const auto& [k, taken] : f.branches) {
            auto& b = to.branches[k];
            if (taken) b = add(b.value_or(0), *taken);
        }
    }
}

Tracefile merge_tracefiles(const std::vector<std::filesystem::path>& files) {
    Tracefile all;
    for (const auto& f : files) merge_into(all, read_tracefile(f));
    return all;
}

Summary summarize(const FileCoverage& f) {
    Summary s;
    s.lines_found = f.lines.size();
    for (const auto& [line, count] : f.lines) s.lines_hit += count > 0;
    s.functions_found = f.functions.size();
    for (const auto& [name, fn] : f.functions) s.functions_hit += fn.count > 0;
    s.branches_found = f.branches.size();
    for (const auto& [k, taken] : f.branches) s.branches_hit += taken.value_or(0) > 0;
    return s;
}

Summary summarize(const Tracefile& t) {
    Summary s;
    for (const auto& [sf, f] : t.files) {
        const Summary x = summarize(f);
        s.lines_found += x.lines_found, s.lines_hit += x.lines_hit;
        s.functions_found += x.functions_found, s.functions_hit += x.functions_hit;
        s.branches_found += x.branches_found, s.branches_hit += x.branches_hit;
    }
    return s;
}

void write_tracefile(std::ostream& os, const Tracefile& t) {
    for (const auto& [sf, f] : t.files) {
        const Summary s = summarize(f);
        os << "TN:\nSF:" << sf << '\n';
        for (const auto& [name, fn] : f.functions) os << "FN:" << fn.line << ',' << name << '\n';
        for (const auto& [name, fn] : f.functions) os << "FNDA:" << fn.count << ',' << name << '\n';
        os << "FNF:" << s.functions_found << "\nFNH:" << s.functions_hit << '\n';
        for (const auto& [k, taken] : f.branches) {
            os << "BRDA:" << std::get<0>(k) << ',' << std::get<1>(k) << ',' << std::get<2>(k) << ',';
            if (taken) os << *taken;
            else os << '-';
            os << '\n';
        }
        os << "BRF:" << s.branches_found << "\nBRH:" << s.branches_hit << '\n';
        for (const auto& [line, count] : f.lines) os << "DA:" << line << ',' << count << '\n';
        os << "LF:" << s.lines_found << "\nLH:" << s.lines_hit << "\nend_of_record\n";
    }
}

void write_tracefile_to(const std::filesystem::path& file, const Tracefile& t) {
    OutputFile out(file, "the coverage tracefile");
    write_tracefile(out.stream(), t);
    out.close();
}

} // namespace rcsim::coverage
