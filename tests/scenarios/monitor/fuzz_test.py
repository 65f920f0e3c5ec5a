"""The monitor's endpoint under abuse (issue #33; docs/monitor.md "Limits"), through
tests/scenarios/monitor/abuse.yaml: random bytes, truncated and oversized HTTP requests, a flood of idle HTTP
connections, broken, truncated and oversized WebSocket frames, random requests with random field
values, a client that floods requests, and one that subscribes and never reads. Throughout, a
witness client is answered and simulated time goes on, and the process's memory stays bounded;
at the end SIGTERM, while a client still floods, ends the run within a second with its report
(exit 143, verdict interrupted). Seeded: every run sends the same bytes.

usage: fuzz_test.py RCSIM SCENARIO"""
import json
import os
import random
import re
import shutil
import signal
import socket
import sys
import tempfile
import threading
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import check, failures, rss_kib, status_kib  # noqa: E402
from wsclient import Rcsim, WebSocket, ws_frame  # noqa: E402


class RssWatch(threading.Thread):
    """The process's peak VmRSS (KiB), sampled every 20 ms."""

    def __init__(self, pid):
        super().__init__(daemon=True)
        self.pid, self.peak, self.stop = pid, 0, False

    def run(self):
        while not self.stop:
            rss = status_kib(self.pid, "VmRSS")
            if rss is None:  # the process is gone
                return
            self.peak = max(self.peak, rss)
            time.sleep(0.02)


def raw(port, data=b"", rcvbuf=None):
    s = socket.socket()
    if rcvbuf:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, rcvbuf)
    s.settimeout(2)
    s.connect(("127.0.0.1", port))
    if data:
        try:
            s.sendall(data)
        except OSError:
            pass
    return s


def closed_by_server(s, timeout=3.0):
    """True when the server closes the connection (EOF or reset) within `timeout`."""
    s.settimeout(timeout)
    try:
        while s.recv(65536):
            pass
        return True
    except ConnectionError:
        return True
    except (socket.timeout, OSError):
        return False


def http_abuse(port, rng):
    for _ in range(20):  # random bytes where an HTTP request should be
        s = raw(port, bytes(rng.getrandbits(8) for _ in range(rng.randrange(1, 4096))))
        s.close()
    held = [raw(port, b"GET / HTTP/1.1\r\nHost: x\r\n") for _ in range(5)]  # truncated, held open
    s = raw(port, b"GET / HTTP/1.1\r\nX: " + b"a" * 40000 + b"\r\n\r\n")
    check(closed_by_server(s), "an HTTP header over 16 KiB is refused and closed")
    s.close()
    s = raw(port, b"POST / HTTP/1.1\r\nHost: x\r\nContent-Length: 1000000\r\n\r\n" + b"b" * 100000)
    check(closed_by_server(s), "an HTTP body over 64 KiB is refused and closed")
    s.close()
    idle = []
    for _ in range(100):  # more idle connections than the server keeps from one address
        try:
            idle.append(raw(port))
        except OSError:
            break
    closed = sum(closed_by_server(c) for c in idle[:20])
    check(closed == 20, "past 16 HTTP connections from one address, the oldest idle ones are closed (%d of the first 20)" % closed)
    for c in held + idle:
        c.close()


def ws_abuse(run, rng):
    for what, data in (("random bytes", bytes(rng.getrandbits(8) for _ in range(2000))),
                       ("a frame over 64 KiB", ws_frame(b"x" * 10, length=1 << 40)),
                       ("an unmasked frame", b"\x81\x05hello"),
                       ("a binary message", ws_frame(b"\x00\x01", opcode=2))):
        c = run.ws()
        c.recv()
        try:
            c.sock.sendall(data)
        except OSError:
            pass
        check(closed_by_server(c.sock), "a WebSocket client sending %s is dropped" % what)
        c.close()
    c = run.ws()  # a truncated frame: its header promises 1000 bytes, 10 come, then the client goes
    c.recv()
    c.sock.sendall(ws_frame(b"x" * 1000)[:16])
    c.close()


VALUES = [None, True, False, "x", "", -1, 0, 1, 2.7, 1e300, -1e300, 60001, [], {}, [1, [2]], {"a": 1}, "\u00ff" * 3]
OPS = ["snapshot", "subscribe", "unsubscribe", "inject_fault", "step", "set_rtf", "send_frame", "motion", "warp", ""]
FIELDS = ["port", "kind", "bit", "from", "clock", "period_ms", "path", "ms", "rtf", "token", "data", "duration_ms"]


def random_requests(run, rng, n=300):
    c = run.ws()
    c.recv()
    answered = 0
    for i in range(n):
        m = {"op": rng.choice(OPS), "id": i}
        for k in rng.sample(FIELDS, rng.randrange(0, 4)):
            m[k] = rng.choice(VALUES)
        if m["op"] == "inject_fault":
            m["port"] = 1  # no host on port 1: an accepted fault changes nothing the checks judge
        if m["op"] == "motion":
            m["token"] = rng.choice(["", "X", "ABC", 5, None])  # never a real token
        c.send(m)
        r = c.recv_until(lambda x: x.get("id") == i)
        answered += r.get("type") in ("ok", "error", "snapshot")
    check(answered == n, "%d random requests each get a reply (%d did)" % (n, answered))
    for m in ({"op": "unsubscribe"}, {"op": "resume"}, {"op": "set_rtf", "rtf": 1}):  # undo what was accepted
        c.request(m)
    return c


