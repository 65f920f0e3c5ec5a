"""rcsim search end to end (docs/search.md), on the known-answer ROM of search_kat.asm:

  1. the search gets within 1 % of the analytic maximum of port 1's latency over its send time
     (3184 clocks = 398.000 us, derived in search_kat.asm) in the runs docs/search.md states,
     and never above it;
  2. the witness: `rcsim run DIR/worst.yaml` gives the same report, figure and causes;
  3. search.json's shape; best so far never falls; the same seed gives the same search with
     --jobs 1 and --jobs 2; --minimize goes the other way;
  4. the scenario's search: section is used when no --axis is given;
  5. search.html links the witness, its report and shows two charts and the cause;
  6. bad input exits 2 with one message naming the value: a figure path (the message lists the
     ones that exist), an axis path, range, value the scenario refuses, an algorithm, --runs, a tcp
     host, a monitor section, a malformed search section (file:line), a scenario that does not run
     as written (the run's own message).

  7. --symbols reaches every run: their causes name the ROM's routines, and the witness's command
     carries it.

Usage: search_cli_test.py RCSIM KAT_ROM SOURCE_DIR WORK_DIR SYMBOLS_ROM SYMBOLS_MAP
"""
import json
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import check, failures  # noqa: E402

RCSIM, KAT_ROM, SRC, W, SYM_ROM, SYM_MAP = sys.argv[1:7]
# search_kat.asm: C + 1 clocks, C = 57 + 3028 + 33 + 12 + 53 = 3183, one clock = 125 ns (8 MHz).
ANALYTIC_MAX_US = (57 + 3028 + 33 + 12 + 53 + 1) * 0.125
KAT_RUNS = 32  # docs/search.md "A known answer"
FIGURE = "interrupts.rs232_1.latency_us.max"
AXIS = "ports[1].send[0].at_ms=9.5..11.5"

shutil.rmtree(W, ignore_errors=True)
os.makedirs(W)
os.chdir(W)
shutil.copy(KAT_ROM, "search_kat.bin")
shutil.copy(os.path.join(SRC, "tests/scenarios/search/search_kat.yaml"), "search_kat.yaml")


def rcsim(*args):
    p = subprocess.run([RCSIM] + list(args), capture_output=True, text=True, timeout=600)
    return p.returncode, p.stdout, p.stderr


def load(path):
    with open(path) as f:
        return json.load(f)


def search(out, *extra):
    return rcsim("search", "search_kat.yaml", "--maximize", FIGURE, "--axis", AXIS, "--runs", str(KAT_RUNS),
                 "--out", out, "--reproducible", *extra)


# 1. The known answer.
code, out, err = search("kat", "--jobs", "2")
check(code == 0, "search exits 0 (%d: %s)" % (code, err.strip()[-300:]))
s = load("kat/search.json")
best = s["best"]["value"]
check(best >= 0.99 * ANALYTIC_MAX_US, "within 1 %% of the analytic maximum %.3f us: %.3f" % (ANALYTIC_MAX_US, best))
check(best <= ANALYTIC_MAX_US, "never above the analytic maximum: %.3f" % best)
check(s["runs"] <= KAT_RUNS and len(s["history"]) == s["runs"], "at most --runs runs, each in the history")
check(s["base"] is not None and s["base"] < 10, "the scenario as written (T1 = 11 ms) is the entry only: %s" % s["base"])
check("best: %s = %.3f" % (FIGURE, best) in out, "the last lines name the best: " + out.strip())

# 2. The witness.
code, _, err = rcsim("run", "kat/worst.yaml", "--out", "rep", "--reproducible")
check(code == 0, "the witness runs (%d %s)" % (code, err.strip()[-200:]))
witness = "kat/runs/%s/report.json" % s["best"]["run"]
with open(witness) as a, open("rep/report.json") as b:
    check(a.read() == b.read(), "rcsim run worst.yaml gives the witness's report.json byte for byte")
rep = load("rep/report.json")
check(rep["interrupts"]["rs232_1"]["latency_us"]["max"] == best, "the same figure to the last digit")
check(rep["interrupts"]["rs232_1"]["worst"][0]["text"] in s["best"]["cause"], "the same cause")

# 3. search.json; the same seed, the same search, whatever --jobs; --minimize.
check(s["figure"] == FIGURE and s["direction"] == "maximize" and s["algorithm"] == "subplex", "figure, direction, algorithm")
values = [h["best_so_far"] for h in s["history"] if h["best_so_far"] is not None]
check(all(a <= b for a, b in zip(values, values[1:])), "best so far never falls")
check(values[-1] == best, "the last best so far is the best")
check([a["path"] for a in s["axes"]] == ["ports[1].send[0].at_ms"], "the --axis only")
code, _, _ = search("kat1", "--jobs", "1")
s1 = load("kat1/search.json")
check(s1["best"].pop("reproduce") == "rcsim run kat1/worst.yaml", "the command that reproduces it names its --out")
s["best"].pop("reproduce")
check(code == 0 and s1 == s, "the same search.json with --jobs 1 and --jobs 2 (but the --out in its command)")
code, _, _ = rcsim("search", "search_kat.yaml", "--minimize", FIGURE, "--axis", AXIS, "--runs", "8", "--out", "min")
m = load("min/search.json")
lows = [h["best_so_far"] for h in m["history"] if h["best_so_far"] is not None]
check(code == 0 and m["direction"] == "minimize" and all(a >= b for a, b in zip(lows, lows[1:])), "--minimize: best so far never rises")
check(m["best"]["value"] == min(h["value"] for h in m["history"] if h["value"] is not None), "--minimize keeps the least")

