#include "scenarios/search/search.h"

#include "models/plumbing/config_error.h"
#include "models/plumbing/output_file.h"
#include "models/plumbing/stop_signal.h"
#include "scenarios/search/search_page.h"
#include "scenarios/sweep/merge.h"
#include "scenarios/sweep/process_pool.h"
#include "scenarios/sweep/sweep.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <thread>

namespace rcsim::search {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// What the search works from: the scenario, its axes and the document every point starts from.
struct Setup {
    SearchOptions o;
    Scenario s;
    YAML::Node base; // inputs absolute, --rom written in
    std::vector<Axis> axes;
    std::string algorithm;
    unsigned starts = 4;
    fs::path dir, runs_dir;
    std::string exe;
};

/// A search needs runs that end by themselves and reproduce, unattended: a tcp or pty host is a
/// person, a monitor listens for one.
void refuse_interactive(const Scenario& s) {
    if (s.monitor) throw ConfigError(s.file, 0, "a 'monitor' section listens for a person: a search runs unattended");
    for (std::size_t p = 0; p < s.ports.size(); ++p)
        if (s.ports[p].host == PortScenario::Host::tcp || s.ports[p].host == PortScenario::Host::pty)
            throw ConfigError(s.file, 0, "port " + std::to_string(p) +
                                             " has a tcp or pty host: a search runs simulated hosts only");
    if (s.duration_s == 0) throw ConfigError(s.file, 0, "'duration_s: 0' runs until a session ends: a search needs a length");
}

std::vector<Axis> choose_axes(const SearchOptions& o, const Scenario& s) {
    if (!o.axes.empty()) {
        std::vector<SearchAxisRange> ranges;
        for (const std::string& a : o.axes) ranges.push_back(parse_axis_text(a));
        return written_axes(ranges, s, "--axis");
    }
    if (s.search && !s.search->axes.empty()) return written_axes(s.search->axes, s, "the scenario's search section");
    return default_axes(s);
}

/// One scenario file per point, as a sweep writes it (sweep::materialise: checked by the loader).
sweep::SweepRun make_run(const Setup& st, const std::string& id, const std::vector<double>& values) {
    sweep::SweepRun run;
    run.id = id;
    run.entry = "search";
    run.scenario = values.empty() ? YAML::Clone(st.base) : apply(st.base, st.s, st.axes, values);
    run.scenario.remove("search");
    run.scenario["name"] = st.s.name + "-" + id;
    for (std::size_t i = 0; i < values.size(); ++i)
        run.parameters.emplace_back(st.axes[i].path, YAML::Node(st.axes[i].text(values[i])));
    return run;
}

/// Each axis alone at its two ends must give a scenario the loader accepts: a bad range is one
/// message naming the axis and the loader's reason before anything runs.
void check_axes(const Setup& st) {
    const fs::path file = st.dir / "axis_check.yaml";
    for (std::size_t i = 0; i < st.axes.size(); ++i)
        for (double end : {st.axes[i].lo, st.axes[i].hi}) {
            std::vector<double> values;
            for (std::size_t k = 0; k < st.axes.size(); ++k) values.push_back(k == i ? end : st.axes[k].lo);
            const std::string what = "search axis '" + st.axes[i].path + "' = " + st.axes[i].text(end);
            try {
                write_file(file, sweep::scenario_text(make_run(st, "check", values)), "a scenario to check");
                (void)load_scenario(file.string());
            } catch (const std::invalid_argument& e) {
                throw ConfigError(what + ": " + e.what());
            } catch (const ConfigError& e) { // "FILE:LINE: why": the file is ours, the why the user's
                const std::string m = e.what();
                const std::size_t at = m.rfind(file.string() + ":", 0) == 0 ? m.find(": ", file.string().size() + 1) : std::string::npos;
                throw ConfigError(what + ": the scenario refuses it: " + (at == std::string::npos ? m : m.substr(at + 2)));
            }
        }
    std::error_code ec;
    fs::remove(file, ec);
}

Setup prepare(const SearchOptions& o) {
    Setup st;
    st.o = o;
    st.s = load_scenario(o.scenario);
    refuse_interactive(st.s);
    if (o.runs < 2) throw ConfigError("--runs " + std::to_string(o.runs) + ": a search needs at least 2 runs");
    st.axes = choose_axes(o, st.s);
    st.algorithm = !o.algorithm.empty() ? o.algorithm
                   : st.s.search && !st.s.search->algorithm.empty() ? st.s.search->algorithm
                                                                    : search_algorithms().front();
    st.starts = o.starts ? o.starts : st.s.search && st.s.search->starts ? *st.s.search->starts : 4;
    st.base = YAML::Clone(st.s.root);
    sweep::absolutise_inputs(st.base, fs::path(o.scenario).parent_path());
    if (!o.rom.empty()) {
        std::error_code ec;
        if (!fs::is_regular_file(o.rom, ec)) throw ConfigError(o.rom, 0, "--rom: no such ROM image");
        st.base["rom"] = fs::absolute(o.rom).lexically_normal().string();
    }
    st.dir = fs::absolute(o.out).lexically_normal();
    st.runs_dir = st.dir / "runs";
    std::error_code ec;
    fs::remove_all(st.runs_dir, ec); // an earlier search's runs would be merged with these
    fs::create_directories(st.runs_dir, ec);
    if (!fs::is_directory(st.runs_dir)) throw ConfigError(o.out, 0, "--out: cannot create the directory");
    check_axes(st);
    st.exe = sweep::self_executable();
    return st;
}

/// The last line a run wrote to its log (its error message, for a run that failed).
std::string last_line(const fs::path& log) {
    std::ifstream f(log);
    std::string line, last;
    while (std::getline(f, line))
        if (!line.empty()) last = line;
    return last;
}

/// The runs of one batch, on the pool; what each reported.
class Runner {
public:
    Runner(const Setup& st, SearchResult& result, sweep::Progress& progress)
        : st_(st), result_(result), progress_(progress), t0_(std::chrono::steady_clock::now()) {}

