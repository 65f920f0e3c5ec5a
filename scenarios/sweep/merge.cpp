#include "scenarios/sweep/merge.h"

#include "models/plumbing/config_error.h"
#include "models/plumbing/output_file.h"
#include "scenarios/coverage/tracefile.h"
#include "scenarios/sweep/expectation.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace rcsim::sweep {

namespace fs = std::filesystem;
using json = nlohmann::json;

nlohmann::json read_json_file(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw ConfigError(file.string(), 0, "cannot open");
    std::ostringstream text;
    text << in.rdbuf();
    const std::string s = text.str();
    try {
        return nlohmann::json::parse(s);
    } catch (const nlohmann::json::parse_error& e) {
        // nlohmann names the byte; people read lines.
        const std::size_t at = std::min<std::size_t>(e.byte, s.size());
        const int line = 1 + static_cast<int>(std::count(s.begin(), s.begin() + static_cast<long>(at), '\n'));
        std::string why = e.what();
        const auto colon = why.find("syntax error");
        throw ConfigError(file.string(), line, "bad JSON: " + (colon == std::string::npos ? why : why.substr(colon)));
    }
}

namespace {

/// A run directory: run.json's id (a sweep run) or the directory's name.
RunRecord read_run(const fs::path& dir) {
    RunRecord r;
    r.dir = dir;
    r.id = dir.filename().string();
    if (fs::exists(dir / "run.json")) {
        r.meta = read_json_file(dir / "run.json");
        if (!r.meta.is_object() || !r.meta.contains("id") || !r.meta["id"].is_string())
            throw ConfigError((dir / "run.json").string(), 0, "not a run.json of rcsim sweep (no \"id\")");
        r.id = r.meta["id"].get<std::string>();
    } else {
        r.meta = nlohmann::json::object();
    }
    if (fs::exists(dir / "report.json")) r.report = read_json_file(dir / "report.json");
    return r;
}

bool is_run_dir(const fs::path& d) { return fs::exists(d / "run.json") || fs::exists(d / "report.json"); }

/// The latency causes (`interrupts.SOURCE.worst`, docs/scenarios.md "Latency causes") explain
/// figures and are not figures: a list whose length and phases change with every fix.
bool explanation(const std::string& path, const std::string& key) {
    return key == "worst" && path.rfind("interrupts.", 0) == 0;
}

void flatten(const nlohmann::json& j, const std::string& path, Figures& out) {
    if (j.is_object()) {
        for (const auto& [k, v] : j.items())
            if (!explanation(path, k)) flatten(v, path.empty() ? k : path + "." + k, out);
    } else if (j.is_array()) {
        for (std::size_t i = 0; i < j.size(); ++i) flatten(j[i], path + "[" + std::to_string(i) + "]", out);
    } else if (j.is_number() || j.is_boolean() || j.is_null()) {
        out.emplace_back(path, j);
    }
}

std::string csv_cell(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string out = "\"";
    for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}

std::string cell_text(const json& v) {
    if (v.is_null()) return "";
    if (v.is_string()) return v.get<std::string>();
    return v.dump();
}

/// The keys of `field` over all runs, in first-appearance order (runs sorted by id).
std::vector<std::string> union_keys(const json& runs, const char* field) {
    std::vector<std::string> keys;
    std::set<std::string> seen;
    for (const auto& r : runs)
        for (const auto& [k, v] : r[field].items())
            if (seen.insert(k).second) keys.push_back(k);
    return keys;
}

/// The length of the number that starts at `s[i]` (0: none): a sign only right after '=' (a '-'
/// elsewhere separates the parts of an id), digits, a fraction, an exponent.
std::size_t number_at(const std::string& s, std::size_t i) {
    const auto digit = [&](std::size_t k) { return k < s.size() && s[k] >= '0' && s[k] <= '9'; };
    std::size_t k = i;
    if ((s[k] == '-' || s[k] == '+') && k > 0 && s[k - 1] == '=') ++k;
    if (!digit(k)) return 0;
    while (digit(k)) ++k;
    if (k < s.size() && s[k] == '.' && digit(k + 1))
        for (++k; digit(k);) ++k;
    if (k < s.size() && (s[k] == 'e' || s[k] == 'E')) {
        std::size_t e = k + 1;
        if (e < s.size() && (s[e] == '-' || s[e] == '+')) ++e;
        if (digit(e))
            for (k = e; digit(k);) ++k;
    }
    return k - i;
}

} // namespace

