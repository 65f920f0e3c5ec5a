#!/usr/bin/env python3
"""Issue #49 "Done when": the shipped scenario with a CSP path misses no SYNC over seeds 1-10.

usage: csp_seeds_test.py RCSIM SWEEP OUTDIR

Runs the sweep (csp_seeds.yaml) through the real binary: it must exit 0, and every run's report
must hold the csp_missed_sync check with 0 missed SYNCs out of a non-zero number of set-points
(so a run where the check went missing, or the path never started, cannot pass)."""
import glob
import json
import os
import shutil
import subprocess
import sys


def main():
    rcsim, sweep, out = sys.argv[1:4]
    shutil.rmtree(out, ignore_errors=True)
    r = subprocess.run([rcsim, "sweep", sweep, "--out", out, "--jobs", "2"], capture_output=True, text=True)
    if r.returncode != 0:
        print(r.stdout, r.stderr)
        sys.exit(f"FAIL: the sweep exited {r.returncode}")
    reports = sorted(glob.glob(os.path.join(out, "*", "report.json")))
    if len(reports) != 10:
        sys.exit(f"FAIL: {len(reports)} reports, wanted 10 (seeds 1-10)")
    for path in reports:
        with open(path) as f:
            j = json.load(f)
        csp = j["motion"]["csp"]
        check = [c for c in j["checks"] if c["name"] == "csp_missed_sync"]
        if not check or check[0]["status"] != "passed" or csp["missed_sync"] != 0 or csp["setpoints"] == 0:
            sys.exit(f"FAIL: {path}: csp {csp}, check {check}")
    print("ok: 10 seeds, no SYNC missed")


if __name__ == "__main__":
    main()
