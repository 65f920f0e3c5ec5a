// A mutation fuzzer over rcsim's two text inputs, the scenario schema and the replay session log,
// driving the real binary: every case must end with exit code 0, 1, 2 or 4 (never 3, a signal, a
// sanitizer report or a hang), a bad input with exactly one line on stderr, and within a bounded
// wall time (docs/scenarios.md "Exit codes", "Limits").
//
// Cases are built from the schema (keys with values drawn from edge cases: negative, zero, tiny,
// huge, NaN, infinite, fractional, strings, lists, maps, control characters), then, for half of
// them, mutated byte by byte (flips, inserted YAML punctuation, deleted spans, duplicated lines).
// A replay log is generated the same way. Each scenario starts with a fixed, unmutated
// `duration_s: 0.002` and `drain_s: 0`, so every case is short.
//
// Usage: fuzz_inputs RCSIM. Environment: RCSIM_FUZZ_CASES (default 300), RCSIM_FUZZ_SEED
// (default 1; the same seed gives the same cases), RCSIM_FUZZ_KEEP=DIR keeps failing cases,
// RCSIM_FUZZ_VERBOSE=1 prints every case with its outcome.
#include "tests/support/files.h"

#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace {

constexpr double kCaseLimitS = 30;   // the longest a case may take (a 2 ms run plus start-up)
constexpr double kCaseKillS = 90;    // then it is a hang

class Rng {
public:
    explicit Rng(std::uint64_t seed) : s_(seed) {}
    std::uint64_t next() { // splitmix64: the same cases for a seed on every platform
        std::uint64_t z = (s_ += 0x9E3779B97F4A7C15ULL);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        return z ^ (z >> 31);
    }
    std::size_t below(std::size_t n) { return n ? static_cast<std::size_t>(next() % n) : 0; }
    bool chance(unsigned percent) { return below(100) < percent; }
    template <typename T> const T& pick(const std::vector<T>& v) { return v[below(v.size())]; }

private:
    std::uint64_t s_;
};

const std::vector<std::string> kNumbers = {
    "0", "1", "-1", "-0.5", "0.5", "1.7", "2", "3", "7", "8", "9", "11", "12", "16", "64", "255", "256",
    "1000", "8192", "8193", "1e6", "1e-6", "1e-300", "1e300", "1e308", ".nan", ".inf", "-.inf", "0x10",
    "18446744073709551615", "18446744073709551616", "-9223372036854775808", "4294967296", "abc", "''",
    "~", "[]", "{}", "[1, 2]", "{a: 1}", "\"\\x01\\x1b\"", "true", "10", "100", "1000000"};
const std::vector<std::string> kFormats = {"\"9600,8E1\"", "\"9600,7N2\"", "\"19200,8N1\"", "\"9600,5O1.5\"",
                                           "\"0,8E1\"", "\"9600,9E1\"", "\"300,8M2\"", "\"115200,8S1\"", "x"};
const std::vector<std::string> kHosts = {"protocol", "protocol", "protocol", "raw", "replay", "replay",
                                         "none", "tcp", "protocol", "modem"};
const std::vector<std::string> kTraffic = {"none", "fixed", "poisson", "burst", "saturate", "warp"};
const std::vector<std::string> kFaultKinds = {"flip_data_bit", "flip_cell", "drop", "corrupt_stop", "break", "zap"};
const std::vector<std::string> kFiles = {"a.log", "b.bin", "full", "fuzz.log", "missing.log", "dir", "\"\""};
const std::vector<std::string> kPunct = {"\n", ": ", "- ", "{", "}", "[", "]", ",", "&a ", "*a", "---\n", "? ",
                                         "!!str ", "|\n", "#", "\"", "'", "\t", std::string(1, '\0'), "\x01",
                                         "\xff", "  ", "1e308", ".nan", "-"};

const std::vector<std::string> kPlausible = {"0", "1", "2", "4", "10", "16", "100", "0.5", "1000"};

/// Mostly a plausible value (so that many cases run), else an edge case.
std::string number(Rng& r) { return r.chance(60) ? r.pick(kPlausible) : r.pick(kNumbers); }

/// One `key: value` line at `indent`, most values from the key's own domain, some from any.
std::string entry(Rng& r, const std::string& indent, const std::string& key, const std::string& value) {
    return indent + key + ": " + (r.chance(15) ? number(r) : value) + "\n";
}