bool run_id_less(const std::string& a, const std::string& b) {
    std::size_t i = 0, j = 0;
    while (i < a.size() && j < b.size()) {
        const std::size_t na = number_at(a, i), nb = number_at(b, j);
        if (na && nb) {
            const std::string ta = a.substr(i, na), tb = b.substr(j, nb);
            const double va = std::strtod(ta.c_str(), nullptr), vb = std::strtod(tb.c_str(), nullptr);
            if (va != vb) return va < vb;
            if (ta != tb) return ta < tb; // 1 and 1.0: still one order
            i += na, j += nb;
            continue;
        }
        if (a[i] != b[j]) return a[i] < b[j];
        ++i, ++j;
    }
    return a.size() - i < b.size() - j;
}

std::vector<RunRecord> collect_runs(const std::vector<std::string>& dirs) {
    std::vector<RunRecord> runs;
    std::map<std::string, fs::path> where;
    for (const std::string& d : dirs) {
        std::error_code ec;
        if (!fs::is_directory(d, ec)) throw ConfigError(d, 0, "not a directory of runs");
        std::vector<fs::path> found;
        if (is_run_dir(d)) found.push_back(d);
        else
            for (const auto& e : fs::directory_iterator(d))
                if (e.is_directory() && is_run_dir(e.path())) found.push_back(e.path());
        for (const fs::path& p : found) {
            RunRecord r = read_run(p);
            const auto [it, fresh] = where.emplace(r.id, p);
            if (!fresh)
                throw ConfigError(p.string(), 0, "run '" + r.id + "' is also in " + it->second.string() +
                                                     " (merge each run once)");
            runs.push_back(std::move(r));
        }
    }
    std::sort(runs.begin(), runs.end(), [](const RunRecord& a, const RunRecord& b) { return run_id_less(a.id, b.id); });
    return runs;
}

Figures flatten_figures(const nlohmann::json& report) {
    Figures out;
    for (const auto& [k, v] : report.items()) {
        if (k == "checks" || k == "checks_off" || k == "warnings" || k == "passed") continue;
        flatten(v, k, out);
    }
    return out;
}

std::vector<std::pair<std::string, nlohmann::json>> report_checks(const nlohmann::json& report) {
    std::vector<std::pair<std::string, nlohmann::json>> out;
    if (!report.contains("checks") || !report["checks"].is_array()) return out;
    for (const auto& c : report["checks"]) {
        if (!c.is_object() || !c.contains("name")) continue;
        nlohmann::json v = c;
        v.erase("name");
        v["passed"] = c.contains("passed") && c["passed"].is_boolean() && c["passed"].get<bool>(); // else: failed
        out.emplace_back(c["name"].is_string() ? c["name"].get<std::string>() : c["name"].dump(), v);
    }
    return out;
}

const char* const kNotRunMarker = "not_run.txt";

std::string run_status(const RunRecord& run) {
    if (!run.report) return fs::exists(run.dir / kNotRunMarker) ? "not run" : "no report";
    const nlohmann::json& r = *run.report;
    // passed, failed, inconclusive or interrupted; a report from before verdicts has `passed` only.
    if (r.contains("verdict") && r["verdict"].is_string()) return r["verdict"].get<std::string>();
    return r.contains("passed") && r["passed"].is_boolean() && r["passed"].get<bool>() ? "passed" : "failed";
}

