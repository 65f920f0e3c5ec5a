#include "scenarios/sweep/compare.h"

#include "models/plumbing/config_error.h"
#include "scenarios/config/yaml_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <set>

namespace rcsim::sweep {

namespace fs = std::filesystem;
using json = nlohmann::json;

bool glob_match(const std::string& p, const std::string& t) {
    // Iterative wildcard match with backtracking to the last '*'.
    std::size_t i = 0, j = 0, star = std::string::npos, mark = 0;
    while (j < t.size()) {
        if (i < p.size() && (p[i] == '?' || p[i] == t[j])) {
            ++i, ++j;
        } else if (i < p.size() && p[i] == '*') {
            star = i++;
            mark = j;
        } else if (star != std::string::npos) {
            i = star + 1;
            j = ++mark;
        } else {
            return false;
        }
    }
    while (i < p.size() && p[i] == '*') ++i;
    return i == p.size();
}

std::vector<Tolerance> default_tolerances() {
    std::vector<Tolerance> out;
    for (const char* host : {"wall_time_s", "rtf", "realtime.*"}) {
        Tolerance t;
        t.figure = host;
        t.ignore = true;
        t.origin = "default (host-dependent)";
        out.push_back(t);
    }
    Tolerance exact;
    exact.origin = "default (exact)";
    out.push_back(exact);
    return out;
}

std::vector<Tolerance> load_tolerances(const std::string& path) {
    std::vector<Tolerance> out;
    const YAML::Node root = load_yaml_file(path);
    YamlMap top(root, path, "");
    for (YamlMap& m : top.maps("tolerances")) {
        Tolerance t;
        t.origin = path + ":" + std::to_string(YamlMap::line_of(m.child("figure")));
        t.figure = m.require<std::string>("figure");
        t.run = m.get<std::string>("run", "*");
        t.abs = m.number("abs", 0, 0, 1e300);
        t.rel = m.number("rel", 0, 0, 1e300);
        const std::string better = m.choice("better", "none", {"none", "lower", "higher"});
        t.better = better == "lower" ? Tolerance::Better::lower
                   : better == "higher" ? Tolerance::Better::higher : Tolerance::Better::none;
        t.ignore = m.get<bool>("ignore", false);
        m.finish();
        out.push_back(t);
    }
    top.finish();
    for (const Tolerance& t : default_tolerances()) out.push_back(t);
    return out;
}

Tolerance::Better figure_direction(const std::string& key) {
    using B = Tolerance::Better;
    // First match wins; the same directions as scenarios/regress/tolerances.yaml.
    static const std::pair<const char*, B> kKnown[] = {
        {"table3.budget_us", B::none},         {"table3.paper_*", B::none},
        {"table3.margin_us", B::higher},       {"table3.worst_margin_us", B::higher}, // table3_*margin_us >=
        {"table3.*_us", B::lower},             {"interrupts.*_us.count", B::none},
        {"interrupts.*_us.*", B::lower},       {"ports[*].char_latency_us.count", B::none},
        {"ports[*].char_latency_us.*", B::lower}, // port<n>_char_latency_max_us <=
        {"ports[*].frames_delivered", B::higher}, // frames_delivered >=
        {"ports[*].frames_failed", B::lower},  {"ports[*].overruns", B::lower},
        {"bus_errors", B::lower},
    };
    for (const auto& [pattern, better] : kKnown)
        if (glob_match(pattern, key)) return better;
    return B::none;
}

std::string figure_family(const std::string& key) {
    const std::size_t first = key.find_first_of(".[");
    if (first == std::string::npos) return key;
    const std::string head = key.substr(0, first);
    if (head == "interrupts") return key.substr(0, key.find('.', first + 1)); // interrupts.<source>
    if (key[first] == '[') return key.substr(0, key.find(']', first) + 1);    // ports[<n>]
    return head;
}

Rank rank_of(const std::string& key) {
    if (key.rfind("table3.", 0) == 0) return Rank::budget;
    if (key.rfind("interrupts.", 0) == 0)
        for (const char* stat : {".max", ".p99", ".mean"})
            for (const char* what : {".latency_us", ".service_us"})
                if (glob_match(std::string("interrupts.*") + what + stat, key)) return Rank::latency;
    for (const char* delivery : {"ports[*].frames_*", "ports[*].overruns", "ports[*].commands.*", "ports[*].responses.*",
                                 "ports[*].main_cpu_frames_*", "ports[*].responses_*"})
        if (glob_match(delivery, key)) return Rank::delivery;
    return Rank::other;
}

const char* change_name(Change v) {
    switch (v) {
    case Change::same: return "same";
    case Change::within: return "changed (within tolerance)";
    case Change::ignored: return "ignored";
    case Change::improvement: return "improvement";
    case Change::regression: return "regression";
    case Change::added: return "new";
    }
    return "?";
}

bool Comparison::regression() const {
    return std::any_of(runs.begin(), runs.end(), [](const RunDiff& r) { return r.regression; });
}

std::map<std::string, RunRecord> load_run_set(const std::string& path) {
    std::error_code ec;
    std::map<std::string, RunRecord> out;
    if (fs::is_regular_file(path, ec)) {
        RunRecord r;
        r.dir = fs::path(path).parent_path();
        r.report = read_json_file(path);
        if (!r.report->is_object()) throw ConfigError(path, 1, "not an rcsim report.json (not a JSON object)");
        const json& rep = *r.report;
        r.id = rep.contains("scenario") && rep["scenario"].is_string() ? rep["scenario"].get<std::string>()
                                                                       : fs::path(path).stem().string();
        r.meta = json::object();
        out.emplace(r.id, std::move(r));
        return out;
    }
    if (!fs::exists(path, ec)) throw ConfigError(path, 0, "no such report.json or run directory");
    for (RunRecord& r : collect_runs({path})) {
        if (r.report && !r.report->is_object())
            throw ConfigError((r.dir / "report.json").string(), 1, "not an rcsim report.json (not a JSON object)");
        out.emplace(r.id, std::move(r));
    }
    if (out.empty()) throw ConfigError(path, 0, "holds no run (no report.json, no run directories)");
    return out;
}

namespace {

const Tolerance& rule_for(const std::vector<Tolerance>& rules, const std::string& run, const std::string& key) {
    for (const Tolerance& t : rules)
        if (glob_match(t.run, run) && glob_match(t.figure, key)) return t;
    static const Tolerance exact{};
    return exact;
}

void judge(FigureDiff& f, const Tolerance& t) {
    f.rule = t.origin;
    f.better = t.better != Tolerance::Better::none ? t.better : figure_direction(f.key);
    if (t.ignore) f.change = Change::ignored;
    else if (!f.has_current) f.change = Change::regression; // a figure the report no longer has
    else if (!f.has_baseline) f.change = Change::added;
    if (t.ignore || !f.has_current || !f.has_baseline) return;
    if (f.baseline == f.current) return; // same (numbers compare by value: 5 == 5.0)
    if (!f.baseline.is_number() || !f.current.is_number() || f.baseline.is_boolean() || f.current.is_boolean()) {
        f.change = Change::regression; // null <-> number (measured or not), true <-> false
        return;
    }
    const double b = f.baseline.get<double>(), c = f.current.get<double>(), d = c - b;
    f.delta = d;
    if (b != 0) f.rel = d / std::fabs(b);
    if (std::fabs(d) <= t.abs || (f.rel && std::fabs(*f.rel) <= t.rel)) {
        f.change = Change::within;
        return;
    }
    const bool good = (t.better == Tolerance::Better::lower && d < 0) || (t.better == Tolerance::Better::higher && d > 0);
    f.change = good ? Change::improvement : Change::regression;
}

void compare_figures(const json& base, const json& cur, const std::string& id, const std::vector<Tolerance>& rules,
                     RunDiff& r) {
    const Figures bf = flatten_figures(base), cf = flatten_figures(cur);
    std::map<std::string, const json*> cm;
    for (const auto& [k, v] : cf) cm[k] = &v;
    std::set<std::string> seen;
    for (const auto& [k, v] : bf) {
        FigureDiff f;
        f.key = k;
        f.baseline = v;
        seen.insert(k);
        const auto it = cm.find(k);
        if (it == cm.end()) f.has_current = false;
        else f.current = *it->second;
        judge(f, rule_for(rules, id, k));
        r.figures.push_back(std::move(f));
    }
    for (const auto& [k, v] : cf) {
        if (seen.count(k)) continue;
        FigureDiff f;
        f.key = k;
        f.current = v;
        f.has_baseline = false;
        judge(f, rule_for(rules, id, k));
        r.figures.push_back(std::move(f));
    }
}

void compare_checks(const json& base, const json& cur, RunDiff& r) {
    std::map<std::string, bool> bm, cm;
    std::vector<std::string> order;
    for (const auto& [k, v] : report_checks(base)) bm[k] = v.value("passed", false), order.push_back(k);
    for (const auto& [k, v] : report_checks(cur)) {
        cm[k] = v.value("passed", false);
        if (!bm.count(k)) order.push_back(k);
    }
    for (const std::string& k : order) {
        CheckDiff c;
        c.name = k;
        if (bm.count(k)) c.baseline = bm[k];
        if (cm.count(k)) c.current = cm[k];
        if (!c.current) c.change = Change::regression; // the check is gone
        else if (!*c.current && (!c.baseline || *c.baseline)) c.change = Change::regression;
        else if (*c.current && c.baseline && !*c.baseline) c.change = Change::improvement;
        else if (!c.baseline) c.change = Change::added;
        r.checks.push_back(c);
    }
}

} // namespace

Comparison compare_runs(const std::map<std::string, RunRecord>& baseline, const std::map<std::string, RunRecord>& current,
                        const std::vector<Tolerance>& rules, bool allow_missing) {
    Comparison c;
    c.allow_missing = allow_missing;
    std::set<std::string, decltype(&run_id_less)> ids(&run_id_less); // seed=2 before seed=10
    for (const auto& [k, v] : baseline) ids.insert(k);
    for (const auto& [k, v] : current) ids.insert(k);
    for (const std::string& id : ids) {
        RunDiff r;
        r.id = id;
        const auto b = baseline.find(id), cu = current.find(id);
        if (cu == current.end()) {
            r.state = RunDiff::State::missing;
            r.regression = !allow_missing;
            ++c.missing;
        } else if (b == baseline.end()) {
            r.state = RunDiff::State::extra;
            r.regression = !allow_missing;
            ++c.extra;
        } else if (!cu->second.report || !b->second.report) {
            r.state = RunDiff::State::no_report; // the run (or the baseline's) did not finish
            r.regression = true;
            ++c.no_report;
        } else {
            compare_figures(*b->second.report, *cu->second.report, id, rules, r);
            compare_checks(*b->second.report, *cu->second.report, r);
            for (const auto& f : r.figures) ++c.figure_counts[f.change], r.regression |= f.change == Change::regression;
            for (const auto& k : r.checks) ++c.check_counts[k.change], r.regression |= k.change == Change::regression;
        }
        c.runs.push_back(std::move(r));
    }
    return c;
}

namespace {

std::string value_text(const json& v, bool present) {
    if (!present) return "(absent)";
    if (v.is_null()) return "null";
    if (v.is_number_float()) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.6g", v.get<double>());
        return buf;
    }
    return v.dump();
}

std::string signed_text(std::optional<double> v, bool percent) {
    if (!v) return "";
    char buf[32];
    std::snprintf(buf, sizeof buf, percent ? "%+.2f%%" : "%+.6g", percent ? *v * 100 : *v);
    return buf;
}

/// One line of the console table: a figure (or check) over every run where it changed this way,
/// with the run where it changed most.
struct Row {
    std::string what, run, baseline, current, delta, rel;
    std::size_t runs = 1;
    Rank rank = Rank::other;
    double order = 0; // |rel| of the worst run, infinite for a change from 0 or null
};

/// The rows of one kind of change, one per figure or check (grouped over the runs), ranked, the
/// largest change first within a rank.
std::vector<Row> rows_of(const Comparison& c, Change want) {
    std::vector<Row> rows;
    std::map<std::string, std::size_t> at; // figure or check -> its row
    auto add = [&](Row row) {
        const auto it = at.find(row.what);
        if (it == at.end()) {
            at[row.what] = rows.size();
            rows.push_back(std::move(row));
            return;
        }
        Row& old = rows[it->second];
        const std::size_t n = old.runs + 1;
        if (row.order > old.order) old = std::move(row);
        old.runs = n;
    };
    for (const RunDiff& r : c.runs) {
        if (want == Change::regression && r.state != RunDiff::State::matched && r.regression) {
            const char* what = r.state == RunDiff::State::missing ? "run missing from current"
                               : r.state == RunDiff::State::extra ? "run not in the baseline"
                                                                  : "run has no report.json";
            rows.push_back({what, r.id, "", "", "", "", 1, Rank::run, INFINITY});
        }
        for (const auto& k : r.checks)
            if (k.change == want)
                add({"check " + k.name, r.id, k.baseline ? (*k.baseline ? "PASS" : "FAIL") : "(absent)",
                     k.current ? (*k.current ? "PASS" : "FAIL") : "(absent)", "", "", 1, Rank::check, INFINITY});
        for (const auto& f : r.figures)
            if (f.change == want)
                add({f.key, r.id, value_text(f.baseline, f.has_baseline), value_text(f.current, f.has_current),
                     signed_text(f.delta, false), signed_text(f.rel, true), 1, rank_of(f.key),
                     f.rel ? std::fabs(*f.rel) : INFINITY});
    }
    std::stable_sort(rows.begin(), rows.end(),
                     [](const Row& a, const Row& b) { return a.rank != b.rank ? a.rank < b.rank : a.order > b.order; });
    return rows;
}

const char* rank_title(Rank r) {
    switch (r) {
    case Rank::run: return "runs";
    case Rank::check: return "checks that flipped";
    case Rank::budget: return "the budget (Table 3)";
    case Rank::latency: return "interrupt latency and service, per source";
    case Rank::delivery: return "delivery";
    case Rank::other: return "other figures";
    }
    return "?";
}

/// The figures of Rank::other, one line per family: how many changed, and the one that changed
/// most, in which run, by how much. Families whose worst change is largest first.
void print_families(std::vector<Row>::const_iterator begin, std::vector<Row>::const_iterator end, std::ostream& os) {
    struct Family {
        std::size_t figures = 0;
        const Row* worst = nullptr;
    };
    std::map<std::string, Family> by_name;
    for (auto it = begin; it != end; ++it) {
        Family& f = by_name[figure_family(it->what)];
        ++f.figures;
        if (!f.worst || it->order > f.worst->order) f.worst = &*it;
    }
    if (by_name.empty()) return;
    std::vector<std::pair<std::string, Family>> families(by_name.begin(), by_name.end());
    std::stable_sort(families.begin(), families.end(),
                     [](const auto& a, const auto& b) { return a.second.worst->order > b.second.worst->order; });
    os << "  -- " << rank_title(Rank::other) << ": " << (end - begin) << " in " << families.size()
       << " families, one line each\n  " << std::left << std::setw(20) << "family" << std::right << std::setw(8)
       << "figures" << "  " << std::left << std::setw(44) << "most changed" << std::setw(28) << "in run" << std::right
       << std::setw(11) << "rel" << "\n";
    for (const auto& [name, f] : families)
        os << "  " << std::left << std::setw(20) << name << std::right << std::setw(8) << f.figures << "  " << std::left
           << std::setw(44) << f.worst->what << std::setw(28) << f.worst->run << std::right << std::setw(11)
           << (f.worst->rel.empty() ? f.worst->delta : f.worst->rel) << "\n";
}

/// The rows above Rank::other, each rank under its title, at most `limit`; then the other
/// figures by family (print_families).
void print_rows(const std::vector<Row>& rows, const char* title, std::size_t items, std::ostream& os,
                std::size_t limit) {
    if (rows.empty()) return;
    const auto others = std::find_if(rows.begin(), rows.end(), [](const Row& x) { return x.rank == Rank::other; });
    const std::size_t ranked = static_cast<std::size_t>(others - rows.begin()), shown = std::min(ranked, limit);
    std::size_t wr = 9, ww = 6;
    for (std::size_t i = 0; i < shown; ++i) wr = std::max(wr, rows[i].run.size()), ww = std::max(ww, rows[i].what.size());
    const int r = static_cast<int>(std::min<std::size_t>(wr, 40)), w = static_cast<int>(std::min<std::size_t>(ww, 44));
    os << "\n" << title << ": " << items << " in " << rows.size() << " figures/checks; per figure the run where it "
       << "changed most\n  " << std::left << std::setw(w) << "figure" << std::right << std::setw(5) << "runs"
       << "  " << std::left << std::setw(r) << "worst run" << std::right << std::setw(13) << "baseline" << std::setw(13)
       << "current" << std::setw(13) << "delta" << std::setw(11) << "rel" << "\n";
    for (std::size_t i = 0; i < shown; ++i) {
        const Row& x = rows[i];
        if (i == 0 || rows[i - 1].rank != x.rank) os << "  -- " << rank_title(x.rank) << "\n";
        os << "  " << std::left << std::setw(w) << x.what << std::right << std::setw(5) << x.runs << "  " << std::left
           << std::setw(r) << x.run << std::right << std::setw(13) << x.baseline << std::setw(13) << x.current
           << std::setw(13) << x.delta << std::setw(11) << x.rel << "\n";
    }
    if (ranked > shown) os << "  ... and " << ranked - shown << " more of these (--html lists every run)\n";
    print_families(others, rows.end(), os);
}

std::size_t count(const std::map<Change, std::size_t>& m, Change v) {
    const auto it = m.find(v);
    return it == m.end() ? 0 : it->second;
}

} // namespace

