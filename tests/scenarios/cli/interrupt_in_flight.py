#!/usr/bin/env python3
"""SIGINT while a response is on its way: the frame is "in flight", never "lost", and the
exactly-once checks judge only what completed (docs/scenarios.md "Interrupted runs").

A tcp host (paced to wall time) is the test itself: it sends one EC command with 200 data bytes,
takes the controller's EOT, ACKs the controller's ENQ for the response and reads its first 20
bytes. The response (210 bytes, 0.24 s at 9600 8E1) is then handed by the main CPU and still on the
line: the test stops the run with SIGINT there, a state reached by the protocol, not by a timer.

usage: interrupt_in_flight.py RCSIM"""
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import ACK, ENQ, EOT, SOH, protocol_frame, wait_for  # noqa: E402


def recv_exactly(s, n):
    got = b""
    while len(got) < n:
        chunk = s.recv(n - len(got))
        if not chunk:
            raise RuntimeError(f"connection closed after {got!r}")
        got += chunk
    return got


def main():
    rcsim = os.path.realpath(sys.argv[1])
    problems = []
    with tempfile.TemporaryDirectory(prefix="rcsim_in_flight.") as w:
        with open(os.path.join(w, "s.yaml"), "w") as f:
            f.write("name: in_flight\nduration_s: 3600\n"
                    "ports:\n  - {host: tcp, listen: \"127.0.0.1:0\", port_file: port.txt}\n")
        out = os.path.join(w, "out")
        env = dict(os.environ, SC_COPYRIGHT_MESSAGE="DISABLE")
        with open(os.path.join(w, "stdout.txt"), "w") as log:
            run = subprocess.Popen([rcsim, "run", os.path.join(w, "s.yaml"), "--out", out, "--reproducible"],
                                   stdout=log, stderr=subprocess.STDOUT, env=env)
            try:
                port_file = os.path.join(out, "port.txt")  # a relative output lands under --out
                wait_for(lambda: os.path.exists(port_file) and open(port_file).read().strip(), run, timeout=30,
                         poll=0.05)
                port = int(open(port_file).read())
                s = socket.create_connection(("127.0.0.1", port), timeout=20)
                s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                time.sleep(0.2)  # the firmware programs its 82510 in the first ~20 ms
                s.sendall(ENQ)
                if recv_exactly(s, 1) != ACK:
                    problems.append("no ACK to the ENQ")
                s.sendall(protocol_frame(b"EC", b"x" * 200))
                if recv_exactly(s, 1) != EOT:
                    problems.append("no EOT for the frame")
                if recv_exactly(s, 1) != ENQ:
                    problems.append("no ENQ for the response")
                s.sendall(ACK)
                if not recv_exactly(s, 20).startswith(SOH + b"EC"):
                    problems.append("the response does not start SOH EC")
                run.send_signal(signal.SIGINT)  # the response is half way to the host
                rc = run.wait(timeout=60)
                s.close()
            finally:
                if run.poll() is None:
                    run.kill()
                    run.wait()
        if rc != 130:
            problems.append(f"exit {rc}, expected 130")
        with open(os.path.join(out, "report.json")) as f:
            report = json.load(f)
        p = report["ports"][0]
        checks = {c["name"]: c for c in report["checks"]}
        wants = [
            (report.get("interrupted") is True, "report.json has no \"interrupted\": true"),
            (report.get("verdict") == "interrupted", f"verdict {report.get('verdict')!r}, expected 'interrupted'"),
            (p["commands"]["matched"] == 1 and p["commands"].get("in_flight") == 0, f"commands: {p['commands']}"),
            (p["responses"]["main_cpu_handed"] == 1 and p["responses"]["host_received"] == 0,
             f"responses: {p['responses']}"),
            (p["responses"].get("in_flight") == 1, f"responses in flight {p['responses'].get('in_flight')}, expected 1"),
            (p["responses"]["lost"] == 0 and p["responses"]["mismatches"] == 0, f"responses: {p['responses']}"),
            (p["line"]["controller_to_host"]["abandoned"] == 0, f"line: {p['line']}"),
        ]
        for name in ("commands_delivered_exactly_once", "responses_delivered_exactly_once"):
            c = checks.get(name, {})
            wants.append((c.get("passed") is True and c.get("value") == 0, f"{name}: {c}"))
        c = checks.get("responses_delivered_exactly_once", {})
        wants.append((c.get("detail") == {"unexplained": [], "expected_drops": 0, "in_flight": 1},
                      f"responses_delivered_exactly_once detail: {c.get('detail')}"))
        problems += [why for ok, why in wants if not ok]
        if problems:
            print(open(os.path.join(w, "stdout.txt")).read())
    for p in problems:
        print("FAIL:", p)
    if not problems:
        print("interrupt_in_flight: the response on its way at SIGINT is in flight, not lost")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