    /// Runs the points (id, stage, values); false when a stop signal came. A point the scenario
    /// loader refuses is bad input (ConfigError): check_axes() has tried every axis at its ends.
    bool run(const std::vector<Point>& points) {
        const sweep::Sweep sw{st_.s.file, "search", {}};
        std::vector<sweep::Job> jobs;
        const std::size_t first = result_.history.size();
        for (const Point& p : points) {
            const sweep::SweepRun run = make_run(st_, p.id, p.values);
            sweep::materialise(sw, run, st_.runs_dir);
            std::vector<std::string> argv = sweep::run_argv(st_.exe, st_.runs_dir, run, "");
            if (!st_.o.symbols.empty()) argv.insert(argv.end(), {"--symbols", st_.o.symbols});
            jobs.push_back({argv, (st_.runs_dir / p.id / "run.log").string()});
            result_.history.push_back(p);
        }
        const unsigned parallel = st_.o.jobs ? st_.o.jobs : std::max(1u, std::thread::hardware_concurrency());
        const auto results = sweep::run_jobs(
            jobs, parallel,
            [&](std::size_t j, const sweep::JobResult& r, std::size_t) {
                read_result(result_.history[first + j], r.exit_code);
                ++done_;
                progress_.update(done_, failed_, elapsed());
            },
            [] { return stop_signal(); });
        // A stop leaves out the points that never started: the pool starts them in order.
        std::size_t started = 0;
        while (started < results.size() && results[started].started) ++started;
        result_.history.resize(first + started);
        return stop_signal() == 0;
    }

    /// Runs that ended with their figure, and runs a stop signal cut short.
    std::size_t completed() const { return done_ - interrupted_; }
    std::size_t interrupted() const { return interrupted_; }

    double elapsed() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    }
    std::size_t failed() const { return failed_; }

private:
    void read_result(Point& p, int exit_code) {
        const fs::path report = st_.runs_dir / p.id / "report.json";
        std::error_code ec;
        const int stop = stop_signal();
        if (stop != 0 && exit_code == 128 + stop) { // its report, if any, says interrupted: no figure
            p.verdict = "interrupted";
            ++interrupted_;
            return;
        }
        if (!fs::exists(report, ec)) {
            if (p.stage == "base") // the scenario as written does not run: every point would fail alike
                throw ConfigError((st_.runs_dir / p.id / "run.log").string(), 0,
                                  "the scenario as written ended without a report (exit " + std::to_string(exit_code) +
                                      "): " + last_line(st_.runs_dir / p.id / "run.log"));
            p.verdict = "exit " + std::to_string(exit_code);
            ++failed_;
            progress_.note("run " + p.id + ": no report, exit " + std::to_string(exit_code) + " (" +
                           (st_.runs_dir / p.id / "run.log").string() + ")");
            return;
        }
        try {
            const json r = sweep::read_json_file(report);
            p.verdict = r.value("verdict", std::string("?"));
            if (p.verdict != "interrupted") p.figure = figure_of(r, st_.o.figure);
        } catch (const ConfigError& e) {
            if (p.stage == "base") throw; // the figure's path is wrong: bad input
            p.figure.reset();             // this run has no such figure (a source that never interrupted)
        }
    }

