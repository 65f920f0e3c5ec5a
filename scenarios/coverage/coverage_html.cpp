// report.html's coverage section (coverage_run.h).
#include "scenarios/coverage/coverage_run.h"

#include "scenarios/report/svg.h"

#include <sstream>

namespace rcsim::coverage {

namespace {

using svg::esc;

std::string ratio(std::uint64_t hit, std::uint64_t found) {
    if (found == 0) return "-";
    std::ostringstream o;
    o << hit << " / " << found << " (" << svg::num(100.0 * static_cast<double>(hit) / static_cast<double>(found), 1)
      << " %)";
    return o.str();
}

bool is_handler(const std::string& name) {
    return name.rfind("isr_", 0) == 0 || (name.size() > 4 && name.compare(name.size() - 4, 4, "_isr") == 0);
}

std::string file_name(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

/// The branches on the lines of the function starting at `first`: up to the next function's first
/// line of the file (to its end for the last).
Summary branches_of(const FileCoverage& f, unsigned first) {
    unsigned end = ~0u;
    for (const auto& [name, fn] : f.functions)
        if (fn.line > first && fn.line < end) end = fn.line;
    Summary s;
    for (const auto& [k, taken] : f.branches)
        if (std::get<0>(k) >= first && std::get<0>(k) < end) {
            ++s.branches_found;
            s.branches_hit += taken.value_or(0) > 0;
        }
    return s;
}

} // namespace

std::string coverage_section_html(const Tracefile& t, const std::string& genhtml_index) {
    std::ostringstream o;
    o << "<section id=\"coverage\"><h2>Firmware coverage</h2>\n<p class=\"note\">Instructions of the comm CPU's ROM "
         "executed in this run (--coverage): lines, functions entered, conditional jumps taken and not taken "
         "(each way is a branch). The tracefile is <code>coverage.info</code> (lcov; docs/tools.md \"Coverage\")";
    if (!genhtml_index.empty()) o << "; the annotated sources: <a href=\"" << esc(genhtml_index) << "\">genhtml's pages</a>";
    o << ".</p>\n<table>\n<tr><th>file</th><th>lines hit</th><th>functions hit</th><th>branches hit</th></tr>\n";
    for (const auto& [sf, f] : t.files) {
        const Summary s = summarize(f);
        o << "<tr><td>" << esc(file_name(sf)) << "</td><td>" << ratio(s.lines_hit, s.lines_found) << "</td><td>"
          << ratio(s.functions_hit, s.functions_found) << "</td><td>" << ratio(s.branches_hit, s.branches_found) << "</td></tr>\n";
    }
    const Summary all = summarize(t);
    o << "<tr><th>all</th><th>" << ratio(all.lines_hit, all.lines_found) << "</th><th>"
      << ratio(all.functions_hit, all.functions_found) << "</th><th>" << ratio(all.branches_hit, all.branches_found)
      << "</th></tr>\n</table>\n";
    std::ostringstream handlers;
    for (const auto& [sf, f] : t.files)
        for (const auto& [name, fn] : f.functions)
            if (is_handler(name)) {
                const Summary b = branches_of(f, fn.line);
                handlers << "<tr><td>" << esc(name) << "</td><td>" << esc(file_name(sf)) << ":" << fn.line << "</td><td>"
                         << fn.count << "</td><td>" << ratio(b.branches_hit, b.branches_found) << "</td></tr>\n";
            }
    if (!handlers.str().empty())
        o << "<h3>Interrupt handlers</h3>\n<p class=\"note\">A handler's branches are those on its lines: from its first "
             "line to the next function's (the three port entries share the lines of their macro, RS232_ENTRY).</p>\n"
             "<table>\n<tr><th>function</th><th>at</th><th>entries</th><th>branches hit</th></tr>\n"
          << handlers.str() << "</table>\n";
    o << "</section>\n";
    return o.str();
}

} // namespace rcsim::coverage
