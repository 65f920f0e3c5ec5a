#!/usr/bin/env python3
"""Runs one scenario through the real rcsim binary and asserts its verdict.

usage: check_case.py [--rom ROM] [--symbols MAP] [--report KEY=JSON ...] RCSIM SCENARIO OUTDIR EXIT
                     [FAILING_CHECK[=STATUS] ...] [--expect=EXPR ...]

EXIT is the expected exit code (0 every check holds, 1 a check failed, 4 inconclusive: none failed
but one was not measured). The FAILING_CHECKs are exactly the checks that do not hold (all others
must pass), each optionally with the status it must report ("failed" or "not measured"; default
"failed"). The verdict follows from them (FAILED when one failed, else INCONCLUSIVE when one was not
measured, else PASSED) and is asserted in all three places a user reads it: the exit code,
report.json (`verdict`, `passed`, each check's `passed` and `status`) and the printed summary (a
FAIL or ---- line naming the check, and the verdict line PASSED, FAILED: ... or INCONCLUSIVE: ...).

--rom runs the scenario with that ROM image (--symbols: its symbols); each --report KEY=JSON asserts one report.json value,
KEY a dotted path (list elements by index: bus_errors.first.0.address), JSON its value.
Each --html=TEXT must appear in report.html. Each --expect=EXPR is a Python expression that must be true of the report, with `report`,
`ports` (report["ports"]), `main` (report["main_cpu"]["ports"]), `why(NAME)` (the failed
check's explanation, "" without one) and `summary` (what rcsim printed) in scope: it states what the figures must be from the
scenario's design, e.g. that two independent counters agree."""
import json
import os
import subprocess
import sys


def report_value(report, key):
    v = report
    for part in key.split("."):
        v = v[int(part)] if isinstance(v, list) else v[part]
    return v


def main():
    args = sys.argv[1:]
    extra, report_wants = [], []
    while args and args[0] in ("--rom", "--symbols", "--report"):
        if args[0] in ("--rom", "--symbols"):
            extra += [args[0], args[1]]
        else:
            key, _, value = args[1].partition("=")
            report_wants.append((key, json.loads(value)))
        args = args[2:]
    rcsim, scenario, out, want_exit = args[:4]
    want = {}
    expects, htmls = [], []
    for arg in args[4:]:
        if arg.startswith("--expect="):
            expects.append(arg[len("--expect="):])
            continue
        if arg.startswith("--html="):
            htmls.append(arg[len("--html="):])
            continue
        name, _, status = arg.partition("=")
        want[name] = status or "failed"
    run = subprocess.run([rcsim, "run", scenario, "--out", out, "--reproducible"] + extra,
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
    problems = []
    if run.returncode != int(want_exit):
        problems.append(f"exit {run.returncode}, expected {want_exit}")
    try:
        with open(os.path.join(out, "report.json")) as f:
            report = json.load(f)
    except (OSError, ValueError) as e:
        print(run.stdout)
        print(f"FAIL: no readable report.json: {e}")
        return 1
    checks = {c["name"]: c for c in report["checks"]}
    failing = {n: c.get("status", "failed") for n, c in checks.items() if not c["passed"]}
    for name, status in want.items():
        if name not in checks:
            problems.append(f"check {name} is not in the report")
        elif name not in failing:
            problems.append(f"check {name} passed, expected it to fail ({status})")
        elif failing[name] != status:
            problems.append(f"check {name} is '{failing[name]}', expected '{status}'")
        else:
            mark = "FAIL" if status == "failed" else "----"
            if f"{mark}  {name}" not in run.stdout:
                problems.append(f"the summary has no '{mark}  {name}' line")
    for name in failing:
        if name not in want:
            problems.append(f"check {name} failed too ({failing[name]}): {checks[name]}")
    verdict_want = ("failed" if any(s == "failed" for s in want.values()) else
                    "inconclusive" if want else "passed")
    if report.get("verdict") != verdict_want:
        problems.append(f"report.json verdict = {report.get('verdict')!r}, expected {verdict_want!r}")
    if report["passed"] != (verdict_want == "passed"):
        problems.append(f"report.json passed = {report['passed']}")
    for key, value in report_wants:
        try:
            got = report_value(report, key)
        except (KeyError, IndexError, ValueError, TypeError):
            got = "(missing)"
        if got != value:
            problems.append(f"report.json {key} = {got!r}, expected {value!r}")
    scope = {"report": report, "ports": report.get("ports", []),
             "main": report.get("main_cpu", {}).get("ports", []),
             "why": lambda name: checks.get(name, {}).get("why", ""),
             "summary": run.stdout}
    for expr in expects:
        try:
            ok = eval(expr, {"__builtins__": {"all": all, "any": any, "sum": sum, "len": len, "range": range}}, scope)
        except Exception as e:  # a key the report lacks is a failure, not a crash
            ok = False
            expr += f"  ({type(e).__name__}: {e})"
        if not ok:
            problems.append(f"expected: {expr}")
    try:
        with open(os.path.join(out, "report.html")) as f:
            html = f.read()
    except OSError:
        html = ""
    for text in htmls:
        if text not in html:
            problems.append(f"report.html lacks {text!r}")
    verdict = [l for l in run.stdout.splitlines()
               if l == "PASSED" or l.startswith("FAILED: ") or l.startswith("INCONCLUSIVE: ")]
    if len(verdict) != 1 or verdict[0].split(":")[0] != verdict_want.upper():
        problems.append(f"the summary's verdict lines are {verdict}, expected {verdict_want.upper()}")
    if problems:
        print(run.stdout)
        for p in problems:
            print("FAIL:", p)
        return 1
    print(f"ok: {os.path.basename(scenario)} exit {run.returncode}, failing {sorted(failing) or 'none'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