    const Setup& st_;
    SearchResult& result_;
    sweep::Progress& progress_;
    std::chrono::steady_clock::time_point t0_;
    std::size_t done_ = 0, failed_ = 0, interrupted_ = 0;
};

std::string run_id(const std::string& stage, std::size_t n) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%03zu", n);
    return stage + "-" + buf;
}

/// The optimiser's batches as runs: a point asked before (a whole axis rounds many u to one
/// value) is answered from its first run, not run again.
Evaluate evaluator(const Setup& st, SearchResult& result, Runner& runner) {
    auto seen = std::make_shared<std::map<std::string, std::size_t>>(); // parameters -> history index
    auto counts = std::make_shared<std::map<std::string, std::size_t>>();
    return [&st, &result, &runner, seen, counts](const std::vector<Ask>& asks, std::vector<Answer>& out) {
        std::vector<Point> fresh;
        std::vector<std::string> keys(asks.size());
        for (std::size_t i = 0; i < asks.size(); ++i) {
            Point p;
            p.stage = asks[i].stage;
            for (std::size_t k = 0; k < st.axes.size(); ++k) {
                p.values.push_back(st.axes[k].at(asks[i].u[k]));
                keys[i] += st.axes[k].text(p.values.back()) + ";";
            }
            if (seen->count(keys[i])) {
                out[i].ran = false;
                continue;
            }
            p.id = run_id(p.stage, ++(*counts)[p.stage]);
            (*seen)[keys[i]] = result.history.size() + fresh.size();
            fresh.push_back(std::move(p));
        }
        const bool go_on = fresh.empty() || runner.run(fresh);
        for (std::size_t i = 0; i < asks.size(); ++i) {
            const std::size_t at = seen->at(keys[i]); // beyond the history: a stop kept it from running
            out[i].figure = at < result.history.size() ? result.history[at].figure : std::nullopt;
        }
        return go_on;
    };
}

std::optional<std::size_t> best_of(const SearchResult& r, Direction d) {
    std::optional<std::size_t> best;
    for (std::size_t i = 0; i < r.history.size(); ++i) {
        const auto& f = r.history[i].figure;
        if (!f) continue;
        if (!best || (d == Direction::maximize ? *f > *r.history[*best].figure : *f < *r.history[*best].figure)) best = i;
    }
    return best;
}

/// With --as-run (a sweep's search entry): DIR holds the witness's reports as if it were the run,
/// and its run.json says what was searched (from search.json, `s`).
void place_as_run(const Setup& st, const json& s) {
    if (s["best"].is_null()) return;
    const json& best = s["best"];
    const fs::path from = st.runs_dir / best["run"].get<std::string>();
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(from, ec)) {
        const std::string name = e.path().filename().string();
        if (e.is_regular_file() && name != "scenario.yaml" && name != "run.json" && name != "run.log")
            fs::copy_file(e.path(), st.dir / name, fs::copy_options::overwrite_existing, ec);
    }
    json meta = fs::exists(st.dir / "run.json") ? sweep::read_json_file(st.dir / "run.json") : json::object();
    json& search = meta["search"];
    for (const char* key : {"figure", "direction", "seed", "budget", "runs"}) search[key] = s[key];
    search["witness"] = best["run"];
    search["value"] = best["value"];
    search["parameters"] = best["parameters"];
    write_file(st.dir / "run.json", meta.dump(2) + "\n", "the run's parameters");
}

} // namespace

