"""The tcp host under abuse (issue #33 item 4; docs/serial.md "Connecting your own tools"), through
the rcsim executable: a client that resets its connection, then one that floods far faster than the
line carries and never reads. The run goes on, its memory stays bounded (the input queue holds
4 KiB; TCP flow control holds the client back), it ends at its duration with the verdict of an idle run, and report.json
and the summary say how many bytes never reached the line. A second run ends by SIGTERM within a
second while such a client floods: exit 143, report.json verdict interrupted.

The bytes are printable ASCII from a fixed seed: the firmware ignores them (no ENQ), so the verdict
does not depend on how many of them reach the line in the wall time the run takes.

usage: flood_test.py RCSIM"""
import json
import os
import random
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import check, failures, rss_kib, wait_for  # noqa: E402


def start(rcsim, tmp, name, duration):
    scenario = os.path.join(tmp, name + ".yaml")
    with open(scenario, "w") as f:
        f.write("name: %s\nduration_s: %s\nports:\n"
                "  - {host: tcp, format: \"9600,8E1\", listen: \"127.0.0.1:0\", port_file: port}\n" % (name, duration))
    out = os.path.join(tmp, name)
    err = tempfile.TemporaryFile(mode="w+")
    proc = subprocess.Popen([rcsim, "run", scenario, "--out", out], stdout=subprocess.PIPE, stderr=err, text=True)
    port_file = os.path.join(out, "port")
    wait_for(lambda: os.path.exists(port_file), proc, timeout=20)
    with open(port_file) as f:
        return proc, out, int(f.read()), err


def connect(port, rcvbuf=None):
    s = socket.socket()
    if rcvbuf:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, rcvbuf)  # never read: fills at once
    s.connect(("127.0.0.1", port))
    return s


def flood(s, proc, until, data):
    """Sends without blocking until `until` or the run ends; (bytes sent, peak RSS in KiB)."""
    s.setblocking(False)
    sent, peak = 0, 0
    while time.monotonic() < until and proc.poll() is None:
        try:
            sent += s.send(data)
        except BlockingIOError:
            time.sleep(0.005)
        except OSError:
            break
        peak = max(peak, rss_kib(proc.pid))
    return sent, peak


def flooded_run(rcsim, tmp, rng):
    proc, out, port, err = start(rcsim, tmp, "tcp_flood", 4)
    printable = bytes(rng.randrange(0x20, 0x7F) for _ in range(65536))
    # A client that sends a little and resets its connection (no FIN).
    a = connect(port)
    a.sendall(printable[:2000])
    time.sleep(0.2)
    a.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
    a.close()
    time.sleep(0.2)
    # The next one floods and never reads.
    b = connect(port, rcvbuf=4096)
    time.sleep(0.1)
    before = rss_kib(proc.pid)
    sent, peak = flood(b, proc, time.monotonic() + 10, printable)
    stdout, _ = proc.communicate(timeout=30)
    b.close()
    # INCONCLUSIVE, as with no client at all: nothing the firmware forwards, so no DP-RAM figure.
    check(proc.returncode == 4, "the flooded run ends at its duration, INCONCLUSIVE as an idle one (exit %d)"
          % proc.returncode)
    growth = (peak - before) / 1024
    if os.environ.get("RCSIM_SANITIZED"):  # ASan's quarantine holds freed memory (CMakeLists.txt)
        print("--    memory bound not judged in a sanitizer build: peak %.0f MB" % (peak / 1024))
    else:
        check(growth < 32, "its memory stays bounded while %.1f MB are offered: RSS %.0f -> %.0f MB"
              % (sent / 1e6, before / 1024, peak / 1024))
    with open(os.path.join(out, "report.json")) as f:
        r = json.load(f)
    t = dict({"bytes_unsent": 0, "input_stalls": 0}, **r["ports"][0]["tcp"])
    print("      ports[0].tcp = %s" % json.dumps(t))
    check(r["verdict"] == "inconclusive", "report.json verdict inconclusive (%s)" % r["verdict"])
    check(t["connections"] == 2, "both clients were served (%d connections)" % t["connections"])
    check(t["bytes_in"] <= 2000 + sent and t["bytes_sent"] <= t["bytes_in"], "bytes_in and bytes_sent are what was sent")
    check(t["bytes_unsent"] >= t["bytes_in"] - t["bytes_sent"] > 0,
          "bytes_unsent (%d) counts at least what was read and never put on the line (%d)"
          % (t["bytes_unsent"], t["bytes_in"] - t["bytes_sent"]))
    check(t["input_stalls"] > 0, "the full input queue held the client back (%d stalls)" % t["input_stalls"])
    check(t["bytes_in"] - t["bytes_sent"] <= 4096 + 1024, "at most 4 KiB and one read wait for the line")
    warned = [w for w in r["warnings"] if "never reached the line" in w]
    check(len(warned) == 1, "report.json warns that bytes never reached the line: %s" % warned)
    check("never reached the line" in stdout, "so does the summary")


def signalled_run(rcsim, tmp, rng):
    proc, out, port, err = start(rcsim, tmp, "tcp_term", 60)
    c = connect(port, rcvbuf=4096)
    data = bytes(rng.randrange(0x20, 0x7F) for _ in range(65536))
    flood(c, proc, time.monotonic() + 1.0, data)
    t0 = time.monotonic()
    proc.send_signal(signal.SIGTERM)
    try:
        flood(c, proc, time.monotonic() + 5, data)  # the client keeps at it
        proc.communicate(timeout=5)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
    took = time.monotonic() - t0
    c.close()
    check(proc.returncode == 143, "SIGTERM ends the run while the client floods: exit 143 (got %s)" % proc.returncode)
    check(took < 1.0, "within a second (%.2f s)" % took)
    try:
        with open(os.path.join(out, "report.json")) as f:
            verdict = json.load(f)["verdict"]
    except (OSError, ValueError) as e:
        verdict = str(e)
    check(verdict == "interrupted", "report.json is written, verdict interrupted (%s)" % verdict)


def main(rcsim):
    tmp = tempfile.mkdtemp(prefix="rcsim-tcp-flood-")
    rng = random.Random(33)
    try:
        flooded_run(rcsim, tmp, rng)
        signalled_run(rcsim, tmp, rng)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
