"""The monitor's connections as an outside client uses them (issue #48 items 5, 6, 7; docs/monitor.md
"Limits"), with raw sockets through tests/scenarios/monitor/board.yaml:
  - pipelining: 256 requests in one write (the documented per-client queue) all answered to a
    client that reads them; none dropped as too slow;
  - idle connections: at most 16 plain HTTP connections from one address and 64 in all, a new one
    closing the oldest that has sent nothing; an idle connection closed after 2 s; with 64 idle
    sockets renewed as they get closed, GET / and a WebSocket request are answered within 1 s;
  - the bytes sent in the same write as the WebSocket upgrade request are served;
  - 16 WebSocket clients at once, the 17th handshake answered 503; a message nested 33 deep drops
    its client.

usage: net_test.py RCSIM SCENARIO"""
import json
import os
import select
import signal
import socket
import sys
import threading
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import HANG_S, check, failures  # noqa: E402
from wsclient import Rcsim, WebSocket, http_get, ws_frame  # noqa: E402

UPGRADE = (b"GET /api/v1/ws HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
           b"Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n")
PER_PEER, IN_ALL = 16, 64  # docs/monitor.md "Limits"


def connect(port, source="127.0.0.1"):
    s = socket.socket()
    s.bind((source, 0))  # the whole of 127/8 is this machine: other source addresses, other peers
    s.settimeout(HANG_S)
    s.connect(("127.0.0.1", port))
    return s


def is_closed(s, timeout=0.0):
    """True when the server has closed `s` (EOF or reset) within `timeout`; reads nothing else."""
    if not select.select([s], [], [], timeout)[0]:
        return False
    try:
        return s.recv(1, socket.MSG_PEEK) == b""
    except OSError:
        return True


def wait_closed(socks, timeout=HANG_S):
    end = time.monotonic() + timeout
    while not all(is_closed(s) for s in socks) and time.monotonic() < end:
        time.sleep(0.01)
    return all(is_closed(s) for s in socks)


def pipelining(run):
    """256 requests in one write, twice: small replies (the slice answers them all at once) and
    snapshots (several MB in all); the client reads every reply."""
    for op in ("unsubscribe", "snapshot"):
        c = run.ws()
        c.recv()  # hello
        n = 256
        c.sock.sendall(b"".join(ws_frame(json.dumps({"op": op, "id": i}).encode()) for i in range(n)))
        ids = set()
        try:
            while len(ids) < n:
                m = c.recv_until(lambda m: "id" in m)
                ids.add(m["id"])
        except (ConnectionError, TimeoutError, OSError) as e:
            print("--    after %d replies: %r" % (len(ids), e))
        check(ids == set(range(n)), "%d %s requests pipelined in one write are all answered (%d were)" % (n, op, len(ids)))
        c.close()
    check("too slow" not in run.stderr(), "a client that reads its replies is not dropped as too slow")


# Evictions are judged before the 2 s request timeout could have closed the connections instead.
EVICTED_WITHIN_S = 1.8


def per_peer_cap(run):
    """20 idle connections from one address: the 4 oldest are closed to make room, at once."""
    t0 = time.monotonic()
    socks = [connect(run.port) for _ in range(PER_PEER + 4)]
    closed = wait_closed(socks[:4], timeout=EVICTED_WITHIN_S)
    kept = sum(not is_closed(s) for s in socks[4:])
    took = time.monotonic() - t0
    check(closed and took < EVICTED_WITHIN_S,
          "past %d idle connections from one address, the oldest are closed at once (%.2f s)" % (PER_PEER, took))
    check(kept == PER_PEER, "the %d newest stay open (%d do)" % (PER_PEER, kept))
    for s in socks:
        s.close()


def total_cap(run):
    """16 idle connections from each of 4 addresses fill the 64 (one address's cap does not close
    another's); one from a fifth address closes the oldest of all, at once."""
    time.sleep(0.1)  # the server has seen the previous part's connections close
    t0 = time.monotonic()
    socks = [connect(run.port, "127.0.0.%d" % a) for a in range(1, 5) for _ in range(PER_PEER)]
    time.sleep(0.1)
    check(not any(is_closed(s) for s in socks), "16 idle connections from each of 4 addresses all stay open")
    extra = connect(run.port, "127.0.0.5")
    closed = wait_closed(socks[:1], timeout=EVICTED_WITHIN_S)
    others = sum(is_closed(s) for s in socks[1:])
    took = time.monotonic() - t0
    check(closed and took < EVICTED_WITHIN_S, "past %d in all, the oldest idle one is closed at once (%.2f s)" % (IN_ALL, took))
    check(others == 0, "only that one (%d others closed)" % others)
    for s in socks + [extra]:
        s.close()


def idle_timeout(run):
    """A connection that sends nothing, and one that never ends its request, are closed in 2 s."""
    port = run.port
    silent, truncated = connect(port), connect(port)
    truncated.sendall(b"GET / HTTP/1.1\r\nHost: x\r\n")
    t0 = time.monotonic()
    closed = wait_closed([silent, truncated], timeout=HANG_S)
    took = time.monotonic() - t0
    check(closed and took < 4.0, "idle and truncated connections are closed after the 2 s request timeout (%.2f s)" % took)
    silent.close()
    truncated.close()


