#include "scenarios/sweep/sweep.h"

#include "models/plumbing/config_error.h"
#include "models/plumbing/output_file.h"
#include "scenarios/config/check_names.h"
#include "scenarios/config/scenario.h"
#include "scenarios/config/yaml_map.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <stdexcept>

namespace rcsim::sweep {

namespace fs = std::filesystem;

namespace {

/// One varied key and its values; `texts` are the values as they appear in run ids.
struct Axis {
    std::string path;
    std::string label;
    std::vector<YAML::Node> values;
    std::vector<std::string> texts;
    int line = 0;
};

/// Axes that move together (a `zip:` group), or a single grid axis.
using AxisGroup = std::vector<Axis>;

struct Base {
    YAML::Node doc;
    std::string written; // as the sweep file names it ("" for an inline mapping)
};

/// `expect_fail_when:` item: the checks that runs with one value of one axis expect to fail.
struct ExpectFailWhen {
    std::string axis;  // an axis path of the entry, or `base` for a list of bases
    std::string value; // as written in the axis (its text in run ids)
    std::vector<std::string> checks;
};

struct Entry {
    std::string name;
    std::vector<Base> bases;  // more than one: the base is an axis too
    bool base_axis = false;
    std::vector<std::pair<std::string, YAML::Node>> set;
    std::vector<AxisGroup> groups;
    std::vector<std::string> expect_fail; // by every run of the entry
    std::vector<ExpectFailWhen> expect_fail_when;
    std::optional<SearchSpec> search;
    int line = 0;
};

/// Characters a run id keeps; every other becomes '_' (ids are directory names and shell words).
std::string id_text(const std::string& s) {
    std::string out;
    for (char c : s) {
        const bool keep = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
                          c == '_' || c == '+' || c == '-';
        out += keep ? c : '_';
    }
    return out.empty() ? "_" : out;
}

/// An axis's values: a list of scalars, or {range: [first, last]} / {range: [first, last, step]}.
void read_values(const YAML::Node& n, const std::string& file, Axis& a) {
    auto fail = [&](const YAML::Node& at, const std::string& why) {
        throw ConfigError(file, YamlMap::line_of(at), "axis '" + a.path + "': " + why);
    };
    if (n.IsMap()) {
        YamlMap m(n, file, a.path + ".");
        const auto r = m.list<long long>("range", 3);
        if (r.size() < 2) fail(n, "range must be [first, last] or [first, last, step] (integers)");
        const long long step = r.size() == 3 ? r[2] : 1;
        if (step == 0 || (r[1] - r[0]) / step < 0) fail(n, "range step must be non-zero and lead from first to last");
        if ((r[1] - r[0]) / step >= 100000) fail(n, "range has more than 100000 values");
        m.finish();
        for (long long v = r[0]; step > 0 ? v <= r[1] : v >= r[1]; v += step) {
            a.values.emplace_back(std::to_string(v));
            a.texts.push_back(std::to_string(v));
        }
        return;
    }
    if (!n.IsSequence() || n.size() == 0) fail(n, "values must be a non-empty list or {range: [first, last]}");
    for (const auto& v : n) {
        if (!v.IsScalar()) fail(v, "a value must be a scalar, not '" + YAML::Dump(v) + "'");
        a.values.push_back(YAML::Clone(v));
        a.texts.push_back(v.Scalar());
    }
}

/// `axes:` (each key one grid axis) or one `zip:` group (the keys move together).
std::vector<Axis> read_axes(const YAML::Node& n, const std::string& file, const std::string& what) {
    if (!n.IsMap() || n.size() == 0)
        throw ConfigError(file, YamlMap::line_of(n), "'" + what + "' must map scenario keys to lists of values");
    std::vector<Axis> out;
    for (const auto& kv : n) {
        Axis a;
        if (!kv.first.IsScalar()) throw ConfigError(file, YamlMap::line_of(kv.first), "an axis must be a key path");
        a.path = kv.first.Scalar();
        a.line = YamlMap::line_of(kv.first);
        read_values(kv.second, file, a);
        out.push_back(std::move(a));
    }
    return out;
}

/// Id labels: the last key of each path ("rom" for board.wait_states.rom), or the whole path
/// without brackets when two axes of the entry share a last key.
void label_axes(std::vector<AxisGroup>& groups) {
    auto leaf = [](const std::string& p) {
        std::string last = p.substr(p.rfind('.') == std::string::npos ? 0 : p.rfind('.') + 1);
        return last.substr(0, last.find('['));
    };
    std::map<std::string, int> uses;
    for (const auto& g : groups)
        for (const auto& a : g) ++uses[leaf(a.path)];
    for (auto& g : groups)
        for (auto& a : g) {
            if (uses[leaf(a.path)] == 1) {
                a.label = leaf(a.path);
                continue;
            }
            for (char c : a.path)
                if (c != '[' && c != ']' && c != '*') a.label += c;
        }
}

std::vector<std::pair<std::string, YAML::Node>> read_set(const YAML::Node& n, const std::string& file) {
    std::vector<std::pair<std::string, YAML::Node>> out;
    if (!n.IsDefined() || n.IsNull()) return out;
    if (!n.IsMap()) throw ConfigError(file, YamlMap::line_of(n), "'set' must map scenario keys to values");
    for (const auto& kv : n) out.emplace_back(kv.first.Scalar(), kv.second);
    return out;
}

Base load_base(const YAML::Node& n, const std::string& file, const fs::path& dir) {
    Base b;
    if (n.IsMap()) {
        b.doc = YAML::Clone(n);
        absolutise_inputs(b.doc, dir);
        return b;
    }
    if (!n.IsScalar()) throw ConfigError(file, YamlMap::line_of(n), "'base' must be a scenario file, a mapping or a list of files");
    b.written = n.Scalar();
    const fs::path p = fs::path(b.written).is_absolute() ? fs::path(b.written) : dir / b.written;
    b.doc = load_yaml_file(p.string());
    if (!b.doc.IsMap()) throw ConfigError(p.string(), YamlMap::line_of(b.doc), "a base scenario must be a mapping");
    absolutise_inputs(b.doc, p.parent_path());
    return b;
}

/// A list of check names (`expect_fail:`, `checks:` of `expect_fail_when:`). A name no report can
/// carry is a typo that would otherwise wait forever to "fail as expected": an error at its line.
std::vector<std::string> read_check_names(const YAML::Node& n, const std::string& file, const std::string& what) {
    if (!n.IsSequence() || n.size() == 0)
        throw ConfigError(file, YamlMap::line_of(n), "'" + what + "' must be a non-empty list of check names");
    std::vector<std::string> names;
    for (const auto& item : n) {
        if (!item.IsScalar() || !is_report_check_name(item.Scalar()))
            throw ConfigError(file, YamlMap::line_of(item), "'" + what + "': '" + YAML::Dump(item) +
                                                               "' is not a check name (docs/scenarios.md \"Checks\")");
        names.push_back(item.Scalar());
    }
    return names;
}

/// The value texts of the entry's axis `path` (`base`: the base files); nullptr when it has none.
const std::vector<std::string>* axis_texts(const Entry& e, const std::string& path, std::vector<std::string>& bases) {
    if (path == "base" && e.base_axis) {
        for (const Base& b : e.bases) bases.push_back(b.written);
        return &bases;
    }
    for (const AxisGroup& g : e.groups)
        for (const Axis& a : g)
            if (a.path == path) return &a.texts;
    return nullptr;
}

/// `expect_fail_when: [{axis: PATH, value: V, checks: [NAME, ...]}, ...]`: PATH must be one of the
/// entry's axes and V one of its values, so that a declaration cannot silently match no run.
void read_expect_fail_when(YamlMap& m, Entry& e) {
    for (YamlMap& item : m.maps("expect_fail_when")) {
        ExpectFailWhen w;
        const YAML::Node axis = item.child("axis"), value = item.child("value");
        if (!axis.IsDefined() || !axis.IsScalar()) item.fail("'expect_fail_when' needs 'axis: PATH', one of the entry's axes");
        if (!value.IsDefined() || !value.IsScalar()) item.fail("'expect_fail_when' needs 'value: V', one of the axis's values");
        w.axis = axis.Scalar();
        w.value = value.Scalar();
        std::vector<std::string> bases;
        const std::vector<std::string>* texts = axis_texts(e, w.axis, bases);
        if (!texts) item.fail(axis, "expect_fail_when: '" + w.axis + "' is not an axis of this entry");
        if (std::find(texts->begin(), texts->end(), w.value) == texts->end())
            item.fail(value, "expect_fail_when: '" + w.value + "' is not a value of the axis '" + w.axis + "'");
        w.checks = read_check_names(item.child("checks"), item.file(), "expect_fail_when.checks");
        item.finish();
        e.expect_fail_when.push_back(std::move(w));
    }
}

/// `search: {maximize: FIGURE | minimize: FIGURE, runs: N, seed: S, algorithm: NAME}`: the entry's
/// one run searches its base for the figure's worst case. The figure's path and the algorithm are
/// checked by `rcsim search` when it runs (it knows the report and its optimisers).
SearchSpec read_search(YamlMap m) {
    SearchSpec s;
    if (m.has("maximize") == m.has("minimize")) m.fail("'search' needs one of 'maximize: FIGURE' and 'minimize: FIGURE'");
    s.maximize = m.has("maximize");
    s.figure = m.require<std::string>(s.maximize ? "maximize" : "minimize");
    if (s.figure.empty()) m.fail("'search': the figure path is empty");
    s.runs = static_cast<std::size_t>(m.integer("runs", s.runs, 2, 100000));
    s.seed = m.get<std::uint64_t>("seed", 1);
    s.algorithm = m.get<std::string>("algorithm", "");
    m.finish();
    return s;
}

/// One entry of `sweeps:`, or the top level when the file has no `sweeps:` (`top`: its `set:` is
/// the sweep's, applied by the caller).
Entry read_entry(YamlMap m, const std::string& default_name, const fs::path& dir, bool top) {
    Entry e;
    e.line = YamlMap::line_of(m.child("base"));
    const YAML::Node base = m.child("base");
    if (!base.IsDefined() || base.IsNull()) m.fail("missing required key '" + m.context() + "base'");
    if (base.IsSequence()) {
        if (base.size() == 0) m.fail(base, "'base' lists no scenario file");
        e.base_axis = true;
        for (const auto& f : base) {
            if (!f.IsScalar()) m.fail(f, "a base in a list must be a scenario file name");
            e.bases.push_back(load_base(f, m.file(), dir));
        }
    } else {
        e.bases.push_back(load_base(base, m.file(), dir));
    }
    const std::string stem = e.bases[0].written.empty() ? default_name : fs::path(e.bases[0].written).stem().string();
    e.name = id_text(m.get<std::string>("name", e.base_axis ? std::string() : stem));
    if (e.name == "_" && !m.has("name")) e.name.clear();
    if (top) m.child("set");
    else e.set = read_set(m.child("set"), m.file());
    if (m.has("axes"))
        for (auto& a : read_axes(m.child("axes"), m.file(), "axes")) e.groups.push_back({std::move(a)});
    if (m.has("zip")) {
        const YAML::Node zip = m.child("zip");
        if (!zip.IsSequence()) m.fail(zip, "'zip' must be a list of groups of axes that move together");
        for (const auto& g : zip) {
            AxisGroup group = read_axes(g, m.file(), "zip");
            for (const auto& a : group)
                if (a.values.size() != group[0].values.size())
                    throw ConfigError(m.file(), a.line, "zip axis '" + a.path + "' has " + std::to_string(a.values.size()) +
                                                            " values, '" + group[0].path + "' has " +
                                                            std::to_string(group[0].values.size()));
            e.groups.push_back(std::move(group));
        }
    }
    label_axes(e.groups);
    if (m.has("expect_fail")) e.expect_fail = read_check_names(m.child("expect_fail"), m.file(), "expect_fail");
    if (m.has("expect_fail_when")) read_expect_fail_when(m, e);
    if (m.has("search")) {
        if (!e.groups.empty() || e.base_axis)
            m.fail(m.child("search"), "a 'search' entry is one run: it takes no axes, zip or list of bases");
        e.search = read_search(m.map("search"));
    }
    m.finish();
    return e;
}

/// The checks a run with these axis values expects to fail: the entry's, and those of every
/// `expect_fail_when` whose axis has its value in the run; sorted, each once.
std::vector<std::string> expected_failures(const Entry& e,
                                           const std::vector<std::pair<std::string, YAML::Node>>& parameters) {
    std::set<std::string> names(e.expect_fail.begin(), e.expect_fail.end());
    for (const ExpectFailWhen& w : e.expect_fail_when)
        for (const auto& [path, value] : parameters)
            if (path == w.axis && value.Scalar() == w.value) names.insert(w.checks.begin(), w.checks.end());
    return {names.begin(), names.end()};
}

/// Every combination of the entry's axes (the first axis varies slowest), as runs.
void expand(const Entry& e, const Sweep& sweep, const std::vector<std::pair<std::string, YAML::Node>>& top_set,
            std::vector<SweepRun>& runs) {
    std::vector<std::size_t> sizes{e.bases.size()};
    for (const auto& g : e.groups) sizes.push_back(g[0].values.size());
    std::vector<std::size_t> at(sizes.size(), 0);
    const fs::path sweep_dir = fs::path(sweep.file).parent_path();
    for (;;) {
        SweepRun r;
        r.entry = e.name;
        r.line = e.line;
        const Base& base = e.bases[at[0]];
        std::string id = e.name;
        auto add = [&id](const std::string& part) { id += (id.empty() ? "" : "-") + part; };
        if (e.base_axis) {
            add(id_text(fs::path(base.written).stem().string()));
            r.parameters.emplace_back("base", YAML::Node(base.written));
        }
        for (std::size_t g = 0; g < e.groups.size(); ++g)
            for (const Axis& a : e.groups[g]) {
                add(id_text(a.label) + "=" + id_text(a.texts[at[g + 1]]));
                r.parameters.emplace_back(a.path, a.values[at[g + 1]]);
            }
        r.id = id.empty() ? "run" : id;
        r.expect_fail = expected_failures(e, r.parameters);
        r.search = e.search;
        r.scenario = YAML::Clone(base.doc);
        r.scenario["name"] = r.id;
        auto apply = [&](const std::string& path, const YAML::Node& v, int line) {
            r.sources.emplace_back(path, line);
            try {
                set_path(r.scenario, path, YAML::Clone(v));
            } catch (const std::invalid_argument& ex) {
                throw ConfigError(sweep.file, line, "run '" + r.id + "': '" + path + "': " + ex.what());
            }
        };
        for (const auto& [k, v] : top_set) apply(k, v, YamlMap::line_of(v));
        for (const auto& [k, v] : e.set) apply(k, v, YamlMap::line_of(v));
        for (std::size_t g = 0; g < e.groups.size(); ++g)
            for (const Axis& a : e.groups[g]) apply(a.path, a.values[at[g + 1]], a.line);
        absolutise_inputs(r.scenario, sweep_dir); // inputs the sweep itself named
        runs.push_back(std::move(r));
        // Next combination: the last axis fastest.
        std::size_t k = sizes.size();
        while (k > 0 && ++at[k - 1] == sizes[k - 1]) at[--k] = 0;
        if (k == 0) break;
    }
}

} // namespace

void absolutise_inputs(YAML::Node doc, const fs::path& dir) {
    auto fix = [&dir](YAML::Node n) {
        if (!n.IsScalar()) return;
        const fs::path p = n.Scalar();
        if (!p.empty() && p.is_relative()) n = fs::absolute(dir / p).lexically_normal().string();
    };
    if (!doc.IsMap()) return;
    if (doc["rom"]) fix(doc["rom"]);
    if (doc["rom"] && doc["rom"].IsMap())
        for (const char* chip : {"even", "odd"})
            if (doc["rom"][chip]) fix(doc["rom"][chip]);
    if (doc["ports"] && doc["ports"].IsSequence())
        for (std::size_t i = 0; i < doc["ports"].size(); ++i)
            if (doc["ports"][i].IsMap() && doc["ports"][i]["file"]) fix(doc["ports"][i]["file"]);
    for (const char* section : {"motion", "main_cpu"})
        if (doc[section] && doc[section].IsMap() && doc[section]["program"]) fix(doc[section]["program"]);
}

Sweep load_sweep(const std::string& path) {
    Sweep s;
    s.file = path;
    const YAML::Node root = load_yaml_file(path);
    if (!root.IsDefined() || root.IsNull()) throw ConfigError(path, 0, "the sweep file is empty");
    YamlMap top(root, path, "");
    s.name = id_text(top.get<std::string>("name", fs::path(path).stem().string()));
    const auto top_set = read_set(top.child("set"), path);
    const fs::path dir = fs::path(path).parent_path();
    std::vector<Entry> entries;
    if (top.has("sweeps")) {
        for (const char* k : {"base", "axes", "zip", "expect_fail", "expect_fail_when", "search"})
            if (top.has(k)) top.fail(top.child(k), std::string("'") + k + "' belongs inside an entry of 'sweeps'");
        for (YamlMap& m : top.maps("sweeps")) entries.push_back(read_entry(m, s.name, dir, false));
        if (entries.empty()) top.fail(top.child("sweeps"), "'sweeps' lists no entry");
    } else {
        // The top level is the one entry (its finish() checks the keys of both).
        entries.push_back(read_entry(YamlMap(root, path, ""), s.name, dir, true));
        for (const char* k : {"base", "axes", "zip", "sweeps", "expect_fail", "expect_fail_when", "search"}) top.child(k);
    }
    top.finish();
    std::map<std::string, int> seen;
    for (const Entry& e : entries) {
        const std::size_t first = s.runs.size();
        expand(e, s, top_set, s.runs);
        for (std::size_t i = first; i < s.runs.size(); ++i) {
            const auto [it, fresh] = seen.emplace(s.runs[i].id, s.runs[i].line);
            if (!fresh)
                throw ConfigError(path, s.runs[i].line, "two runs have the id '" + s.runs[i].id + "' (the other at line " +
                                                            std::to_string(it->second) + "); give the entries distinct names");
        }
    }
    return s;
}

void set_path(YAML::Node doc, const std::string& path, const YAML::Node& value) {
    // Split into keys, each with an optional [n] or [*].
    const std::size_t dot = path.find('.');
    const std::string head = path.substr(0, dot);
    const std::string rest = dot == std::string::npos ? "" : path.substr(dot + 1);
    const std::size_t bra = head.find('[');
    const std::string key = head.substr(0, bra);
    if (key.empty() || (dot != std::string::npos && rest.empty())) throw std::invalid_argument("not a key path");
    if (!doc.IsMap() && !doc.IsNull()) throw std::invalid_argument("'" + key + "' is inside a value that is not a mapping");
    if (bra == std::string::npos) {
        if (rest.empty()) {
            doc[key] = value;
            return;
        }
        YAML::Node child = doc[key];
        if (!child.IsDefined() || child.IsNull()) child = YAML::Node(YAML::NodeType::Map);
        set_path(child, rest, value);
        doc[key] = child;
        return;
    }
    const std::string index = head.substr(bra + 1, head.size() - bra - 2);
    if (head.back() != ']' || index.empty()) throw std::invalid_argument("'" + head + "' must be key[n] or key[*]");
    YAML::Node list = doc[key];
    if (!list.IsDefined() || !list.IsSequence())
        throw std::invalid_argument("'" + key + "' is not a list in the base scenario");
    std::vector<std::size_t> items;
    if (index == "*") {
        for (std::size_t i = 0; i < list.size(); ++i) items.push_back(i);
    } else {
        std::size_t n = 0;
        const auto r = std::from_chars(index.data(), index.data() + index.size(), n);
        if (r.ec != std::errc() || r.ptr != index.data() + index.size())
            throw std::invalid_argument("'" + head + "': the index must be a number or *");
        if (n >= list.size())
            throw std::invalid_argument("'" + key + "' has " + std::to_string(list.size()) + " elements, no [" + index + "]");
        items.push_back(n);
    }
    for (std::size_t i : items) {
        if (rest.empty()) {
            list[i] = value;
        } else {
            YAML::Node elem = list[i];
            set_path(elem, rest, value);
        }
    }
}

std::string scenario_text(const SweepRun& run) {
    YAML::Emitter out;
    out << run.scenario;
    return "# rcsim sweep run '" + run.id + "' (materialised by rcsim sweep; edit the sweep file, not this)\n" +
           out.c_str() + "\n";
}

nlohmann::json scalar_json(const YAML::Node& n) {
    if (!n.IsScalar()) return n.IsNull() ? nlohmann::json() : nlohmann::json(YAML::Dump(n));
    const std::string& t = n.Scalar();
    if (n.Tag() == "!") return t; // quoted: a string, whatever it looks like
    long long i = 0;
    const auto ri = std::from_chars(t.data(), t.data() + t.size(), i);
    if (!t.empty() && ri.ec == std::errc() && ri.ptr == t.data() + t.size()) return i;
    try { // YAML's number and boolean forms
        const double d = n.as<double>();
        if (std::isfinite(d)) return d;
    } catch (const YAML::Exception&) {
    }
    try {
        return n.as<bool>();
    } catch (const YAML::Exception&) {
    }
    return t;
}

nlohmann::json run_json(const SweepRun& run) {
    nlohmann::json params = nlohmann::json::object();
    for (const auto& [k, v] : run.parameters) params[k] = scalar_json(v);
    nlohmann::json j = {{"id", run.id}, {"entry", run.entry}, {"parameters", params}};
    if (!run.expect_fail.empty()) j["expect_fail"] = run.expect_fail;
    if (run.search)
        j["search"] = {{"figure", run.search->figure}, {"direction", run.search->maximize ? "maximize" : "minimize"},
                       {"runs", run.search->runs}, {"seed", run.search->seed}};
    return j;
}

namespace {
/// The sweep line that set the key a scenario error names ('board.wait_states.rom' = 99 ...,
/// 'ports[1].data_size' for an axis on ports[*].data_size); the entry's line when none did.
int source_line(const SweepRun& run, const std::string& message) {
    for (auto it = run.sources.rbegin(); it != run.sources.rend(); ++it) {
        const std::string& p = it->first;
        const std::size_t star = p.find("[*]");
        if (star == std::string::npos) {
            if (message.find("'" + p + "'") != std::string::npos) return it->second;
            continue;
        }
        const std::string head = "'" + p.substr(0, star) + "[", tail = p.substr(star + 3) + "'";
        const std::size_t at = message.find(head);
        if (at == std::string::npos) continue;
        const std::size_t end = message.find('\'', at + 1);
        if (end != std::string::npos && message.compare(end + 1 - tail.size(), tail.size(), tail) == 0) return it->second;
    }
    return run.line;
}
} // namespace

void materialise(const Sweep& sweep, const SweepRun& run, const fs::path& dir) {
    const fs::path d = dir / run.id;
    std::error_code ec;
    fs::remove_all(d, ec);
    fs::create_directories(d, ec);
    if (ec) throw ConfigError(d.string(), 0, "cannot create the run directory: " + ec.message());
    const fs::path scen = d / "scenario.yaml";
    write_file(scen, scenario_text(run), "the run's scenario");
    write_file(d / "run.json", run_json(run).dump(2) + "\n", "the run's parameters");
    try {
        (void)load_scenario(scen.string());
    } catch (const ConfigError& e) {
        throw ConfigError(sweep.file, source_line(run, e.what()), "run '" + run.id + "': " + e.what());
    }
}

void remove_stale_runs(const Sweep& sweep, const fs::path& dir) {
    std::set<std::string> ids;
    for (const SweepRun& r : sweep.runs) ids.insert(r.id);
    std::error_code ec;
    std::vector<fs::path> stale;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.is_directory() && fs::exists(e.path() / "run.json") && !ids.count(e.path().filename().string()))
            stale.push_back(e.path());
    for (const fs::path& p : stale) fs::remove_all(p, ec);
}

