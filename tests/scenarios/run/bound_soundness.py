#!/usr/bin/env python3
"""The static bound is sound (issue #47 item 6): in every run given, no observed service, blocking
time or latency of any source exceeds its bound from `rcsim run --bound`. A service of a handler that
re-enables interrupts includes the services nested in it (docs/scenarios.md), which its bound leaves
out, so only handlers that keep IF = 0 to their IRET are compared on their service.

Usage: bound_soundness.py RCSIM WORK SCENARIO[:SECONDS] ...   (SECONDS cuts the scenario's duration)
Prints each run's tightest ratio observed / bound per figure; exit 1 on any figure over its bound.
"""
import json
import os
import re
import subprocess
import sys

rcsim, work = sys.argv[1], sys.argv[2]
failures = []
for spec in sys.argv[3:]:
    path, _, seconds = spec.partition(":")
    name = os.path.splitext(os.path.basename(path))[0]
    out = os.path.join(work, name)
    scenario = path
    if seconds:  # the same scenario with its top-level duration_s cut (it names no relative path)
        with open(path) as f:
            text, n = re.subn(r"(?m)^duration_s:.*$", "duration_s: " + seconds, f.read())
        if n != 1:
            sys.exit(f"{path}: no top-level duration_s to cut")
        os.makedirs(work, exist_ok=True)
        scenario = os.path.join(work, name + ".yaml")
        with open(scenario, "w") as f:
            f.write(text)
    run = subprocess.run([rcsim, "run", scenario, "--bound", "--out", out, "--reproducible"],
                         capture_output=True, text=True)
    if run.returncode not in (0, 1):
        failures.append(f"{name}: rcsim run exited {run.returncode}: {run.stderr.strip()}")
        continue
    with open(os.path.join(out, "report.json")) as f:
        report = json.load(f)
    with open(os.path.join(out, "bound.json")) as f:
        bound = json.load(f)
    tightest = {}
    for source, b in report["bound"]["sources"].items():
        figures = ["blocking", "latency"]
        if not bound["sources"][source]["reenables_interrupts"]:
            figures.append("service")
        for fig in figures:
            observed, limit = b[f"observed_{fig}_us"], b[f"bound_{fig}_us"]
            if observed is None:
                continue
            if observed > limit:
                failures.append(f"{name}: {source} observed {fig} {observed} us over its bound {limit} us")
            tightest[f"{source}.{fig}"] = round(observed / limit, 3)
    print(name, json.dumps(tightest, sort_keys=True))

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