# 4. The search: section.
with open("search_kat.yaml") as f:
    text = f.read()
with open("sectioned.yaml", "w") as f:
    f.write(text + "search:\n  axes:\n    ports[1].send[0].at_ms: [9.5, 11.5]\n  algorithm: cobyla\n")
code, _, err = rcsim("search", "sectioned.yaml", "--maximize", FIGURE, "--runs", "6", "--out", "sec")
sec = load("sec/search.json")
check(code == 0 and [a["path"] for a in sec["axes"]] == ["ports[1].send[0].at_ms"] and sec["algorithm"] == "cobyla",
      "the section's axes and algorithm (%d %s)" % (code, err.strip()[-200:]))
with open("sec/worst.yaml") as f:
    check("search:" not in f.read(), "the witness carries no search section")

# 5. The page.
with open("kat/search.html") as f:
    page = f.read()
check(page.count("<svg") == 2, "search.html: two charts")
check('href="worst.yaml"' in page and 'href="runs/%s/report.html"' % s["best"]["run"] in page, "links the witness and its report")
check("isr_port0" in page or "rs232_0" in page, "shows what held the interrupt")


# 6. Bad input: exit 2, one message.
def bad(what, args, *needles):
    code, out, err = rcsim(*args)
    ok = code == 2 and all(n in err for n in needles) and "Traceback" not in err
    check(ok, "%s: exit 2 naming %s (%d: %s)" % (what, needles, code, err.strip()[-300:]))


kat = ["search", "search_kat.yaml", "--out", "bad", "--runs", "4"]
bad("a figure path", kat + ["--maximize", "interrupts.rs232_9.latency_us.max", "--axis", AXIS],
    "interrupts.rs232_9.latency_us.max", "interrupts.rs232_1.latency_us.max")
bad("an axis path", kat + ["--maximize", FIGURE, "--axis", "ports[7].send[0].at_ms=1..2"], "ports[7]")
bad("an axis range", kat + ["--maximize", FIGURE, "--axis", "ports[1].send[0].at_ms=2..1"], "above the high end")
bad("an axis text", kat + ["--maximize", FIGURE, "--axis", "seed"], "PATH=LO..HI")
bad("a value the scenario refuses", kat + ["--maximize", FIGURE, "--axis", "board.wait_states.rom=0..99"],
    "board.wait_states.rom", "99")
bad("an algorithm", kat + ["--maximize", FIGURE, "--algorithm", "simplex"], "simplex")
bad("--runs 1", ["search", "search_kat.yaml", "--out", "bad", "--runs", "1", "--maximize", FIGURE], "--runs")
bad("no figure", kat, "--maximize")
with open("tcp.yaml", "w") as f:
    f.write("duration_s: 0.1\nports:\n  - {host: tcp}\n")
bad("a tcp host", ["search", "tcp.yaml", "--out", "bad", "--maximize", FIGURE], "tcp")
with open("bad.rom", "wb") as f:
    f.write(b"\x90\x90\x90")
bad("a scenario that does not run", kat + ["--maximize", FIGURE, "--axis", AXIS, "--rom", "bad.rom"],
    "the scenario as written ended without a report", "bad.rom")
check(not os.path.exists("bad/runs/sample-001"), "nothing but the scenario as written ran")
with open("monitor.yaml", "w") as f:
    f.write(text + "monitor: {listen: '127.0.0.1:0'}\n")
bad("a monitor section", ["search", "monitor.yaml", "--out", "bad", "--maximize", FIGURE, "--axis", AXIS], "monitor")
with open("badsec.yaml", "w") as f:
    f.write(text + "search:\n  algorithm: simplex\n")
bad("a search section", ["search", "badsec.yaml", "--out", "bad", "--maximize", FIGURE], "badsec.yaml:", "simplex")

# 7. --symbols (tests/scenarios/cli/symbols_rom.asm: its interrupt waits in hold_if with IF = 0).
code, _, err = rcsim("search", os.path.join(SRC, "tests/scenarios/cli/symbols_alone.yaml"), "--rom", SYM_ROM, "--symbols", SYM_MAP,
                     "--maximize", "interrupts.rs232_0.latency_us.max", "--axis", "seed=1..3", "--runs", "3", "--out", "sym")
sym = load("sym/search.json")
check(code == 0 and "--symbols " + SYM_MAP in sym["best"]["reproduce"], "--symbols: the witness's command carries it (%d %s)"
      % (code, err.strip()[-200:]))
check(all(load("sym/runs/%s/report.json" % h["run"])["symbols"]["file"] == os.path.basename(SYM_MAP) for h in sym["history"]),
      "--symbols: every run read the map")
check("hold_if" in sym["best"]["cause"], "--symbols: the cause names the routine: " + sym["best"]["cause"])

sys.exit(1 if failures else 0)
