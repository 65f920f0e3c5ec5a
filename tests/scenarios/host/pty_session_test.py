#!/usr/bin/env python3
"""End-to-end tests of `host: pty` with pyserial against `rcsim run` and the real firmware.

Usage: pty_session_test.py CASE RCSIM WORKDIR, CASE one of
  protocol  the transfer of docs/system.md §5.2 through the pty: ENQ -> ACK, an EC frame -> EOT,
            the controller's ENQ -> ACK, its echo response -> EOT; report.json agrees
  mismatch  a client at 4800 baud on the 9600,8E1 port (once an ENQ at 9600 got its ACK):
            each character is a framing error at the 82510, counted in report.json
  break     a NUL at 300 baud is a BREAK to the 82510 (report.json break_detects), after which
            the port answers ENQ with ACK again

The scenario runs with duration_s: 0, so closing the port ends the run (docs/serial.md "A pty as
the serial port"). Every wait has a deadline. Exit 77 (skipped) when pyserial is missing.
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
from rcsim_test import ACK, ENQ, EOT, ETX, protocol_frame, wait_for  # noqa: E402


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def start(rcsim, work, name):
    link = os.path.join(work, name + ".tty")
    scenario = os.path.join(work, name + ".yaml")
    with open(scenario, "w") as f:
        f.write(f"name: {name}\nduration_s: 0\ndrain_s: 0.2\n"
                f"ports:\n  - {{host: pty, link: {link}, format: \"9600,8E1\"}}\n")
    out = os.path.join(work, name + ".out")
    proc = subprocess.Popen([rcsim, "run", scenario, "--out", out], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    if not wait_for(lambda: os.path.islink(link), proc, timeout=10):
        proc.kill()
        fail("no pty link %s; rcsim said:\n%s" % (link, proc.communicate()[0]))
    return proc, link, out


def finish(proc, out, link):
    try:
        text = proc.communicate(timeout=30)[0]
    except subprocess.TimeoutExpired:
        proc.kill()
        fail("rcsim did not end after the client closed the port:\n" + proc.communicate()[0])
    print(text)
    if proc.returncode not in (0, 1, 4):  # a session that sent no whole frame measures nothing
        fail("rcsim exit code %d" % proc.returncode)
    if os.path.lexists(link):
        fail("the link %s outlived the run" % link)
    with open(os.path.join(out, "report.json")) as f:
        return json.load(f)


def read_exact(port, n, what):
    got = port.read(n)
    if len(got) != n:
        fail("%s: got %r within %.1f s" % (what, got, port.timeout))
    return got


def enq_ack(port):
    """ENQ until ACK: the firmware programs its 82510 in its first ~20 ms of simulated time."""
    for _ in range(5):
        port.reset_input_buffer()
        port.write(ENQ)
        if port.read(1) == ACK:
            return
    fail("no ACK to five ENQs")


def case_protocol(rcsim, work):
    proc, link, out = start(rcsim, work, "pty_protocol")
    with serial.Serial(link, 9600, parity=serial.PARITY_EVEN, timeout=3) as s:
        time.sleep(0.3)
        enq_ack(s)
        command = protocol_frame(b"EC", b"HELLO")
        s.write(command)
        if read_exact(s, 1, "answer to the frame") != EOT:
            fail("the controller did not take the frame with EOT")
        if read_exact(s, 1, "the controller's ENQ") != ENQ:
            fail("no ENQ for the response")
        s.write(ACK)
        response = b""
        deadline = time.monotonic() + 5
        while not response.endswith(ETX) and time.monotonic() < deadline:
            response += s.read(1)
        s.write(EOT)
        time.sleep(0.1)
    # EC echoes its data with BCH 00 (docs/system.md §7.2): the response is the command frame itself.
    if response != command:
        fail("response %r, expected %r" % (response, command))
    r = finish(proc, out, link)
    p = r["ports"][0]
    checks = {
        "host": (p["host"], "pty"),
        "framing_errors": (p["framing_errors"], 0),
        "parity_errors": (p["parity_errors"], 0),
        "main_cpu_frames_received": (p["main_cpu_frames_received"], 1),
        "main_cpu_frames_sent": (p["main_cpu_frames_sent"], 1),
        # every byte the client wrote went on the line: the ACKed ENQ(s), the frame, ACK, EOT
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
    # The ENQs go once the firmware has programmed its 82510, which an ACK at 9600 shows: before
    # that the 82510 samples at its reset settings, and a fixed wait for it races a loaded host.
    # One character per START edge (docs/serial.md, the sampling rule): the ENQs may follow each
    # other closely on the line, and whatever the firmware does with the first (a NAK in its
    # receiving step) the 82510 still counts each.
    n = 3
    proc, link, out = start(rcsim, work, "pty_mismatch")
    with serial.Serial(link, 9600, parity=serial.PARITY_EVEN, timeout=10) as s:
        enq_ack(s)
        s.baudrate = 4800
        for _ in range(n):
            s.write(ENQ)
    r = finish(proc, out, link)
    p = r["ports"][0]
    if p["pty"]["client_format"] != "4800,8E1":
        fail("client_format %r" % p["pty"]["client_format"])
    if p["framing_errors"] != n:
        fail("framing_errors = %d, expected %d (one per ENQ sent at 4800)" % (p["framing_errors"], n))


def case_break(rcsim, work):
    proc, link, out = start(rcsim, work, "pty_break")
    with serial.Serial(link, 9600, parity=serial.PARITY_EVEN, timeout=3) as s:
        time.sleep(0.3)
        enq_ack(s)    # the 82510 is programmed
        time.sleep(0.2)  # no SOH follows the ACK: the firmware's T1 (50 ms) ends the transfer
        # 300,8E1: a NUL is 10 bits of SPACE = 33 ms, longer than one 9600 character (1.15 ms):
        # a BREAK; the firmware resets the port (docs/system.md §6.4).
        s.baudrate = 300
        s.write(b"\0")
        time.sleep(0.2)
        s.baudrate = 9600
        time.sleep(0.1)
        enq_ack(s)  # the port works again after its reset
    r = finish(proc, out, link)
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
