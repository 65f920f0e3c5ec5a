#!/usr/bin/env python3
"""End-to-end tests of `host: pty` with pyserial against `rcsim run` and the real firmware.

Usage: pty_session_test.py CASE RCSIM WORKDIR, CASE one of
  protocol  the transfer of docs/system.md §5.2 through the pty: ENQ -> ACK, an EC frame -> EOT,
            the controller's ENQ -> ACK, its echo response -> EOT; report.json agrees
  mismatch  a client at 4800 baud on the 9600,8E1 port: each character is a framing error at
            the 82510, counted in report.json
  break     a NUL at 300 baud is a BREAK to the 82510 (report.json break_detects), after which
            the port answers ENQ with ACK again

The scenario runs with duration_s: 0, so closing the port ends the run (docs/serial.md "A pty as
the serial port"), and with the monitor (docs/monitor.md): the client waits for simulated time
and for what the line carries through its API, never for a guessed wall-clock time. Every wait
has a deadline only a hang reaches. Exit 77 (skipped) when pyserial is missing.
"""
import json
import os
import subprocess
import sys
import time

try:
    import serial  # Debian python3-serial
except ImportError:
    print("SKIP: pyserial (Debian package python3-serial) is not installed")
    sys.exit(77)

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "monitor"))
from rcsim_test import ACK, ENQ, EOT, ETX, HANG_S, Rcsim, protocol_frame  # noqa: E402
from wsclient import WebSocket  # noqa: E402


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


# Simulated time by which the firmware has programmed its 82510 (it enables interrupts at 4.8 ms):
# a byte sent earlier is sampled at the 82510's reset settings.
FIRMWARE_READY_S = 0.02


class Run:
    """`rcsim run` of a one-port pty scenario, with the monitor: the test waits on simulated time
    and on the line through its snapshot (docs/monitor.md), never on a wall-clock guess."""

    def __init__(self, rcsim, work, name, realtime=1.0):
        self.link = os.path.join(work, name + ".tty")
        scenario = os.path.join(work, name + ".yaml")
        with open(scenario, "w") as f:
            f.write(f"name: {name}\nduration_s: 0\ndrain_s: 0.2\nrealtime: {realtime}\n"
                    f"ports:\n  - {{host: pty, link: {self.link}, format: \"9600,8E1\"}}\n")
        self.out = os.path.join(work, name + ".out")
        # rcsim makes the link, then prints the monitor's URL; the wait only ends at a hang.
        self.run = Rcsim(rcsim, ["run", scenario, "--out", self.out, "--monitor", "127.0.0.1:0"],
                         {"monitor": r"monitor: http://127\.0\.0\.1:(\d+)/"}, required=False)
        self.proc = self.run.proc
        found = self.run.found.get("monitor")
        self.port = int(found.group(1)) if found else None
        if self.port is None or not os.path.islink(self.link):
            self.run.kill()
            fail("no monitor URL or no pty link %s; rcsim said:\n%s%s"
                 % (self.link, "".join(self.run.lines), self.run.stderr()))

        self.api = WebSocket("127.0.0.1", self.port, "/api/v1/ws")
        self.api.recv()  # hello

    def snapshot(self):
        """Made when asked, between two slices (GET /api/v1/snapshot may be 50 ms old)."""
        return self.api.request({"op": "snapshot"})["data"]

    def wait(self, pred, what):
        """The first snapshot that satisfies pred (asked every 10 ms of wall time)."""
        end = time.monotonic() + HANG_S
        while True:
            s = self.snapshot()
            if pred(s):
                return s
            if time.monotonic() > end:
                self.proc.kill()
                fail("%s: not within %.0f s" % (what, HANG_S))
            time.sleep(0.01)

    def wait_sim(self, t_s, what):
        return self.wait(lambda s: s["sim_time_s"] >= t_s, what)

    def finish(self):
        self.api.close()
        try:
            _, out, err = self.run.finish(timeout=HANG_S)
        except subprocess.TimeoutExpired:
            self.run.kill()
            fail("rcsim did not end after the client closed the port:\n" + "".join(self.run.lines) + self.run.stderr())
        text = out + err
        print(text)
        if self.proc.returncode not in (0, 1, 4):  # a session that sent no whole frame measures nothing
            fail("rcsim exit code %d" % self.proc.returncode)
        if os.path.lexists(self.link):
            fail("the link %s outlived the run" % self.link)
        with open(os.path.join(self.out, "report.json")) as f:
            return json.load(f)


def read_exact(port, n, what):
    got = port.read(n)
    if len(got) != n:
        fail("%s: got %r within %.1f s" % (what, got, port.timeout))
    return got


def enq_ack(port):
    """ENQ -> ACK (once the 82510 is programmed, FIRMWARE_READY_S)."""
    port.reset_input_buffer()
    port.write(ENQ)
    if read_exact(port, 1, "the answer to ENQ") != ACK:
        fail("no ACK to ENQ")


