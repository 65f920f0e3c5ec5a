"""The `mbpoll` command lines of docs/monitor.md "Modbus TCP" (issue #51 item 6), run as the page
writes them against a run of tests/scenarios/modbus/board.yaml with --modbus: only the port, 1502 on the
page, is the run's. A line whose comment says "exception 02" must fail with mbpoll's "Illegal data
address"; every other must succeed. The reads at -r 1 and at -0 -r 0 both read address 0
(sim_time): the page's point about mbpoll's 1-based references.

usage: mbpoll_test.py RCSIM DOCS_MONITOR_MD SCENARIO"""
import os
import re
import shlex
import signal
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import HANG_S, check, failures  # noqa: E402
from mbrun import Rcsim  # noqa: E402

MARK = "CTest modbus.mbpoll runs these lines"


def doc_lines(page):
    """(command, comment) of each `$ mbpoll` line in the fenced block after the mark."""
    text = open(page, encoding="utf-8").read()
    at = text.find(MARK)
    if at < 0:
        return []
    block = re.search(r"```\n(.*?)```", text[at:], re.S).group(1)
    out = []
    for line in block.splitlines():
        m = re.match(r"\$ (mbpoll .*?)\s*(?:#\s*(.*))?$", line)
        if m:
            out.append((m.group(1), m.group(2) or ""))
    return out


def main(rcsim, page, scenario):
    lines = doc_lines(page)
    check(len(lines) >= 3 and any("exception 02" in c for _, c in lines),
          "docs/monitor.md has its mbpoll block, one line reading an unmapped address (%d lines)" % len(lines))
    run = Rcsim(rcsim, scenario)
    try:
        for cmd, comment in lines:
            check("-p 1502" in cmd, "the page's line uses the default port: " + cmd)
            argv = shlex.split(cmd.replace("-p 1502", "-p %d" % run.port))
            r = subprocess.run(argv, capture_output=True, text=True, timeout=HANG_S)
            said = r.stdout + r.stderr
            if "exception 02" in comment:
                ok = r.returncode != 0 and "Illegal data address" in said
                check(ok, "%s: exception 02, illegal data address (exit %d)" % (cmd, r.returncode))
            else:
                ok = r.returncode == 0 and "failed" not in said
                check(ok, "%s: exit %d" % (cmd, r.returncode))
            if not ok:
                print(said)
            if "-t 3:int" in cmd:
                first = "[0]:" if " -0 " in cmd else "[1]:"
                check(re.search(r"^\[[01]\]:\s+\d+", said, re.M) is not None and first in said,
                      "%s: reads sim_time as reference %s" % (cmd, first))
    finally:
        run.proc.send_signal(signal.SIGTERM)
        rc, _, err = run.finish(timeout=HANG_S)
    check(rc == 128 + signal.SIGTERM, "the run ends on SIGTERM (exit %d)" % rc)
    if failures:
        print(err)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2], sys.argv[3]))