/// A port whose keys mostly belong to its host kind (a key of another kind now and then).
std::string port(Rng& r) {
    const std::string in = "    ", host = r.pick(kHosts);
    auto mine = [&](bool of_this_kind, unsigned percent) { return r.chance(of_this_kind ? percent : 3); };
    const bool protocol = host == "protocol", raw = host == "raw", replay = host == "replay", tcp = host == "tcp";
    std::string p = "  - host: " + host + "\n";
    if (r.chance(40)) p += entry(r, in, "format", r.pick(kFormats));
    if (mine(protocol, 80)) p += entry(r, in, "traffic", r.pick(kTraffic));
    for (const char* k : {"rate_hz", "burst_size", "burst_period_ms", "count", "start_ms", "data_size", "nak_enqs",
                          "response_timeout_ms"})
        if (mine(protocol, 15)) p += entry(r, in, k, number(r));
    if (r.chance(10)) p += entry(r, in, "noise_per_bit", r.chance(70) ? "0.001" : number(r));
    if (mine(protocol, 10)) p += entry(r, in, "random_size", r.chance(80) ? "true" : "maybe");
    if (mine(protocol, 10)) p += entry(r, in, "tokens", r.chance(70) ? "{EC: 1, ST: 2}" : "{EC: " + number(r) + "}");
    if (mine(protocol, 10)) p += entry(r, in, "log", r.pick(kFiles));
    if (mine(replay, 95)) p += entry(r, in, "file", r.chance(85) ? "fuzz.log" : r.pick(kFiles));
    if (mine(raw || tcp || replay, 15)) p += entry(r, in, "record", r.pick(kFiles));
    if (mine(raw, 70)) p += entry(r, in, "send", "[{at_ms: " + number(r) + ", bytes: \"\\\\x05ab\"}]");
    if (r.chance(25)) {
        p += in + "faults:\n";
        for (std::size_t i = 0, n = 1 + r.below(3); i < n; ++i) {
            const std::string kind = r.pick(kFaultKinds);
            p += in + "  - {kind: " + kind;
            const bool brk = kind == "break", flip = kind.rfind("flip", 0) == 0;
            if (mine(!brk, 70)) p += ", index: " + number(r);
            if (mine(flip, 70)) p += ", bit: " + number(r);
            if (mine(brk, 70)) p += ", at_ms: " + number(r);
            if (mine(brk, 50)) p += ", duration_ms: " + number(r);
            if (r.chance(20)) p += ", from: " + std::string(r.chance(80) ? "controller" : "both");
            p += "}\n";
        }
    }
    return p;
}

std::string scenario_body(Rng& r) {
    std::string s;
    if (r.chance(10)) s += entry(r, "", "realtime", r.chance(70) ? "0" : number(r));
    if (r.chance(10)) s += entry(r, "", "budget_us", number(r));
    if (r.chance(10)) s += entry(r, "", "seed", number(r));
    if (r.chance(5)) s += entry(r, "", "rom", r.pick(kFiles));
    if (r.chance(25)) {
        s += "board:\n";
        for (const auto& [k, v] : std::vector<std::pair<const char*, const char*>>{
                 {"cpu_hz", "8e6"}, {"uart_clock_hz", "18432000"}, {"quantum_us", "1"}, {"dpram_speed_grade_ns", "35"}})
            if (r.chance(30)) s += entry(r, "  ", k, r.chance(30) ? number(r) : v);
        if (r.chance(20)) s += "  wait_states: {ram: " + number(r) + ", io: " + number(r) + "}\n";
    }
    if (r.chance(25)) {
        s += "main_cpu:\n";
        for (const auto& [k, v] : std::vector<std::pair<const char*, const char*>>{
                 {"bus_clock_hz", "16e6"}, {"irq_entry_us", "2"}, {"command_time_us", "20"},
                 {"cycle_period_us", "200"}, {"cycle_time_us", "50"}, {"ack_timeout_us", "1000"}})
            if (r.chance(30)) s += entry(r, "  ", k, r.chance(30) ? number(r) : v);
    }
    if (r.chance(25)) {
        s += "checks:\n";
        for (const char* k : {"max_overruns", "max_frames_failed", "max_char_latency_us", "min_margin_us",
                              "min_frames_delivered", "overruns"})
            if (r.chance(30)) s += entry(r, "  ", k, r.chance(20) ? "off" : number(r));
    }
    if (r.chance(85)) {
        s += "ports:\n";
        for (std::size_t i = 0, n = r.chance(5) ? 4 : 1 + r.below(3); i < n; ++i) s += port(r);
    }
    return s;
}

