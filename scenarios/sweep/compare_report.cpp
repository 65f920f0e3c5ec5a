// rcsim — the comparison as JUnit XML (for CI) and as one HTML page (for people). See compare.h.
#include "scenarios/sweep/compare.h"
#include "scenarios/sweep/summary_html.h"
#include "scenarios/report/svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

namespace rcsim::sweep {

using json = nlohmann::json;
using svg::esc;

namespace {

std::string text_of(const json& v, bool present) {
    if (!present) return "(absent)";
    if (v.is_number_float()) return html::cell(v.get<double>());
    return v.dump();
}

std::string pass_text(const std::optional<bool>& p) { return p ? (*p ? "PASS" : "FAIL") : "(absent)"; }

const char* run_problem(const RunDiff& r) {
    switch (r.state) {
    case RunDiff::State::missing: return "the run is in the baseline but not in the current set";
    case RunDiff::State::extra: return "the run is not in the baseline";
    case RunDiff::State::no_report: return "the run has no report.json (it did not finish)";
    default: return "";
    }
}

std::string percent(const std::optional<double>& v) {
    if (!v) return "";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%+.2f%%", *v * 100);
    return buf;
}

/// One <testcase>; `failure` / `skipped` empty when it passed.
void testcase(std::ostringstream& o, const std::string& suite, const std::string& name, const std::string& failure,
              const std::string& skipped) {
    o << "    <testcase classname=\"" << esc(suite) << "\" name=\"" << esc(name) << "\"";
    if (failure.empty() && skipped.empty()) {
        o << "/>\n";
        return;
    }
    o << ">";
    if (!failure.empty()) o << "<failure type=\"regression\" message=\"" << esc(failure) << "\"/>";
    else o << "<skipped message=\"" << esc(skipped) << "\"/>";
    o << "</testcase>\n";
}

/// A run's figures by family (figure_family), in the order the report has them.
std::vector<std::pair<std::string, std::vector<const FigureDiff*>>> families_of(const RunDiff& r) {
    std::vector<std::pair<std::string, std::vector<const FigureDiff*>>> out;
    std::map<std::string, std::size_t> at;
    for (const FigureDiff& f : r.figures) {
        const std::string family = figure_family(f.key);
        const auto it = at.emplace(family, out.size()).first;
        if (it->second == out.size()) out.push_back({family, {}});
        out[it->second].second.push_back(&f);
    }
    return out;
}

/// A family's failure message: how many of its figures regressed, and the first few of them with
/// their change and the rule that judged it. Empty: none regressed.
std::string family_failure(const std::vector<const FigureDiff*>& figures) {
    constexpr std::size_t kListed = 5;
    std::vector<const FigureDiff*> regressed;
    for (const FigureDiff* f : figures)
        if (f->change == Change::regression) regressed.push_back(f);
    if (regressed.empty()) return "";
    std::string m = std::to_string(regressed.size()) + (regressed.size() == 1 ? " figure regressed: " : " figures regressed: ");
    for (std::size_t i = 0; i < regressed.size() && i < kListed; ++i) {
        const FigureDiff& f = *regressed[i];
        m += (i ? "; " : "") + f.key + " " + text_of(f.baseline, f.has_baseline) + " -> " +
             text_of(f.current, f.has_current) + (f.rel ? " (" + percent(f.rel) + ")" : "") + " [" + f.rule + "]";
    }
    if (regressed.size() > kListed) m += "; and " + std::to_string(regressed.size() - kListed) + " more";
    return m;
}

/// Skipped when every figure of the family is ignored by a rule.
std::string family_skipped(const std::vector<const FigureDiff*>& figures) {
    for (const FigureDiff* f : figures)
        if (f->change != Change::ignored) return "";
    return "ignored: " + figures.front()->rule;
}

} // namespace

std::string junit_xml(const Comparison& c) {
    std::ostringstream suites;
    std::size_t tests = 0, failures = 0, skipped = 0;
    for (const RunDiff& r : c.runs) {
        std::ostringstream cases;
        std::size_t t = 0, f = 0, s = 0;
        auto add = [&](const std::string& name, const std::string& failure, const std::string& skip) {
            testcase(cases, r.id, name, failure, skip);
            ++t;
            f += !failure.empty();
            s += failure.empty() && !skip.empty();
        };
        if (r.state != RunDiff::State::matched) {
            add("run", r.regression ? run_problem(r) : "", r.regression ? "" : std::string(run_problem(r)) + " (--allow-missing)");
        } else {
            add("run", "", "");
        }
        for (const CheckDiff& k : r.checks)
            add("check " + k.name,
                k.change == Change::regression ? pass_text(k.baseline) + " -> " + pass_text(k.current) : "", "");
        for (const auto& [family, figures] : families_of(r))
            add("figures " + family, family_failure(figures), family_skipped(figures));
        suites << "  <testsuite name=\"" << esc(r.id) << "\" tests=\"" << t << "\" failures=\"" << f
               << "\" errors=\"0\" skipped=\"" << s << "\">\n"
               << cases.str() << "  </testsuite>\n";
        tests += t, failures += f, skipped += s;
    }
    std::ostringstream o;
    o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"rcsim compare\" tests=\"" << tests
      << "\" failures=\"" << failures << "\" errors=\"0\" skipped=\"" << skipped << "\">\n"
      << suites.str() << "</testsuites>\n";
    return o.str();
}

namespace {

const char* row_class(Change v) {
    switch (v) {
    case Change::regression: return " class=\"reg\"";
    case Change::improvement: return " class=\"imp\"";
    case Change::within: return " class=\"within\"";
    case Change::ignored: return " class=\"ign\"";
    default: return "";
    }
}

/// The delta's colour: which way the figure is better (FigureDiff::better), not the delta's sign; a
/// figure of unknown direction stays neutral.
std::string delta_class(const FigureDiff& f) {
    if (!f.delta || *f.delta == 0) return "";
    if (f.better == Tolerance::Better::none) return " title=\"direction unknown\"";
    const bool lower = f.better == Tolerance::Better::lower;
    const bool worse = lower ? *f.delta > 0 : *f.delta < 0;
    return std::string(worse ? " class=\"worse\"" : " class=\"better\"") +
           (lower ? " title=\"lower is better\"" : " title=\"higher is better\"");
}

void figure_row(std::ostringstream& o, const std::string& run, const FigureDiff& f) {
    const std::string sign = delta_class(f);
    o << "<tr" << row_class(f.change) << ">";
    if (!run.empty()) o << "<td class=\"k\">" << esc(run) << "</td>";
    o << "<td class=\"k\">" << esc(f.key) << "</td><td>" << esc(text_of(f.baseline, f.has_baseline)) << "</td><td>"
      << esc(text_of(f.current, f.has_current)) << "</td><td" << sign << ">" << (f.delta ? html::cell(*f.delta) : "")
      << "</td><td" << sign << ">" << esc(percent(f.rel)) << "</td><td class=\"k\">" << change_name(f.change)
      << "</td></tr>\n";
}

void check_row(std::ostringstream& o, const std::string& run, const CheckDiff& k) {
    o << "<tr" << row_class(k.change) << ">";
    if (!run.empty()) o << "<td class=\"k\">" << esc(run) << "</td>";
    o << "<td class=\"k\">check " << esc(k.name) << "</td><td>" << pass_text(k.baseline) << "</td><td>"
      << pass_text(k.current) << "</td><td></td><td></td><td class=\"k\">" << change_name(k.change) << "</td></tr>\n";
}

const char* kHead = "<th class=\"k\">figure</th><th>baseline</th><th>current</th><th>delta</th><th>rel</th>"
                    "<th class=\"k\">verdict</th></tr>\n";

/// Every change of kind `v`, ranked as the console ranks them (Rank): runs, checks, then the
/// figures above Rank::other in a table; the other figures in one collapsed table per family.
void change_table(std::ostringstream& o, const Comparison& c, Change v, const char* title) {
    std::map<Rank, std::ostringstream> ranked;
    std::map<std::string, std::pair<std::size_t, std::ostringstream>> families; // rows per family
    std::size_t n = 0;
    for (const RunDiff& r : c.runs) {
        if (v == Change::regression && r.state != RunDiff::State::matched && r.regression) {
            ranked[Rank::run] << "<tr class=\"reg\"><td class=\"k\">" << esc(r.id) << "</td><td class=\"k\" colspan=\"6\">"
                              << run_problem(r) << "</td></tr>\n";
            ++n;
        }
        for (const CheckDiff& k : r.checks)
            if (k.change == v) check_row(ranked[Rank::check], r.id, k), ++n;
        for (const FigureDiff& f : r.figures) {
            if (f.change != v) continue;
            ++n;
            const Rank rank = rank_of(f.key);
            if (rank != Rank::other) {
                figure_row(ranked[rank], r.id, f);
                continue;
            }
            auto& family = families[figure_family(f.key)];
            ++family.first;
            figure_row(family.second, r.id, f);
        }
    }
    o << "<h2>" << title << " (" << n << ")</h2>\n";
    if (!n) return;
    if (!ranked.empty()) {
        o << "<table>\n<tr><th class=\"k\">run</th>" << kHead;
        for (auto& [rank, rows] : ranked) o << rows.str();
        o << "</table>\n";
    }
    for (auto& [name, family] : families)
        o << "<details><summary>" << esc(name) << ": " << family.first << (family.first == 1 ? " figure" : " figures")
          << "</summary>\n<table>\n<tr><th class=\"k\">run</th>" << kHead << family.second.str() << "</table>\n</details>\n";
}

/// The figure paths that changed most: the largest |relative change| in any run; changes from 0
/// (no relative change) after every one that has one.
std::vector<std::string> worst_changed(const Comparison& c, std::size_t n) {
    std::map<std::string, std::pair<int, double>> worst; // (has a relative change, its size)
    for (const RunDiff& r : c.runs)
        for (const FigureDiff& f : r.figures)
            if (f.delta && (f.change == Change::regression || f.change == Change::improvement ||
                            f.change == Change::within)) {
                const std::pair<int, double> w{f.rel ? 1 : 0, f.rel ? std::fabs(*f.rel) : std::fabs(*f.delta)};
                worst[f.key] = std::max(worst[f.key], w);
            }
    std::vector<std::pair<std::string, std::pair<int, double>>> v(worst.begin(), worst.end());
    std::stable_sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
    std::vector<std::string> out;
    for (std::size_t i = 0; i < v.size() && i < n; ++i) out.push_back(v[i].first);
    return out;
}

void histograms(std::ostringstream& o, const Comparison& c) {
    const auto keys = worst_changed(c, 6);
    if (keys.empty()) return;
    o << "<h2>Worst-changed figures</h2>\n<p>Each figure's values over all matched runs, baseline and current "
         "overlaid.</p>\n<div class=\"charts\">\n";
    for (const std::string& key : keys) {
        std::vector<double> b, cur;
        for (const RunDiff& r : c.runs)
            for (const FigureDiff& f : r.figures)
                if (f.key == key) {
                    if (f.has_baseline && f.baseline.is_number()) b.push_back(f.baseline.get<double>());
                    if (f.has_current && f.current.is_number()) cur.push_back(f.current.get<double>());
                }
        o << html::overlaid_histogram(key, b, cur) << "\n";
    }
    o << "</div>\n";
}

} // namespace

std::string compare_html(const Comparison& c) {
    std::ostringstream o;
    const bool bad = c.regression();
    o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>rcsim compare: "
      << (bad ? "REGRESSION" : "no regression") << "</title>\n<style>" << html::kCss
      << "</style>\n</head>\n<body>\n<h1>rcsim compare</h1>\n";
    // The console's report first: the counts and the ranked first screen.
    std::ostringstream console;
    print_comparison(c, console);
    o << "<div class=\"banner " << (bad ? "fail" : "pass") << "\">" << (bad ? "REGRESSION" : "no regression")
      << "</div>\n<pre>" << esc(console.str()) << "</pre>\n";
    change_table(o, c, Change::regression, "Regressions");
    change_table(o, c, Change::improvement, "Improvements");
    histograms(o, c);
    o << "<h2>Runs side by side</h2>\n";
    for (const RunDiff& r : c.runs) {
        std::size_t reg = 0, imp = 0, changed = 0;
        for (const auto& f : r.figures) {
            reg += f.change == Change::regression, imp += f.change == Change::improvement;
            changed += f.change != Change::same && f.change != Change::ignored;
        }
        for (const auto& k : r.checks) reg += k.change == Change::regression, imp += k.change == Change::improvement;
        o << "<details" << (r.regression ? " open" : "") << "><summary>" << esc(r.id) << ": ";
        if (r.state != RunDiff::State::matched) o << run_problem(r);
        else o << reg << " regressions, " << imp << " improvements, " << changed << " figures changed of " << r.figures.size();
        o << "</summary>\n";
        if (r.state == RunDiff::State::matched) {
            o << "<table>\n<tr>" << kHead;
            for (const CheckDiff& k : r.checks) check_row(o, "", k);
            for (const FigureDiff& f : r.figures) figure_row(o, "", f);
            o << "</table>\n";
        }
        o << "</details>\n";
    }
    o << "</body>\n</html>\n";
    return o.str();
}

} // namespace rcsim::sweep