def case_protocol(rcsim, work):
    # Paced at 1/50 of real time: the client's answers are due within the firmware's T1 (50 ms
    # of simulated time, §6.1: the frame after our ACK, the ACK to its ENQ, the EOT after its
    # ETX), which is 2.5 s of wall time here, for a client on a loaded host.
    run = Run(rcsim, work, "pty_protocol", realtime=0.02)
    with serial.Serial(run.link, 9600, parity=serial.PARITY_EVEN, timeout=HANG_S) as s:
        run.wait_sim(FIRMWARE_READY_S, "the firmware's start")
        enq_ack(s)
        command = protocol_frame(b"EC", b"HELLO")
        s.write(command)
        if read_exact(s, 1, "answer to the frame") != EOT:
            fail("the controller did not take the frame with EOT")
        if read_exact(s, 1, "the controller's ENQ") != ENQ:
            fail("no ENQ for the response")
        s.write(ACK)
        response = b""
        while not response.endswith(ETX):
            response += read_exact(s, 1, "the response after %r" % response)
        s.write(EOT)
        # The port is closed once the host has the EOT: it ends the run after the bytes it has
        # read, but reads those of a closing client only for 100 ms. Without the EOT the firmware
        # would send its ENQ again after T1 (§6.2): none within T1 of simulated time, it has it.
        eot = run.snapshot()["sim_time_s"]
        run.wait_sim(eot + 0.06, "T1 after the EOT")
        if s.in_waiting:
            fail("the controller answered the EOT with %r: it did not take it" % s.read(s.in_waiting))
    # EC echoes its data with BCH 00 (docs/system.md §7.2): the response is the command frame itself.
    if response != command:
        fail("response %r, expected %r" % (response, command))
    r = run.finish()
    p = r["ports"][0]
    checks = {
        "host": (p["host"], "pty"),
        "framing_errors": (p["framing_errors"], 0),
        "parity_errors": (p["parity_errors"], 0),
        "main_cpu_frames_received": (p["main_cpu_frames_received"], 1),
        "main_cpu_frames_sent": (p["main_cpu_frames_sent"], 1),
        # every byte the client wrote went on the line: the ACKed ENQ, the frame, ACK, EOT
        "pty.bytes_sent": (p["pty"]["bytes_sent"], p["pty"]["bytes_in"]),
        "pty.client_format": (p["pty"]["client_format"], "9600,8E1"),
        "pty.connections": (p["pty"]["connections"], 1),
    }
    for k, (got, want) in checks.items():
        if got != want:
            fail("report.json ports[0].%s = %r, expected %r" % (k, got, want))
    if p["pty"]["bytes_in"] < 1 + len(command) + 2:
        fail("pty.bytes_in = %d, fewer than ENQ + frame + ACK + EOT" % p["pty"]["bytes_in"])


def case_mismatch(rcsim, work):
    # A 9600 receiver samples its cell k at (k + 1/2) of its bits = cell k // 2 of a 4800
    # character: its stop sample (k = 10) reads 4800 cell 5, data bit 4, which is 0 in ENQ
    # (0x05): every ENQ is a framing error (and no glitch: its START sample, cell 0, is SPACE).
    # One character per START edge (docs/serial.md, the sampling rule), however close the ENQs
    # follow each other on the line.
    n = 3
    run = Run(rcsim, work, "pty_mismatch")
    with serial.Serial(run.link, 4800, parity=serial.PARITY_EVEN, timeout=HANG_S) as s:
        run.wait_sim(FIRMWARE_READY_S, "the firmware's start")
        for _ in range(n):
            s.write(ENQ)
        # The port is closed once they are on the line (the host reads a closing client's bytes
        # for 100 ms only); the report has the exact count.
        run.wait(lambda d: d["ports"][0]["uart"]["framing_errors"] >= n, "the framing errors")
    r = run.finish()
    p = r["ports"][0]
    if p["pty"]["client_format"] != "4800,8E1":
        fail("client_format %r" % p["pty"]["client_format"])
    if p["framing_errors"] != n:
        fail("framing_errors = %d, expected %d (one per ENQ sent at 4800)" % (p["framing_errors"], n))


def case_break(rcsim, work):
    run = Run(rcsim, work, "pty_break")
    with serial.Serial(run.link, 9600, parity=serial.PARITY_EVEN, timeout=HANG_S) as s:
        run.wait_sim(FIRMWARE_READY_S, "the firmware's start")
        enq_ack(s)
        # No SOH follows the ACK: the firmware's T1 (50 ms) ends the transfer. Simulated time
        # asked after the ACK arrived is past the ACK.
        acked = run.snapshot()["sim_time_s"]
        run.wait_sim(acked + 0.05, "T1 after the ACK")
        # 300,8E1: a NUL is 10 bits of SPACE = 33 ms, longer than one 9600 character (1.15 ms):
        # a BREAK; the firmware resets the port (docs/system.md §6.4). The host takes the rate
        # with the byte: 300 stays until the BREAK is on the line.
        s.baudrate = 300
        s.write(b"\0")
        seen = run.wait(lambda d: d["ports"][0]["line"]["breaks"] >= 1, "the BREAK on the line")
        s.baudrate = 9600
        # The BREAK has ended and the firmware has reset the port 0.1 s of simulated time later.
        run.wait_sim(seen["sim_time_s"] + 0.1, "the end of the BREAK")
        enq_ack(s)  # the port works again after its reset
    r = run.finish()
    p = r["ports"][0]
    if p["break_detects"] != 1:
        fail("break_detects = %d, expected 1" % p["break_detects"])
    if p["pty"]["breaks_sent"] != 1:
        fail("pty.breaks_sent = %d, expected 1" % p["pty"]["breaks_sent"])


def main():
    if len(sys.argv) != 4:
        print(__doc__)
        sys.exit(2)
    case, rcsim, work = sys.argv[1:]
    os.makedirs(work, exist_ok=True)
    {"protocol": case_protocol, "mismatch": case_mismatch, "break": case_break}[case](rcsim, work)
    print("PASS")


if __name__ == "__main__":
    main()