void print_comparison(const Comparison& c, std::ostream& os, std::size_t limit) {
    const std::size_t matched = c.runs.size() - c.missing - c.extra - c.no_report;
    const auto& f = c.figure_counts;
    os << "compare: " << matched << " runs matched, " << c.missing << " missing, " << c.extra << " extra, "
       << c.no_report << " without a report" << (c.allow_missing && (c.missing || c.extra) ? " (--allow-missing)" : "")
       << "\nfigures: " << count(f, Change::regression) << " regressions, " << count(f, Change::improvement)
       << " improvements, " << count(f, Change::within) << " changed within tolerance, " << count(f, Change::same)
       << " identical, " << count(f, Change::ignored) << " ignored, " << count(f, Change::added) << " new\n"
       << "checks:  " << count(c.check_counts, Change::regression) << " regressions, "
       << count(c.check_counts, Change::improvement) << " improvements, " << count(c.check_counts, Change::same)
       << " unchanged, " << count(c.check_counts, Change::added) << " new\n";
    const std::size_t regressions = count(f, Change::regression) + count(c.check_counts, Change::regression) +
                                    (c.allow_missing ? 0 : c.missing + c.extra) + c.no_report;
    print_rows(rows_of(c, Change::regression), "regressions", regressions, os, limit);
    print_rows(rows_of(c, Change::improvement), "improvements",
               count(f, Change::improvement) + count(c.check_counts, Change::improvement), os, limit);
    os << "\n" << (c.regression() ? "REGRESSION" : "no regression") << "\n";
}

} // namespace rcsim::sweep