std::string session_log(Rng& r) {
    std::string s = r.chance(80) ? "format " + std::string(r.chance(80) ? "9600,8E1" : "9600,7N2") + "\n" : "";
    std::uint64_t t = 0;
    for (std::size_t i = 0, n = r.below(12); i < n; ++i) {
        t += r.below(3000000000ULL);
        std::string time = std::to_string(t);
        if (r.chance(10)) time = r.pick(std::vector<std::string>{"-5", "+5", "1e3", "3600000000000001",
                                                                "18446744073709551621", "", "0x10", " 5"});
        const std::string word = r.pick(std::vector<std::string>{"in", "out", "in", "out", "connect", "disconnect",
                                                                "listen", "end", "bogus"});
        std::string line = time + " " + word;
        if (word == "in" || word == "out") {
            char hex[3];
            std::snprintf(hex, sizeof hex, "%02X", static_cast<unsigned>(r.below(256)));
            line += " " + std::string(r.chance(90) ? hex : "+5");
            if (r.chance(15)) line += r.pick(std::vector<std::string>{" P", " F", " PF", " X", " P junk"});
        }
        s += line + (r.chance(5) ? "\r\n" : "\n");
    }
    return s;
}

/// A few byte-level edits. No '/' survives: every path a case names stays in the work folder.
std::string mutate(Rng& r, std::string s) {
    for (std::size_t i = 0, n = 1 + r.below(4); i < n; ++i) {
        const std::size_t at = r.below(s.size() + 1);
        switch (r.below(4)) {
        case 0: if (at < s.size()) s[at] = static_cast<char>(s[at] ^ (1u << r.below(8))); break;
        case 1: s.insert(at, r.pick(kPunct)); break;
        case 2: s.erase(at, r.below(8)); break;
        default: {
            const std::size_t b = s.rfind('\n', at == 0 ? 0 : at - 1), e = s.find('\n', at);
            const std::size_t from = b == std::string::npos ? 0 : b + 1;
            if (e != std::string::npos) s.insert(from, s.substr(from, e + 1 - from)); // a line twice
        }
        }
    }
    for (char& c : s)
        if (c == '/') c = '_';
    return s;
}

struct Outcome {
    bool exited = false;
    int code = -1;
    int signal = 0;
    bool killed = false;
    double seconds = 0;
    std::string err;
};

