#!/usr/bin/env python3
"""rcsim bound and rcsim run --bound end to end (docs/tools.md "Bound", docs/scenarios.md).

Expected values come from the spec: the budget of three 9600 8E1 ports is one 11-bit character
time over 3 ports (11 / 9600 / 3 s = 381.944 us); the vectors 0x20..0x23 hold the four handlers
docs/firmware.md names (_isr_port0..2, _isr_dpram), at the addresses the firmware's map gives them; issue #47: the shipped ROM's blocking bounds fit (exit 0),
the frozen all-C ROM's do not (exit 1, naming the handler); bad input exits 2 with one line.

Usage: bound.py RCSIM COMM_FW_ROM COMM_FW_MAP COMM_FW_C_ROM COMM_FW_C_MAP TESTS_DIR
"""
import json
import os
import subprocess
import sys
import tempfile

RCSIM, ROM, MAP, ROM_C, MAP_C, HERE = sys.argv[1:7]
BUDGET_US = 11 / 9600 / 3 * 1e6
# The frozen all-C firmware's annotations, shipped beside its sources (it is not the built firmware,
# so nothing gives them by default).
ANNOTATIONS_C = os.path.join(HERE, "..", "..", "..", "comm_cpu", "firmware", "frozen_all_c", "bound.annotations")
HANDLERS = {"rs232_0": "_isr_port0", "rs232_1": "_isr_port1", "rs232_2": "_isr_port2", "dpram": "_isr_dpram"}


def map_offsets(path):
    """An ld86 map's symbols: NAME -> its offset in the ROM's segment F000."""
    offsets = {}
    with open(path) as f:
        for line in f:
            cols = line.split()
            if len(cols) == 5 and cols[4] in "Rr":
                offsets[cols[1]] = int(cols[3], 16)
    return offsets


OFFSETS = map_offsets(MAP)
SOURCES = {src: "F000:%04X" % OFFSETS[name] for src, name in HANDLERS.items()}
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


def rcsim(*args):
    env = dict(os.environ, SC_COPYRIGHT_MESSAGE="DISABLE")
    return subprocess.run([RCSIM, *args], capture_output=True, text=True, env=env)


def load(path):
    with open(path) as f:
        return json.load(f)


def bound_command(w):
    out = os.path.join(w, "shipped")
    p = rcsim("bound", ROM, "--out", out)
    check(p.returncode == 0, f"bound shipped ROM: exit {p.returncode}, expected 0: {p.stderr.strip()}")
    b = load(os.path.join(out, "bound.json"))
    check(abs(b["budget_us"] - BUDGET_US) < 1e-3, f"bound.json budget_us {b['budget_us']}, expected {BUDGET_US:.3f}")
    check(set(b["sources"]) == set(SOURCES), f"bound.json sources {sorted(b['sources'])}")
    for name, s in b["sources"].items():
        for key in ("service_us", "blocking_us", "latency_us", "path", "loops"):
            check(key in s, f"bound.json sources.{name} has no {key}")
        check(s.get("blocking_us", 1e9) <= b["budget_us"], f"shipped ROM: {name} blocking bound over the budget")
    check(os.path.isfile(os.path.join(out, "bound.txt")), "no bound.txt")
    check(p.stdout.startswith("bound: budget 381.9 us"), f"bound's output starts {p.stdout[:40]!r}")

    out_c = os.path.join(w, "all_c")
    p = rcsim("bound", ROM_C, "--symbols", MAP_C, "--annotations", ANNOTATIONS_C, "--out", out_c)
    check(p.returncode == 1, f"bound all-C ROM: exit {p.returncode}, expected 1: {p.stderr.strip()}")
    if p.returncode == 1:
        b = load(os.path.join(out_c, "bound.json"))
        over = [n for n, s in b["sources"].items() if s["blocking_us"] > b["budget_us"]]
        check(over, "all-C ROM: no source over the budget in bound.json")
        check("OVER BUDGET" in p.stdout and "over budget: " in p.stdout, f"all-C ROM output names no path: {p.stdout}")
        check(any(n in p.stdout for n in over), "all-C ROM output does not name the source over the budget")


