#!/usr/bin/env python3
"""Garbage and disconnects on the socket of `rcsim run --gdb` (docs/tools.md "gdb").

usage: gdb_garbage.py RCSIM SCENARIO FW_JSON WORKDIR

1. A client attaches ('?'), sends line noise and a packet with a bad checksum: the stub answers '-' (appendix E:
   a retransmission request) and still answers the next good packet ('?': the stop reply T05).
   It sets a breakpoint at rs232_isr and drops the connection while the board is stopped.
2. A third of the run later a second client connects (the board stops for it), holds the board
   for HOLD_S, continues, stops it with Ctrl-C (0x03: the stop reply T02, SIGINT), continues,
   sends 20 KB of garbage and disconnects while the board runs. The breakpoint of the first client must be gone: no stop
   reply may arrive before the run ends.
The run must end by itself (exit 0), say on stderr what it ignored, and write the same
report.json as a run without gdb. The scenario is paced to real time: the held time must be left
out of the pacing, so the run lasts at least HOLD_S + its duration (were it counted, the run would
race to catch up and end HOLD_S early).
"""
import filecmp
import json
import os
import re
import shutil
import socket
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import Rcsim  # noqa: E402

# The line `rcsim run --gdb` prints once its stub listens.
GDB_LISTENING = r"gdb: listening on 127\.0\.0\.1:(\d+)"


def frame(payload: bytes) -> bytes:
    return b"$" + payload + b"#" + b"%02x" % (sum(payload) & 0xFF)


def read_for(sock, seconds, until=None):
    """Bytes received within `seconds` (or until `until` appears)."""
    sock.settimeout(0.05)
    got = b""
    end = time.time() + seconds
    while time.time() < end:
        try:
            chunk = sock.recv(65536)
        except socket.timeout:
            continue
        except OSError:  # reset by the stub (gdb_abuse.py drops clients on purpose)
            break
        if not chunk:
            break
        got += chunk
        if until and until in got:
            break
    return got


def connect(port):
    for _ in range(100):
        try:
            return socket.create_connection(("127.0.0.1", port), timeout=5)
        except OSError:
            time.sleep(0.05)
    raise SystemExit("FAIL: cannot connect to the stub")


HOLD_S = 1.0


def main():
    rcsim, scenario, fw_json, work = sys.argv[1:5]
    duration = float(re.search(r"^duration_s: *([0-9.]+)", open(scenario).read(), re.M).group(1))
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    isr = json.load(open(fw_json))["symbols"]["rs232_isr"]["linear"]
    subprocess.run([rcsim, "run", scenario, "--out", work + "/ref", "--reproducible"], check=True,
                   stdout=subprocess.DEVNULL)

    err = open(work + "/dbg.err", "w+")
    run = Rcsim(rcsim, ["run", scenario, "--out", work + "/dbg", "--reproducible", "--gdb", "127.0.0.1:0", "--gdb-wait"],
                {"gdb": GDB_LISTENING}, stderr=err)
    proc, port = run.proc, int(run.found["gdb"].group(1))

    # 1: a first packet (a debugger attaches with it, gdb_peers.py), noise, a bad checksum, then
    # good packets; disconnect while stopped.
    s = connect(port)
    t0 = time.time()
    s.sendall(frame(b"?"))
    got = read_for(s, 5, until=b"#")
    assert got.startswith(b"+$T05#"), "FAIL: no stop reply to the first packet: %r" % got
    s.sendall(b"hello\r\n" + b"$g#00")
    got = read_for(s, 5, until=b"-")
    assert b"-" in got, "FAIL: no '-' for a bad checksum: %r" % got
    s.sendall(frame(b"?"))
    got = read_for(s, 5, until=b"#")
    assert got.startswith(b"+$T05#"), "FAIL: no stop reply after the garbage: %r" % got
    s.sendall(frame(b"Z0,%x,1" % isr))
    got = read_for(s, 5, until=b"#")
    assert b"$OK#" in got, "FAIL: breakpoint not set: %r" % got
    s.close()
    time.sleep(duration / 3)

    # 2: a second debugger; it continues, sends garbage and goes away while the board runs.
    s = connect(port)
    s.sendall(frame(b"?"))
    got = read_for(s, 20, until=b"#")
    assert b"$T05" in got, "FAIL: the second client got no stop reply: %r" % got
    time.sleep(HOLD_S)
    s.sendall(frame(b"c"))
    got = read_for(s, 0.2)
    assert b"$T05" not in got, "FAIL: the first client's breakpoint survived its disconnect: %r" % got
    s.sendall(b"\x03")
    got = read_for(s, 20, until=b"#")
    assert b"$T02#" in got, "FAIL: no stop reply T02 to Ctrl-C: %r" % got
    s.sendall(frame(b"c"))
    s.sendall(b"$" + b"x" * 20000)
    got = read_for(s, duration / 3)
    assert b"$T05" not in got, "FAIL: the first client's breakpoint survived its disconnect: %r" % got
    s.close()

    rest, _ = proc.communicate(timeout=120)
    elapsed = time.time() - t0
    err.seek(0)
    log = err.read()
    assert proc.returncode == 0, "FAIL: rcsim exited %d\n%s" % (proc.returncode, log)
    assert elapsed >= HOLD_S + 0.9 * duration, \
        "FAIL: the paced run took %.2f s after a %.1f s hold: the hold was counted" % (elapsed, HOLD_S)
    assert "gdb: ignored a bad checksum from the debugger" in log, "FAIL: no note of the garbage:\n" + log
    assert log.count("the debugger disconnected; the run continues") == 2, "FAIL: disconnects:\n" + log
    assert filecmp.cmp(work + "/ref/report.json", work + "/dbg/report.json", shallow=False), \
        "FAIL: report.json differs"
    print("garbage and disconnects: answered, noted, the run went on; report unchanged")


if __name__ == "__main__":
    main()