Shard shard_from(const std::string& arg, std::optional<std::size_t> shards,
                 const std::function<const char*(const char*)>& env) {
    auto number = [](const std::string& text, const std::string& what) {
        std::size_t v = 0;
        const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
        if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size())
            throw ConfigError(what + " '" + text + "' is not a number >= 0");
        return v;
    };
    Shard s;
    if (!arg.empty()) {
        const std::size_t slash = arg.find('/');
        if (slash == std::string::npos) throw ConfigError("--shard '" + arg + "' must be K/N (e.g. 0/4)");
        s.index = number(arg.substr(0, slash), "--shard K");
        s.count = number(arg.substr(slash + 1), "--shard N");
    } else if (env("SLURM_ARRAY_TASK_ID") && env("SLURM_ARRAY_TASK_COUNT")) {
        const std::size_t id = number(env("SLURM_ARRAY_TASK_ID"), "SLURM_ARRAY_TASK_ID");
        const std::size_t min = env("SLURM_ARRAY_TASK_MIN") ? number(env("SLURM_ARRAY_TASK_MIN"), "SLURM_ARRAY_TASK_MIN") : 0;
        if (id < min) throw ConfigError("SLURM_ARRAY_TASK_ID is below SLURM_ARRAY_TASK_MIN");
        s.index = id - min;
        s.count = number(env("SLURM_ARRAY_TASK_COUNT"), "SLURM_ARRAY_TASK_COUNT");
    } else if (env("JOB_COMPLETION_INDEX") && shards) {
        s.index = number(env("JOB_COMPLETION_INDEX"), "JOB_COMPLETION_INDEX");
        s.count = *shards;
    } else if (shards) {
        throw ConfigError("--shards " + std::to_string(*shards) + " needs JOB_COMPLETION_INDEX (a Kubernetes Indexed Job) or --shard K/N");
    }
    if (s.count == 0 || s.index >= s.count)
        throw ConfigError("shard " + std::to_string(s.index) + "/" + std::to_string(s.count) +
                          ": K must be 0 .. N-1 and N >= 1");
    return s;
}