Outcome run(const std::string& rcsim, const fs::path& dir) {
    Outcome o;
    const auto t0 = std::chrono::steady_clock::now();
    const pid_t pid = fork();
    if (pid == 0) {
        if (chdir(dir.c_str()) != 0) _exit(120);
        const int out = open("/dev/null", O_WRONLY), err = open("stderr.txt", O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (out < 0 || err < 0) _exit(121);
        dup2(out, 1);
        dup2(err, 2);
        execl(rcsim.c_str(), rcsim.c_str(), "run", "case.yaml", "--out", "out", static_cast<char*>(nullptr));
        _exit(122);
    }
    int status = 0;
    for (;;) {
        if (waitpid(pid, &status, WNOHANG) == pid) break;
        o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (o.seconds > kCaseKillS && !o.killed) {
            kill(pid, SIGKILL);
            o.killed = true;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    o.exited = WIFEXITED(status);
    o.code = o.exited ? WEXITSTATUS(status) : -1;
    o.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
    o.err = rcsim::test::slurp(dir / "stderr.txt");
    return o;
}

/// "" when the outcome is acceptable, else why not.
std::string judge(const Outcome& o) {
    if (o.killed) return "no end within " + std::to_string(static_cast<int>(kCaseKillS)) + " s (killed)";
    if (!o.exited) return "died of signal " + std::to_string(o.signal);
    for (const char* bad : {"AddressSanitizer", "LeakSanitizer", "runtime error:", "terminate called", "Aborted"})
        if (o.err.find(bad) != std::string::npos) return std::string("stderr has '") + bad + "'";
    if (o.code < 0 || (o.code > 2 && o.code != 4))
        return "exit code " + std::to_string(o.code) + " (only 0, 1, 2 and 4 are input's)";
    if (o.code == 2) {
        std::size_t lines = 0;
        std::istringstream ls(o.err);
        for (std::string l; std::getline(ls, l);)
            if (!l.empty() && l != "Run with --help for more information.") ++lines;
        if (lines != 1) return "bad input with " + std::to_string(lines) + " lines on stderr, not one";
    }
    if (o.seconds > kCaseLimitS) return "took " + std::to_string(o.seconds) + " s (limit " + std::to_string(kCaseLimitS) + ")";
    return "";
}

std::string escaped(const std::string& s) {
    std::string out;
    for (unsigned char c : s) {
        if (c == '\n' || (c >= 0x20 && c < 0x7F)) out += static_cast<char>(c);
        else {
            char h[5];
            std::snprintf(h, sizeof h, "\\x%02X", c);
            out += h;
        }
    }
    return out;
}

std::uint64_t env_number(const char* name, std::uint64_t fallback) {
    const char* v = std::getenv(name);
    return v && *v ? std::strtoull(v, nullptr, 10) : fallback;
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: fuzz_inputs RCSIM\n";
        return 2;
    }
    const std::string rcsim = fs::absolute(argv[1]).string();
    const std::uint64_t cases = env_number("RCSIM_FUZZ_CASES", 300);
    const std::uint64_t seed = env_number("RCSIM_FUZZ_SEED", 1);
    const char* keep = std::getenv("RCSIM_FUZZ_KEEP");
    setenv("SC_COPYRIGHT_MESSAGE", "DISABLE", 1);

    // In the working directory (CTest's is in the build tree), so that the build that fuzzes owns
    // its cases; mkdtemp keeps two runs in one tree apart.
    std::string tmpl = (fs::current_path() / "fuzz_work.XXXXXX").string();
    const char* made = mkdtemp(tmpl.data());
    if (!made) {
        std::perror("mkdtemp");
        return 2;
    }
    const fs::path dir = made;
    fs::create_directory(dir / "dir");
    fs::create_symlink("/dev/full", dir / "full"); // a full disk for `record:` and `log:`

    Rng rng(seed);
    std::uint64_t failures = 0, by_code[5] = {0, 0, 0, 0, 0}; // judge() admits 0, 1, 2 and 4
    double slowest = 0;
    for (std::uint64_t i = 0; i < cases; ++i) {
        std::string body = scenario_body(rng), log = session_log(rng);
        if (rng.chance(50)) body = mutate(rng, body);
        if (rng.chance(30)) log = mutate(rng, log);
        const std::string text = "duration_s: 0.002\ndrain_s: 0\n" + body;
        std::ofstream(dir / "case.yaml", std::ios::binary) << text;
        std::ofstream(dir / "fuzz.log", std::ios::binary) << log;
        const Outcome o = run(rcsim, dir);
        slowest = std::max(slowest, o.seconds);
        const std::string why = judge(o);
        if (why.empty()) {
            if (std::getenv("RCSIM_FUZZ_VERBOSE")) std::cout << "case " << i << ": exit " << o.code << ": " << escaped(o.err) << escaped(text) << "\n";
            ++by_code[o.code];
            continue;
        }
        ++failures;
        std::cout << "FAIL case " << i << " (seed " << seed << "): " << why << "\n--- case.yaml\n" << escaped(text)
                  << "--- fuzz.log\n" << escaped(log) << "--- stderr\n" << escaped(o.err.substr(0, 2000)) << "\n";
        if (keep) {
            const fs::path k = fs::path(keep) / ("case" + std::to_string(i));
            fs::create_directories(k);
            fs::copy_file(dir / "case.yaml", k / "case.yaml", fs::copy_options::overwrite_existing);
            fs::copy_file(dir / "fuzz.log", k / "fuzz.log", fs::copy_options::overwrite_existing);
        }
    }
    std::error_code ec;
    fs::remove_all(dir, ec);
    std::cout << cases << " cases (seed " << seed << "): exit 0: " << by_code[0] << ", exit 1: " << by_code[1]
              << ", exit 2: " << by_code[2] << ", exit 4: " << by_code[4] << ", failures: " << failures << "; slowest " << slowest << " s\n";
    return failures == 0 ? 0 : 1;
}
