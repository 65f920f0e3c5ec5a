"""The Modbus TCP server under abuse (docs/monitor.md "Modbus TCP", "Limits"): random bytes,
malformed MBAP headers, wrong lengths, truncated requests, more connections than the server
keeps, a client that sends and never reads. After each, a pymodbus client is still served, the
simulation still runs, and SIGTERM ends the run within a second with its report.

usage: fuzz_test.py RCSIM SCENARIO"""
import os
import random
import signal
import socket
import struct
import sys
import time

from pymodbus.client import ModbusTcpClient

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import check, failures, rss_kib  # noqa: E402
from mbrun import Rcsim, adu, raw, recv_adu, sim_time_ms  # noqa: E402


def closed(port, payload):
    """True when the server closes the connection after `payload` without an answer."""
    return raw(port, payload, timeout=2.0) == b""


def served(port, what):
    c = ModbusTcpClient("127.0.0.1", port=port, timeout=3)
    try:
        ok = c.connect()
        t0 = sim_time_ms(c)
        time.sleep(0.05)
        t1 = sim_time_ms(c)
        check(ok and t1 > t0, "after %s: a pymodbus client is served and the run goes on (%d -> %d ms)" % (what, t0, t1))
    except Exception as e:  # noqa: BLE001 -- any failure of the witness is the test's failure
        check(False, "after %s: a pymodbus client is served (%r)" % (what, e))
    finally:
        c.close()


def main(rcsim, scenario):
    rng = random.Random(32)
    run = Rcsim(rcsim, scenario)
    port = run.port
    rss0 = rss_kib(run.proc.pid)
    try:
        # Random bytes, each on its own connection: an answer or a close, never a hang.
        for _ in range(40):
            junk = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 300)))
            raw(port, junk, timeout=0.3)  # a few bytes may leave the server waiting for the rest
        served(port, "40 connections of random bytes")

        read_ir = bytes([4, 0, 0, 0, 2])
        check(closed(port, adu(1, 1, read_ir, protocol=5)), "protocol id 5: the connection is closed")
        check(closed(port, adu(1, 1, read_ir, length=0)), "MBAP length 0: closed")
        check(closed(port, adu(1, 1, read_ir, length=1000)), "MBAP length 1000: closed")
        resp = raw(port, adu(2, 1, read_ir + b"\x00\x00\x00"))
        check(resp[7:9] == b"\x84\x03", "a read with 3 bytes too many (length field agrees): exception 03 (%s)" % resp.hex())
        resp = raw(port, adu(3, 1, bytes([3, 0, 0])))
        check(resp[7:9] == b"\x83\x03", "a read cut short: exception 03 (%s)" % resp.hex())
        resp = raw(port, adu(4, 1, bytes([16, 0, 2, 0, 2, 4, 0, 1])))
        check(resp[7:9] == b"\x90\x03", "write multiple: byte count 4, 2 bytes of data: exception 03 (%s)" % resp.hex())
        resp = raw(port, adu(5, 1, bytes([16, 0, 2, 0, 2, 3, 0, 1, 0])))
        check(resp[7:9] == b"\x90\x03", "write multiple: byte count 3 for 2 registers: exception 03 (%s)" % resp.hex())
        resp = raw(port, adu(6, 1, bytes([15, 0, 0, 0, 200, 25]) + bytes(25)))
        check(resp[7:9] == b"\x8f\x02", "write 200 coils of a table of 6: exception 02 (%s)" % resp.hex())
        resp = raw(port, adu(7, 1, bytes([5, 0, 0, 0x12, 0x34])))
        check(resp[7:9] == b"\x85\x03", "write single coil 0x1234: exception 03 (%s)" % resp.hex())
        # A truncated request, then nothing: the connection waits, others are served meanwhile.
        s = socket.create_connection(("127.0.0.1", port))
        s.sendall(adu(8, 1, read_ir)[:9])
        served(port, "malformed headers, wrong lengths and a truncated request")
        s.close()

        # Many connections: beyond 16 the server closes the new ones; once they go, it serves again.
        many = [socket.create_connection(("127.0.0.1", port)) for _ in range(40)]
        time.sleep(0.3)
        last = many[-1]
        last.settimeout(2.0)
        try:
            last.sendall(adu(9, 1, read_ir))
            refused = recv_adu(last) == b""
        except OSError:
            refused = True
        check(refused, "the 40th connection at once is closed")
        for k in many:
            k.close()
        time.sleep(0.2)
        served(port, "40 connections at once")

        # A client that sends 20000 requests and never reads: closed once its replies back up.
        s = socket.create_connection(("127.0.0.1", port))
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        s.settimeout(5.0)
        burst = b"".join(adu(i & 0xFFFF, 1, read_ir) for i in range(20000))
        try:
            s.sendall(burst)
        except OSError:
            pass
        served(port, "a client that never reads")
        s.close()
        # Bounded buffers: one request per connection, 4096 writes queued at most.
        grown = rss_kib(run.proc.pid) - rss0
        check(grown < 16 * 1024, "memory after the abuse: %d KiB more than at the start (< 16 MiB)" % grown)
    finally:
        if failures:
            run.kill()
            print(run.stderr())
    if failures:
        return 1
    t = time.monotonic()
    run.proc.send_signal(signal.SIGTERM)
    rc, out, err = run.finish(timeout=10)
    check(rc == 143 and time.monotonic() - t < 1.5, "SIGTERM ends the run within a second (exit %d)" % rc)
    check("malformed MBAP header" in err and "refused: 16 already open" in err, "the log names the dropped clients")
    print("never-reading client: " + ("closed" if "does not read" in err else "all its replies fitted the socket buffers"))
    check("report:" in out, "the run wrote its report")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
