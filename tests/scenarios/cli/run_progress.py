#!/usr/bin/env python3
"""`rcsim run`'s progress line (docs/scenarios.md "Progress"): on a terminal (stderr a pseudo-
terminal here) one line rewritten in place, "\\r\\033[Krun T/TOTAL s  RTF R  ETA M:SS"; with stderr
redirected to a file nothing at all; and every file of the run the same bytes either way.

usage: run_progress.py RCSIM"""
import filecmp
import os
import pty
import re
import subprocess
import sys
import tempfile

# A minute simulated of a saturated port: some 3.5 s of wall time on the development machine, so
# that a redraw (every quarter second) comes even on a machine several times faster; four
# simulated seconds, as here before, had come down to 0.24 s as the simulator got faster, and a
# run could end before its first redraw.
SCENARIO = """duration_s: 60
drain_s: 0.05
ports:
  - {host: protocol, traffic: saturate, start_ms: 5, data_size: 16, tokens: {EC: 1}}
"""

LINE = re.compile(rb"\r\x1b\[Krun \d+\.\d/60\.0 s  RTF \d+\.\d\d  ETA \d+:\d\d")


def run_on_terminal(rcsim, scenario, out, env):
    """Runs rcsim with stdout and stderr on a pseudo-terminal; returns (exit code, what it wrote)."""
    pid, fd = pty.fork()
    if pid == 0:
        os.execve(rcsim, [rcsim, "run", scenario, "--out", out, "--reproducible"], env)
    text = b""
    while True:
        try:
            chunk = os.read(fd, 65536)
        except OSError:  # EIO: the child closed the terminal
            break
        if not chunk:
            break
        text += chunk
    _, status = os.waitpid(pid, 0)
    os.close(fd)
    return os.waitstatus_to_exitcode(status), text


def main():
    rcsim = os.path.realpath(sys.argv[1])
    failures = []
    with tempfile.TemporaryDirectory(prefix="rcsim_run_progress.") as w:
        scenario = os.path.join(w, "p.yaml")
        with open(scenario, "w") as f:
            f.write(SCENARIO)
        env = {k: v for k, v in os.environ.items() if k != "CI"}
        env["SC_COPYRIGHT_MESSAGE"] = "DISABLE"

        code, tty_text = run_on_terminal(rcsim, scenario, os.path.join(w, "tty"), env)
        if code != 0:
            failures.append("on a terminal: exit %d: %r" % (code, tty_text[-400:]))
        if not LINE.search(tty_text):
            failures.append("on a terminal: no progress line in %r" % tty_text[:400])
        # Erased before the summary: the summary's first line does not follow a progress line.
        if re.search(rb"ETA \d+:\d\dscenario", tty_text):
            failures.append("the progress line was not erased before the summary")

        with open(os.path.join(w, "err.txt"), "wb") as err:
            r = subprocess.run([rcsim, "run", scenario, "--out", os.path.join(w, "file"), "--reproducible"],
                               stdout=subprocess.DEVNULL, stderr=err, env=env, timeout=120)
        if r.returncode != 0:
            failures.append("stderr to a file: exit %d" % r.returncode)
        with open(os.path.join(w, "err.txt"), "rb") as err:
            err_text = err.read()
        if b"RTF" in err_text or b"\r" in err_text:
            failures.append("stderr to a file: a progress line: %r" % err_text[:400])

        cmp = filecmp.dircmp(os.path.join(w, "tty"), os.path.join(w, "file"))
        files = sorted(os.listdir(os.path.join(w, "file")))
        _, mismatch, errors = filecmp.cmpfiles(os.path.join(w, "tty"), os.path.join(w, "file"), files, shallow=False)
        if mismatch or errors or cmp.left_only or cmp.right_only:
            failures.append("the run's files differ with the progress line: %s %s %s %s"
                            % (mismatch, errors, cmp.left_only, cmp.right_only))
        if "report.json" not in files:
            failures.append("no report.json")

    for f in failures:
        print("FAIL: " + f)
    if not failures:
        print("run_progress: ok")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