nlohmann::json summary_json(const std::vector<RunRecord>& runs) {
    json list = json::array();
    std::map<std::string, std::size_t> counts{{"passed", 0}, {"failed", 0}, {"inconclusive", 0}, {"no report", 0}};
    std::map<std::string, std::size_t> outcomes = counts;
    for (const RunRecord& r : runs) {
        json j;
        j["id"] = r.id;
        j["entry"] = r.meta.contains("entry") && r.meta["entry"].is_string() ? r.meta["entry"] : json("");
        j["status"] = run_status(r);
        ++counts[j["status"].get<std::string>()];
        j["parameters"] = r.meta.contains("parameters") && r.meta["parameters"].is_object() ? r.meta["parameters"]
                                                                                            : json::object();
        j["figures"] = json::object();
        j["checks"] = json::object();
        if (r.report) {
            for (const auto& [k, v] : flatten_figures(*r.report)) j["figures"][k] = v;
            for (const auto& [k, v] : report_checks(*r.report)) j["checks"][k] = v;
        }
        // The sweep's judgement beside the run's own status, so that a by-design failure shows as both.
        const Expectation judged = judge_run(r);
        j["expected_failures"] = expected_failures(r);
        j["outcome"] = judged.outcome;
        j["outcome_why"] = judged.why;
        ++outcomes[judged.outcome];
        list.push_back(j);
    }
    json s;
    s["runs"] = runs.size();
    for (const auto& [k, n] : counts) s[k] = n;
    s["outcomes"] = outcomes;
    s["results"] = list;
    return s;
}

std::string summary_csv(const nlohmann::json& summary) {
    // Columns in the summary's key order (sorted, as in report.json itself).
    const json& runs = summary["results"];
    const auto params = union_keys(runs, "parameters");
    const auto figures = union_keys(runs, "figures");
    const auto checks = union_keys(runs, "checks");
    std::ostringstream os;
    os << "id,entry,status";
    for (const auto& k : params) os << "," << csv_cell("param:" + k);
    for (const auto& k : figures) os << "," << csv_cell(k);
    for (const auto& k : checks) os << "," << csv_cell("check:" + k);
    os << ",expected_failures,outcome\n"; // last, so that the columns before keep their places
    for (const auto& r : runs) {
        os << csv_cell(r["id"].get<std::string>()) << "," << csv_cell(r["entry"].get<std::string>()) << ","
           << csv_cell(r["status"].get<std::string>());
        for (const auto& k : params) os << "," << (r["parameters"].contains(k) ? csv_cell(cell_text(r["parameters"][k])) : "");
        for (const auto& k : figures) os << "," << (r["figures"].contains(k) ? csv_cell(cell_text(r["figures"][k])) : "");
        for (const auto& k : checks) {
            os << ",";
            if (r["checks"].contains(k)) os << (r["checks"][k].value("passed", false) ? "PASS" : "FAIL");
        }
        std::string expected;
        for (const auto& name : r["expected_failures"]) expected += (expected.empty() ? "" : " ") + name.get<std::string>();
        os << "," << csv_cell(expected) << "," << csv_cell(r["outcome"].get<std::string>()) << "\n";
    }
    return os.str();
}

std::string number_text(const nlohmann::json& v) {
    if (v.is_null()) return "null";
    return v.is_string() ? v.get<std::string>() : v.dump();
}

std::size_t merge_runs(const std::vector<std::string>& dirs, const fs::path& out, std::vector<std::string>* unfinished) {
    const auto runs = collect_runs(dirs);
    for (const RunRecord& r : runs) {
        const std::string status = run_status(r);
        if (!unfinished || status == "passed" || status == "failed" || status == "inconclusive") continue;
        // Where to look: the run's log when it started, else its directory.
        const fs::path log = r.dir / "run.log";
        unfinished->push_back("run " + r.id + ": " + status + " (" + (fs::exists(log) ? log : r.dir).string() + ")");
    }
    const nlohmann::json summary = summary_json(runs);
    write_file(out / "summary.json", summary.dump(2) + "\n", "the summary");
    write_file(out / "summary.csv", summary_csv(summary), "the summary");
    write_file(out / "summary.html", summary_html(summary), "the summary");
    // The runs' coverage (rcsim sweep --coverage), merged as lcov -a merges.
    std::vector<fs::path> tracefiles;
    for (const RunRecord& r : runs)
        if (fs::exists(r.dir / "coverage.info")) tracefiles.push_back(r.dir / "coverage.info");
    if (!tracefiles.empty()) coverage::write_tracefile_to(out / "coverage.info", coverage::merge_tracefiles(tracefiles));
    else {
        std::error_code ec; // an earlier merge's: not these runs'
        fs::remove(out / "coverage.info", ec);
    }
    return runs.size();
}

} // namespace rcsim::sweep