std::optional<double> figure_of(const json& report, const std::string& path) {
    const sweep::Figures figures = sweep::flatten_figures(report);
    for (const auto& [k, v] : figures) {
        if (k != path) continue;
        if (v.is_null()) return std::nullopt;
        if (!v.is_number()) throw ConfigError("figure '" + path + "' is not a number (" + v.dump() + ")");
        return v.get<double>();
    }
    // Name the figures that exist: those under the longest part of the path that does, and of
    // them, when some end as the path does past its first wrong key, those.
    std::string prefix = path;
    std::vector<std::string> near;
    while (near.empty()) {
        const std::size_t cut = prefix.find_last_of(".[");
        prefix = cut == std::string::npos ? "" : prefix.substr(0, cut);
        for (const auto& [k, v] : figures)
            if ((v.is_number() || v.is_null()) && k.rfind(prefix, 0) == 0 &&
                (prefix.empty() || k.size() == prefix.size() || k[prefix.size()] == '.' || k[prefix.size()] == '['))
                near.push_back(k);
        if (prefix.empty()) break;
    }
    const std::size_t wrong_key = path.find_first_of(".[", prefix.size() + 1);
    if (wrong_key != std::string::npos) {
        const std::string tail = path.substr(wrong_key);
        std::vector<std::string> alike;
        for (const std::string& k : near)
            if (k.size() >= tail.size() && k.compare(k.size() - tail.size(), tail.size(), tail) == 0) alike.push_back(k);
        if (!alike.empty()) near = alike;
    }
    std::string list;
    const std::size_t shown = std::min<std::size_t>(near.size(), 40);
    for (std::size_t i = 0; i < shown; ++i) list += "\n  " + near[i];
    if (near.size() > shown) list += "\n  ... and " + std::to_string(near.size() - shown) + " more";
    throw ConfigError("no figure '" + path + "' in report.json; the figures " +
                      (prefix.empty() ? std::string("there are") : "under '" + prefix + "' are") + ":" + list);
}

std::vector<double> influence(const SearchResult& r) {
    std::vector<double> out(r.axes.size(), 0.0);
    std::vector<const Point*> measured;
    for (const Point& p : r.history)
        if (p.figure && p.values.size() == r.axes.size()) measured.push_back(&p);
    if (measured.size() < 2) return out;
    double mean = 0;
    for (const Point* p : measured) mean += *p->figure;
    mean /= static_cast<double>(measured.size());
    double total = 0;
    for (const Point* p : measured) total += (*p->figure - mean) * (*p->figure - mean);
    if (total <= 0) return out;
    constexpr int kCells = 4;
    for (std::size_t a = 0; a < r.axes.size(); ++a) {
        const Axis& ax = r.axes[a];
        double sum[kCells] = {}, n[kCells] = {};
        for (const Point* p : measured) {
            const double span = ax.hi - ax.lo;
            const double u = span > 0 ? (p->values[a] - ax.lo) / span : 0;
            const int c = std::min(kCells - 1, std::max(0, static_cast<int>(u * kCells)));
            sum[c] += *p->figure;
            n[c] += 1;
        }
        double between = 0;
        for (int c = 0; c < kCells; ++c)
            if (n[c] > 0) between += n[c] * (sum[c] / n[c] - mean) * (sum[c] / n[c] - mean);
        out[a] = between / total;
    }
    return out;
}

int run_search(const SearchOptions& o) {
    const Setup st = prepare(o);
    SearchResult result;
    result.axes = st.axes;
    sweep::Progress progress(o.runs, sweep::Progress::interactive_default(), "search");
    Runner runner(st, result, progress);
    install_stop_handlers(); // SIGINT/SIGTERM: no more runs, the running ones stopped (stop_signal.h)
    Point base;
    base.id = base.stage = "base";
    if (runner.run({base})) { // a stop signal ends the search where it is: stopped_by says so
        Plan plan{st.algorithm, st.axes.size(), o.runs - 1, st.starts, o.seed, o.direction, {}};
        for (const Axis& a : st.axes) plan.noise.push_back(a.path == "seed");
        optimise(plan, evaluator(st, result, runner));
    }
    result.stopped_by = stop_signal();
    result.best = best_of(result, o.direction);
    result.wall_s = runner.elapsed();
    if (result.stopped_by)
        progress.interrupted(result.stopped_by == SIGINT ? "SIGINT" : "SIGTERM", runner.completed(),
                             runner.interrupted(), runner.failed(), result.wall_s);
    else
        progress.finish(runner.failed(), result.wall_s);

    if (o.reproducible) result.wall_s = 0;
    const PageInput page{o, st.s.name, st.algorithm, st.starts, st.dir, result};
    const json searched = write_witness(page);
    sweep::merge_runs({st.runs_dir.string()}, st.dir);
    if (o.as_run) place_as_run(st, searched);
    print_outcome(page, std::cout);
    if (result.stopped_by) return 128 + result.stopped_by;
    if (!result.best) return 4;
    const bool witness_failed = result.history[*result.best].verdict == "failed";
    const bool lost = std::any_of(result.history.begin(), result.history.end(),
                                  [](const Point& p) { return p.verdict.rfind("exit ", 0) == 0; });
    return witness_failed || lost ? 1 : 0;
}

} // namespace rcsim::search