def bad_input(w):
    bad = os.path.join(w, "bad.annotations")
    with open(bad, "w") as f:
        f.write("no_such_symbol iterations 3  # a name the map does not have\n")
    cases = {
        "missing ROM": ["bound", os.path.join(w, "nothing.rom"), "--out", os.path.join(w, "x")],
        "bad annotations": ["bound", ROM, "--annotations", bad, "--out", os.path.join(w, "y")],
        "no --out": ["bound", ROM],
        "run: --annotations without --bound": ["run", os.path.join(HERE, "bound_three_ports.yaml"), "--annotations", bad,
                                               "--out", os.path.join(w, "z")],
        "run: a bad --witness": ["run", os.path.join(HERE, "bound_three_ports.yaml"), "--bound", "--witness", bad,
                                 "--out", os.path.join(w, "v")],
    }
    for name, args in cases.items():
        p = rcsim(*args)
        check(p.returncode == 2, f"{name}: exit {p.returncode}, expected 2")
        check(p.stderr.count("\n") <= 2 and p.stderr.strip(), f"{name}: not one clear message: {p.stderr!r}")
    p = rcsim("bound", ROM, "--annotations", bad, "--out", os.path.join(w, "y"))
    check(bad in p.stderr, f"bad annotations: the message does not name the file: {p.stderr!r}")
    yaml = os.path.join(w, "bad_check.yaml")
    with open(os.path.join(HERE, "bound_check_on.yaml")) as f:
        text = f.read().replace("bound_service_us: on", "bound_service_us: maybe")
    with open(yaml, "w") as f:
        f.write(text)
    p = rcsim("run", yaml, "--out", os.path.join(w, "u"))
    check(p.returncode == 2 and "bound_service_us" in p.stderr, f"checks.bound_service_us: maybe: exit {p.returncode}")


def run_bound(w):
    witness = os.path.join(w, "search.json")
    with open(witness, "w") as f:
        json.dump({"figure": "interrupts.rs232_1.latency_us.max", "best": {"value": 321.5}}, f)
    out = os.path.join(w, "run")
    p = rcsim("run", os.path.join(HERE, "bound_three_ports.yaml"), "--bound", "--witness", witness, "--out", out,
              "--reproducible")
    check(p.returncode == 0, f"run --bound: exit {p.returncode}: {p.stderr.strip()}")
    r = load(os.path.join(out, "report.json"))
    check(os.path.isfile(os.path.join(out, "bound.json")), "run --bound wrote no bound.json")
    b = r.get("bound", {})
    check(abs(b.get("budget_us", 0) - BUDGET_US) < 1e-3, "report.json bound.budget_us")
    check(set(b.get("sources", {})) == set(SOURCES), f"report.json bound.sources {sorted(b.get('sources', {}))}")
    for name, s in b.get("sources", {}).items():
        check(s["handler_address"] == SOURCES[name], f"{name}: handler {s['handler_address']}, expected {SOURCES[name]}")
        check(s["vector"] == 0x20 + list(SOURCES).index(name), f"{name}: vector {s['vector']}")
        i = r["interrupts"][name]
        check(s["observed_service_us"] == i["service_us"]["max"], f"{name}: observed_service_us is not interrupts' max")
        check(s["observed_latency_us"] == i["latency_us"]["max"], f"{name}: observed_latency_us is not interrupts' max")
        check(s["observed_blocking_us"] <= s["observed_service_us"], f"{name}: observed blocking over its service")
        for key in ("bound_service_us", "bound_blocking_us", "bound_latency_us", "path", "loops"):
            check(key in s, f"report.json bound.sources.{name} has no {key}")
        check(s["searched_us"] == (321.5 if name == "rs232_1" else None), f"{name}: searched_us {s['searched_us']}")
    check(all(c["name"] != "bound_service_us" for c in r["checks"]), "bound_service_us judged though off by default")
    check("\nbound (us)" in p.stdout, "the summary has no bound table")
    with open(os.path.join(out, "report.html")) as f:
        check('<section id="bound">' in f.read(), "report.html has no bound section")


def check_on(w):
    scenario = os.path.join(HERE, "bound_check_on.yaml")
    p = rcsim("run", scenario, "--out", os.path.join(w, "on"), "--reproducible")
    r = load(os.path.join(w, "on", "report.json"))
    c = [c for c in r["checks"] if c["name"] == "bound_service_us"]
    check(p.returncode == 0 and c and c[0]["status"] == "passed", f"check on, shipped ROM: exit {p.returncode}, {c}")
    check("bound" in r, "the check on did not imply --bound")
    p = rcsim("run", scenario, "--rom", ROM_C, "--symbols", MAP_C, "--annotations", ANNOTATIONS_C,
              "--out", os.path.join(w, "on_c"), "--reproducible")
    r = load(os.path.join(w, "on_c", "report.json"))
    c = [c for c in r["checks"] if c["name"] == "bound_service_us"]
    check(p.returncode == 1 and c and c[0]["status"] == "failed", f"check on, all-C ROM: exit {p.returncode}, {c}")
    if c and c[0]["status"] == "failed":
        why = c[0].get("why", "")
        check(why.startswith("rs232_") and "budget" in why and " on a path of " in why, f"why: {why!r}")
        check(abs(c[0]["limit"] - BUDGET_US) < 1e-3, f"the check's limit {c[0]['limit']}")


with tempfile.TemporaryDirectory() as w:
    bound_command(w)
    bad_input(w)
    run_bound(w)
    check_on(w)
print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
