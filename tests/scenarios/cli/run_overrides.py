#!/usr/bin/env python3
"""`rcsim run ... --duration S --realtime [FACTOR]` over the scenario's own duration_s and realtime
(issue #51 item 2), the summary's simulated times as seconds in groups of three (item 3) and
its last lines, the report paths, a motion run's report.html included (item 7).

usage: run_overrides.py RCSIM SOURCE_DIR"""
import json
import os
import re
import subprocess
import sys
import tempfile
import time
import urllib.request

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
import rcsim_test  # noqa: E402
from rcsim_test import HANG_S, check, failures  # noqa: E402


def seconds_text(us):
    """Issue #51 item 3's form, written here from its example (1466138.750 us = "1.466 138 750 s"):
    whole seconds, then groups of three digits (ms, us, ns), trailing all-zero groups left out but
    the millisecond one."""
    ns = round(us * 1000)
    groups = ["%03d" % (ns // 1000000 % 1000), "%03d" % (ns // 1000 % 1000), "%03d" % (ns % 1000)]
    while len(groups) > 1 and groups[-1] == "000":
        groups.pop()
    return "%d.%s s" % (ns // 1000000000, " ".join(groups))


def texts(j):
    """Every "text" and "why" string in a report."""
    if isinstance(j, dict):
        for k, v in j.items():
            if k in ("text", "why") and isinstance(v, str):
                yield v
            else:
                yield from texts(v)
    elif isinstance(j, list):
        for v in j:
            yield from texts(v)


def run(rcsim, *args):
    p = subprocess.run([rcsim, "run", *args], capture_output=True, text=True, timeout=HANG_S)
    return p.returncode, p.stdout, p.stderr


def report_paths_last(out, d, what):
    """The summary's last two lines name report.json and report.html, and both exist."""
    last = out.rstrip("\n").split("\n")[-2:]
    check(last == ["report: %s/report.json" % d, "html:   %s/report.html" % d],
          "%s: the summary ends with its report paths (got %r)" % (what, last))
    check(os.path.isfile(os.path.join(d, "report.html")), "%s: report.html is written" % what)


def duration_and_times(rcsim, scenario, w):
    d = os.path.join(w, "half")
    code, out, err = run(rcsim, scenario, "--duration", "0.5", "--out", d, "--reproducible")
    # A quarter of the file's run delivers fewer frames than its check asks: FAILED (exit 1) is right.
    check(code in (0, 1), "--duration 0.5: the run ends with a verdict (exit %d: %s)" % (code, err.strip()))
    if code not in (0, 1):
        return
    r = json.load(open(os.path.join(d, "report.json")))
    # The file says duration_s 2.0; the run stops its hosts at 0.5 s and drains at most drain_s 1 s.
    check(0.5 <= r["sim_time_s"] < 1.5, "--duration 0.5: a report of 0.5 s plus the drain (sim_time_s %g)" % r["sim_time_s"])
    check("simulated %s" % seconds_text(r["sim_time_s"] * 1e6) in out.split("\n")[0],
          "the summary's simulated time in seconds, groups of three: %r" % out.split("\n")[0])
    enabled = r["interrupts"]["startup"]["interrupts_enabled_us"]
    check("interrupts first enabled at %s" % seconds_text(enabled) in out,
          "the start-up instant as %s" % seconds_text(enabled))
    worst = r["interrupts"]["rs232_0"]["worst"][0]
    check(re.search(r"rs232_0 latency max [0-9.]+ us at %s: " % re.escape(seconds_text(worst["ir_rise_us"])), out),
          "the longest latency's instant as %s" % seconds_text(worst["ir_rise_us"]))
    # The explanations quoted from report.json ("text", "why") are the judge's, not the summary's.
    own = out
    for quoted in sorted(texts(r), key=len, reverse=True):
        own = own.replace(quoted, "")
    check(not re.search(r"at [0-9]+\.[0-9]+ (us|ms)\b", own), "no instant of the summary's own in us or ms")
    report_paths_last(out, d, "a board run")


def realtime_and_monitor(rcsim, scenario, w):
    """--realtime alone paces at 1: a second simulated takes a wall second at least; --monitor
    serves the page meanwhile."""
    d = os.path.join(w, "paced")
    t0 = time.monotonic()
    run_ = rcsim_test.Rcsim(rcsim, ["run", scenario, "--duration", "1", "--out", d, "--monitor", "127.0.0.1:0",
                                    "--realtime"], {"monitor": r"monitor: (http://127\.0\.0\.1:\d+/)"})
    try:
        with urllib.request.urlopen(run_.found["monitor"].group(1), timeout=HANG_S) as page:
            check(page.status == 200 and b"<html" in page.read().lower(), "--monitor serves the page while the paced run goes on")
    except OSError as e:
        check(False, "--monitor serves the page while the paced run goes on (%s)" % e)
    code, out, err = run_.finish(timeout=HANG_S)
    wall = time.monotonic() - t0
    check(code in (0, 1), "--realtime: the run ends with a verdict (exit %d: %s)" % (code, err.strip()))
    # The lower bound is the pacing; the upper one only a generous bound of a loaded machine.
    check(1.0 <= wall < 30, "--duration 1 --realtime: %.2f s of wall time, about 1 s" % wall)
    if code in (0, 1):
        r = json.load(open(os.path.join(d, "report.json")))
        check(r.get("realtime", {}).get("rtf_target") == 1, "--realtime alone: report.json realtime.rtf_target 1")
    d = os.path.join(w, "fast")
    code, out, err = run(rcsim, scenario, "--duration", "0.01", "--realtime", "50", "--out", d, "--reproducible")
    r = json.load(open(os.path.join(d, "report.json"))) if code in (0, 1) else {}
    check(r.get("realtime", {}).get("rtf_target") == 50, "--realtime 50: rtf_target 50 (exit %d %s)" % (code, err.strip()))


def motion(rcsim, source, w):
    circle = os.path.join(source, "scenarios", "xy_plotter_circle.yaml")
    d = os.path.join(w, "motion")
    code, out, err = run(rcsim, circle, "--duration", "0.3", "--out", d, "--reproducible")
    # The circle is not finished at 0.3 s: its checks fail (exit 1), the run itself is what counts.
    check(code in (0, 1), "a motion run with --duration 0.3 ends (exit %d: %s)" % (code, err.strip()))
    r = json.load(open(os.path.join(d, "report.json")))
    check(r["motion"]["duration_s"] == 0.3, "--duration 0.3 is the motion plan's duration_s (%r)" % r["motion"]["duration_s"])
    report_paths_last(out, d, "a motion run")
    code, _, err = run(rcsim, circle, "--realtime", "1", "--out", os.path.join(w, "motion_paced"))
    check(code == 2 and "--realtime" in err and "motion" in err, "a motion run refuses --realtime (exit %d: %s)" % (code, err.strip()))


def bad_values(rcsim, scenario, w):
    for args, named in [(["--duration", "0"], "'0'"), (["--duration", "-1"], "'-1'"),
                        (["--duration", "3601"], "'3601'"),  # the one-hour cap
                        (["--duration", "nan"], "'nan'"), (["--duration", "1s"], "'1s'"),
                        (["--realtime", "0.001"], "'0.001'"), (["--realtime", "-1"], "'-1'"),
                        (["--realtime", "inf"], "'inf'"), (["--realtime", "fast"], "'fast'")]:
        code, _, err = run(rcsim, scenario, "--out", os.path.join(w, "bad"), *args)
        check(code == 2 and named in err and args[0] in err,
              "%s: exit 2 naming the value (exit %d: %s)" % (" ".join(args), code, err.strip()))


def main():
    rcsim, source = os.path.realpath(sys.argv[1]), sys.argv[2]
    scenario = os.path.join(source, "scenarios", "three_ports_9600.yaml")
    with tempfile.TemporaryDirectory(prefix="rcsim_run_overrides.") as w:
        duration_and_times(rcsim, scenario, w)
        realtime_and_monitor(rcsim, scenario, w)
        motion(rcsim, source, w)
        bad_values(rcsim, scenario, w)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