std::vector<std::size_t> shard_runs(std::size_t total, const Shard& shard) {
    std::vector<std::size_t> out;
    for (std::size_t i = shard.index; i < total; i += shard.count) out.push_back(i);
    return out;
}

std::string shell_quote(const std::string& w) {
    const bool safe = !w.empty() && w.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                        "0123456789._+-=/:,@%") == std::string::npos;
    if (safe) return w;
    std::string out = "'";
    for (char c : w) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

std::vector<std::string> run_argv(const std::string& exe, const fs::path& dir, const SweepRun& run,
                                  const std::string& rom) {
    const fs::path d = dir / run.id;
    std::vector<std::string> argv{exe, "run", (d / "scenario.yaml").string(), "--out", d.string(), "--reproducible"};
    if (run.search) {
        const SearchSpec& s = *run.search;
        argv = {exe, "search", (d / "scenario.yaml").string(), s.maximize ? "--maximize" : "--minimize", s.figure,
                "--runs", std::to_string(s.runs), "--seed", std::to_string(s.seed), "--jobs", "1", "--out", d.string(),
                "--reproducible", "--as-run"};
        if (!s.algorithm.empty()) argv.insert(argv.end(), {"--algorithm", s.algorithm});
    }
    if (!rom.empty()) {
        argv.push_back("--rom");
        argv.push_back(rom);
    }
    return argv;
}

} // namespace rcsim::sweep