class Renewer(threading.Thread):
    """Keeps `n` idle connections open: each one the server closes is opened again at once."""

    def __init__(self, port, n):
        super().__init__(daemon=True)
        self.port, self.stop, self.renewed = port, False, 0
        self.socks = [connect(port) for _ in range(n)]

    def run(self):
        while not self.stop:
            for i, s in enumerate(self.socks):
                if is_closed(s):
                    s.close()
                    try:
                        self.socks[i] = connect(self.port)
                        self.renewed += 1
                    except OSError:
                        pass
            time.sleep(0.02)  # with 16 kept per address, 48 are closed and renewed every round
        for s in self.socks:
            s.close()


def page_under_idle_flood(run):
    renewer = Renewer(run.port, IN_ALL)
    renewer.start()
    time.sleep(0.5)
    worst, errors = 0.0, []
    for _ in range(5):
        t0 = time.monotonic()
        try:
            status, body = http_get("127.0.0.1", run.port, "/", timeout=5)
            if status != 200 or b"<html" not in body.lower():
                errors.append("GET / answered %d" % status)
            c = WebSocket("127.0.0.1", run.port, "/api/v1/ws", timeout=5)
            c.recv()
            c.request({"op": "snapshot"}, timeout=5)
            c.close()
        except (ConnectionError, TimeoutError, OSError, IndexError) as e:  # IndexError: closed with no answer
            errors.append(repr(e))
        worst = max(worst, time.monotonic() - t0)
        time.sleep(0.2)
    renewer.stop = True
    renewer.join()
    check(not errors, "with %d idle sockets renewed, GET / and the WebSocket are served (%s)" % (IN_ALL, errors))
    check(worst < 1.0, "each within 1 s (the slowest took %.2f s; %d idle sockets renewed)" % (worst, renewer.renewed))


def early_frames(run):
    """The upgrade request and two WebSocket requests in one write: both are answered."""
    s = connect(run.port)
    s.sendall(UPGRADE + ws_frame(json.dumps({"op": "snapshot", "id": "early"}).encode())
              + ws_frame(json.dumps({"op": "set_rtf", "rtf": 1, "id": "early2"}).encode()))
    c = WebSocket.__new__(WebSocket)  # the handshake was sent above: read its answer here
    c.sock, c.buf = s, b""
    head = b""
    while b"\r\n\r\n" not in head:
        head += s.recv(1)
    check(b" 101 " in head.split(b"\r\n", 1)[0], "the upgrade is accepted")
    got = []
    try:
        while len(got) < 2:
            got.append(c.recv_until(lambda m: "id" in m)["id"])
    except (ConnectionError, TimeoutError, OSError) as e:
        print("--    %r" % e)
    check(got == ["early", "early2"], "the frames sent with the upgrade request are answered in order (%s)" % got)
    c.close()


WS_CLIENTS = 16  # docs/monitor.md "Limits"


def websocket_cap(run):
    """16 WebSocket clients are served; the 17th handshake is answered 503 and closed."""
    clients = []
    try:
        for _ in range(WS_CLIENTS):
            clients.append(run.ws())
            clients[-1].recv()  # hello: the session is running
        s = connect(run.port)
        s.sendall(UPGRADE)
        head = b""
        while b"\r\n" not in head:
            chunk = s.recv(1)
            if not chunk:
                break
            head += chunk
        check(b" 503 " in head.split(b"\r\n", 1)[0],
              "with %d WebSocket clients the next handshake is answered 503 (%r)" % (WS_CLIENTS, head[:40]))
        s.close()
    finally:
        for c in clients:
            c.close()


def json_nesting(run):
    """A message nested 33 levels deep drops its client, naming the reason in the log."""
    c = run.ws()
    c.recv()  # hello
    c.send_raw(b"[" * 33 + b"]" * 33)
    check(wait_closed([c.sock]), "a client sending JSON nested 33 levels deep is dropped")
    c.close()
    end = time.monotonic() + HANG_S
    while "nested deeper than 32" not in run.stderr() and time.monotonic() < end:
        time.sleep(0.05)
    check("nested deeper than 32" in run.stderr(), "the log says why: JSON nested deeper than 32")


def main(rcsim, scenario):
    run = Rcsim(rcsim, scenario)
    try:
        # The frames sent with the upgrade last: without them the wait for their answer is the
        # only one long enough to outlast the scenario.
        for part in (websocket_cap, json_nesting, pipelining, per_peer_cap, total_cap, idle_timeout, page_under_idle_flood,
                     early_frames):
            try:
                part(run)
            except (ConnectionError, TimeoutError, OSError) as e:
                check(False, "%s: %r" % (part.__name__, e))
    finally:
        run.proc.send_signal(signal.SIGINT)
        rc, _, err = run.finish(timeout=HANG_S)
    check(rc == 130, "the run ends on SIGINT (exit %d)" % rc)
    if failures:
        print(err[-4000:])
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
