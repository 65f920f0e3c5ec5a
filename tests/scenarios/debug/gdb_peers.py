#!/usr/bin/env python3
"""Peers that are not debuggers on the port of `rcsim run --gdb` (issue #48 item 4; docs/tools.md
"gdb", "Who is a debugger").

usage: gdb_peers.py CASE RCSIM SCENARIO WORKDIR

The scenario is paced to real time (paced_run.yaml, 1.5 s).

CASE
  http   without --gdb-wait: an HTTP GET, then a peer that sends nothing, both kept open.
         Neither is a debugger: the board never stops for them, so the paced run ends on time
         (its duration plus MARGIN_S), exit 0; stderr names the GET as no debugger, and no
         debugger is told the run ended. (A stub that stopped the board on connection held it
         while the peers stayed.)
  flood  with --gdb-wait: a silent peer, dropped after 2 s; then 1000 peers that send noise,
         each until the stub closes it. None releases the wait (`monitor time` then says no
         simulated time has passed); a debugger attaches ('?': T05), detaches, and the run
         ends, exit 0. stderr has at most MAX_LINES lines: the connection lines are
         rate-limited, the rest counted.
"""
import json
import os
import re
import shutil
import socket
import sys
import time

from gdb_garbage import GDB_LISTENING, connect, frame, read_for  # the RSP framing and socket helpers
from rcsim_test import Rcsim  # tests/support, on the path since gdb_garbage's import

MARGIN_S = 1.5    # a paced run may end this much later than its duration
PEERS = 1000
MAX_LINES = 20    # stderr lines of the flood run: 8 connection lines a window, a count, the rest


def log_of(err):
    err.seek(0)
    return err.read()


def case_http(rcsim, scenario, work, duration):
    err = open(work + "/run.err", "w+")
    t0 = time.time()
    run = Rcsim(rcsim, ["run", scenario, "--out", work + "/out", "--reproducible", "--gdb", "127.0.0.1:0"],
                {"gdb": GDB_LISTENING}, stderr=err)
    port = int(run.found["gdb"].group(1))
    http = connect(port)
    http.sendall(b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
    silent = connect(port)  # stays, silent, beyond the run's end
    try:
        run.proc.communicate(timeout=duration + MARGIN_S + 10)
    except Exception:
        run.proc.kill()
        raise SystemExit("FAIL: the run did not end with the peers open\n" + log_of(err))
    took = time.time() - t0
    log = log_of(err)
    http.close()
    silent.close()
    assert run.proc.returncode == 0, "FAIL: rcsim exited %d\n%s" % (run.proc.returncode, log)
    assert took < duration + MARGIN_S, \
        "FAIL: the %.1f s paced run took %.2f s: a peer that is no debugger held the board\n%s" % (duration, took, log)
    assert 'dropped a peer that is not a debugger (its first bytes are no gdb packet: "GET / HTTP/1.1' in log, \
        "FAIL: the GET was not named as no debugger:\n" + log
    assert "debugger attached" not in log and "told the debugger" not in log, "FAIL: a peer was taken for a debugger:\n" + log
    print("an HTTP GET and a silent peer: dropped, the board ran on, the run ended on time (%.2f s)" % took)


def case_flood(rcsim, scenario, work, duration):
    err = open(work + "/run.err", "w+")
    run = Rcsim(rcsim, ["run", scenario, "--out", work + "/out", "--reproducible", "--gdb", "127.0.0.1:0",
                        "--gdb-wait"], {"gdb": GDB_LISTENING}, stderr=err)
    port = int(run.found["gdb"].group(1))
    # A silent peer first: dropped after 2 s, the wait not released.
    silent = connect(port)
    end = time.time() + 10
    while "sent no packet within 2 s" not in log_of(err) and time.time() < end:
        time.sleep(0.05)
    silent.close()
    assert "dropped a peer that sent no packet within 2 s (not a debugger)" in log_of(err), \
        "FAIL: the silent peer was not dropped:\n" + log_of(err)
    t0 = time.time()
    for i in range(PEERS):
        s = connect(port)
        s.sendall(b"garbage %d\r\n" % i)
        read_for(s, 5)  # until the stub closes it: one peer after the other
        s.close()
    flood_s = time.time() - t0
    s = connect(port)
    s.sendall(frame(b"?"))
    got = read_for(s, 10, until=b"#")
    assert b"$T05" in got, "FAIL: the debugger after the flood got no stop reply: %r\n%s" % (got, log_of(err))
    s.sendall(frame(b"qRcmd," + b"time".hex().encode()))
    got = read_for(s, 10, until=b"#")
    hexes = re.findall(rb"\$([0-9a-f]+)#", got)  # qRcmd's reply: the text in hex
    text = bytes.fromhex(hexes[0].decode()).decode() if hexes else ""
    # Held at the first instruction boundary all along: the SystemC kernel has not advanced.
    assert "(kernel 0.000 us)" in text, "FAIL: the board ran before the debugger came: %r" % text
    s.sendall(frame(b"D"))
    read_for(s, 5, until=b"$OK#")
    s.close()
    try:
        run.proc.communicate(timeout=duration + MARGIN_S + 10)
    except Exception:
        run.proc.kill()
        raise SystemExit("FAIL: the run did not end after the detach\n" + log_of(err))
    log = log_of(err)
    lines = log.splitlines()
    assert run.proc.returncode == 0, "FAIL: rcsim exited %d\n%s" % (run.proc.returncode, log)
    assert len(lines) <= MAX_LINES, "FAIL: %d peers wrote %d lines on stderr:\n%s" % (PEERS, len(lines), log)
    counted = sum(int(n) for n in re.findall(r"^gdb: (\d+) more connection lines", log, re.M))
    shown = len(re.findall(r"^gdb: dropped a peer that is not a debugger", log, re.M))
    assert shown + counted >= PEERS, "FAIL: %d shown + %d counted of %d peers:\n%s" % (shown, counted, PEERS, log)
    assert json.load(open(work + "/out/report.json")).get("interrupted") is not True, "FAIL: report says interrupted"
    print("%d peers sending noise in %.1f s: none released --gdb-wait, %d lines on stderr; the debugger then attached"
          % (PEERS, flood_s, len(lines)))


def main():
    case, rcsim, scenario, work = sys.argv[1:5]
    duration = float(re.search(r"^duration_s: *([0-9.]+)", open(scenario).read(), re.M).group(1))
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    {"http": case_http, "flood": case_flood}[case](rcsim, scenario, work, duration)


if __name__ == "__main__":
    main()