def deaf_subscriber(port):
    """Subscribed every 0.1 ms of simulated time (an update every slice), reading nothing, with a
    tiny receive buffer."""
    s = raw(port, (b"GET /api/v1/ws HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                   b"Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n"), rcvbuf=4096)
    head = b""
    while b"\r\n\r\n" not in head:  # the 101 first: what follows the request is the WebSocket's
        head += s.recv(1)
    s.sendall(ws_frame(json.dumps({"op": "subscribe", "clock": "sim", "period_ms": 0.1}).encode()))
    return s


def flooder(run):
    """A client that sends snapshot requests as fast as it can and never reads."""
    c = run.ws()
    c.recv()
    c.sock.setblocking(False)
    frame = ws_frame(json.dumps({"op": "snapshot"}).encode())
    end = time.monotonic() + 3
    try:
        while time.monotonic() < end:
            try:
                c.sock.send(frame * 50)
            except BlockingIOError:
                time.sleep(0.001)
    except OSError:
        return c, True  # dropped
    return c, False


def main(rcsim, scenario):
    out = tempfile.mkdtemp(prefix="rcsim-monitor-fuzz-")
    rng = random.Random(33)
    run = Rcsim(rcsim, scenario, "--out", out)
    watch = RssWatch(run.proc.pid)
    try:
        witness = run.ws()
        witness.recv()
        time.sleep(0.3)
        before_kib = rss_kib(run.proc.pid)
        watch.start()
        t0 = witness.request({"op": "snapshot"})["data"]["sim_time_s"]
        http_abuse(run.port, rng)
        ws_abuse(run, rng)
        random_requests(run, rng).close()
        deaf = deaf_subscriber(run.port)
        flood, dropped = flooder(run)
        check(dropped or closed_by_server(flood.sock, 2), "a client flooding requests without reading is dropped")
        deadline = time.monotonic() + 5
        while "too slow" not in run.stderr() and time.monotonic() < deadline:
            time.sleep(0.05)
        check("too slow" in run.stderr(), "a subscriber that never reads is dropped as too slow")
        # The reason counts what it has not read: past 8 MiB (with the update that did not fit,
        # under 1 MiB) or 4096 messages (docs/monitor.md "Limits").
        m = re.search(r"dropped: too slow: (\d+) bytes not yet read \((\d+) messages waiting\)", run.stderr())
        print("--    " + (m.group(0) if m else "no reason"))
        check(m and (int(m.group(1)) > 7 << 20 or int(m.group(2)) == 4096),
              "the reason is what it has not read, at the bound (%s)" % (m.group(0) if m else "none"))
        t1 = witness.request({"op": "snapshot"})["data"]["sim_time_s"]
        check(t1 > t0 + 0.5, "the witness is answered and the run goes on (%.3f -> %.3f s)" % (t0, t1))
        # The last word: SIGTERM while a client floods and another never reads.
        deaf2 = raw(run.port, rcvbuf=4096)
        flood2 = WebSocket("127.0.0.1", run.port, "/api/v1/ws")
        flood2.sock.sendall(ws_frame(json.dumps({"op": "snapshot"}).encode()) * 2000)
        ts = time.monotonic()
        run.proc.send_signal(signal.SIGTERM)
        rc, _, err = run.finish(timeout=10)
        took = time.monotonic() - ts
        for s in (deaf, flood.sock, flood2.sock, deaf2):
            s.close()
    except (ConnectionError, TimeoutError, OSError, StopIteration) as e:
        check(False, "the run goes on: %r" % e)
        run.kill()
        print(run.stderr())
        return 1
    watch.stop = True
    growth = (watch.peak - before_kib) / 1024
    if os.environ.get("RCSIM_SANITIZED"):  # ASan's quarantine holds freed memory (CMakeLists.txt)
        print("--    memory bound not judged in a sanitizer build: peak %.0f MB" % (watch.peak / 1024))
    else:
        check(growth < 64, "memory stays bounded: RSS %.0f MB, peak %.0f MB" % (before_kib / 1024, watch.peak / 1024))
    check(rc == 143, "SIGTERM ends the run (exit 143, got %d)" % rc)
    # The second is judged in the Release build; under the sanitizers the stop and the report's
    # writing run several times slower, so there the bound is only that it ends promptly.
    bound = 3.0 if os.environ.get("RCSIM_SANITIZED") else 1.0
    check(took < bound, "within %g s (%.2f s)" % (bound, took))
    try:
        with open(os.path.join(out, "report.json")) as f:
            verdict = json.load(f).get("verdict")
    except (OSError, ValueError) as e:
        verdict = "no report.json: %s" % e
    check(verdict == "interrupted", "report.json is written, verdict interrupted (%s)" % verdict)
    check("internal error" not in err, "no internal error")
    if failures:
        print(err[-4000:])
    shutil.rmtree(out, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
