"""Modbus TCP with Debian's pymodbus as the client (docs/monitor.md "Modbus TCP"), through a short
run of tests/scenarios/modbus/board.yaml with --modbus and --monitor: time, counters and Table 3 read and
compared with the monitor's JSON snapshot of the same paused instant; the pause and step coils;
a servo coil and motion commands through the mailbox moving axis 0 to its target; a mailbox
"go" written while paused, taking effect on the step; exception responses to bad requests (function
codes 0x80..0xFF: 01 with the code unchanged; reads of the map's gaps: 02).

usage: client_test.py RCSIM SCENARIO"""
import csv
import io
import json
import os
import signal
import struct
import subprocess
import sys
import time

from pymodbus.client import ModbusTcpClient

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import check, failures  # noqa: E402
from mbrun import Rcsim, adu, raw, sim_time_ms  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "monitor"))
from wsclient import http_get  # noqa: E402


class Map:
    """`rcsim modbus-map`: addresses by name, values decoded by type and scale."""

    def __init__(self, rcsim):
        text = subprocess.run([rcsim, "modbus-map"], capture_output=True, text=True, check=True).stdout
        self.rows = {r["name"]: r for r in csv.DictReader(io.StringIO(text))}

    def addr(self, name):
        return int(self.rows[name]["address"])

    def read(self, c, name):
        """The value in the entry's unit; None = not measured."""
        r = self.rows[name]
        a, n = int(r["address"]), int(r["words"])
        regs = (c.read_input_registers if r["table"] == "input_register" else c.read_holding_registers)(a, n, slave=1).registers
        raw_ = regs[0] if n == 1 else regs[0] << 16 | regs[1]
        if r["type"] == "u16" and raw_ == 0xFFFF or r["type"] == "u32" and raw_ == 0xFFFFFFFF or \
                r["type"] == "i32" and raw_ == 0x80000000:
            return None
        if r["type"] == "i32" and raw_ & 0x80000000:
            raw_ -= 1 << 32
        return raw_ / float(r["scale"])


def wait(pred, timeout=8.0, what=""):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        v = pred()
        if v:
            return v
        time.sleep(0.02)
    return None


def mailbox(c, m, token, params):
    """Writes a command and "go"; the sequence number it will have when done."""
    seq = c.read_holding_registers(m.addr("mailbox.sequence"), 1, slave=1).registers[0]
    regs = [ord(token[0]) << 8 | ord(token[1]), len(params)]
    for p in params:
        v = p & 0xFFFFFFFF
        regs += [v >> 16, v & 0xFFFF]
    c.write_registers(m.addr("mailbox.token"), regs, slave=1)
    c.write_register(m.addr("mailbox.go"), 1, slave=1)
    return (seq + 1) & 0xFFFF


def done(c, m, seq):
    h = c.read_holding_registers(m.addr("mailbox.go"), 4, slave=1).registers  # go, result, error_id, sequence
    return h if h[0] == 0 and h[3] == seq else None


def main(rcsim, scenario):
    m = Map(rcsim)
    run = Rcsim(rcsim, scenario, "--monitor", "127.0.0.1:0")
    c = ModbusTcpClient("127.0.0.1", port=run.port, timeout=3)
    try:
        check(c.connect(), "pymodbus connects to --modbus")
        line = next(l for l in run.lines if l.startswith("modbus:"))
        check(line.strip() == "modbus: 127.0.0.1:%d (Modbus TCP, unit 1; rcsim modbus-map, docs/monitor.md)" % run.port,
              "rcsim prints where Modbus TCP listens, as docs/monitor.md shows: " + line.strip())
        body(c, m, run)
    finally:
        c.close()
        if failures:
            run.kill()
            print(run.stderr())
    if failures:
        return 1
    run.proc.send_signal(signal.SIGTERM)
    rc, out, err = run.finish()
    check(rc == 143, "SIGTERM ends the run with its reports (exit 143, got %d)" % rc)
    check("modbus: at " in err and "mailbox MA" in err, "the log records the mailbox's commands")
    return 1 if failures else 0


def body(c, m, run):
    # Time runs at the scenario's real-time pace (realtime: 1).
    t0 = sim_time_ms(c)
    time.sleep(0.3)
    t1 = sim_time_ms(c)
    # realtime: 1 paces it to at most real time; a loaded host may run it slower.
    check(0 < t1 - t0 <= 400, "sim_time advances with the run, paced (%d ms in 0.3 s of wall time)" % (t1 - t0))
    check(wait(lambda: (m.read(c, "port0.frames_delivered") or 0) >= 3), "port 0's delivered frames count up")

    # Pause: time stands still; the counters and figures equal the JSON snapshot of that instant.
    c.write_coil(m.addr("pause"), True, slave=1)
    check(wait(lambda: c.read_coils(m.addr("pause"), 1, slave=1).bits[0]), "the pause coil reads 1 once paused")
    time.sleep(0.15)  # the snapshot is republished every 50 ms
    p0 = sim_time_ms(c)
    time.sleep(0.2)
    check(sim_time_ms(c) == p0, "paused: sim_time stands still (%d ms)" % p0)
    status, body_ = http_get("127.0.0.1", run.http_port, "/api/v1/snapshot")
    snap = json.loads(body_)
    check(round(snap["sim_time_s"] * 1000) == p0, "sim_time equals the snapshot's (%s s)" % snap["sim_time_s"])
    port = snap["ports"][0]
    for name, want in (("frames_sent", port["host_counters"]["frames_sent"]),
                       ("frames_delivered", port["host_counters"]["frames_delivered"]),
                       ("frames_failed", port["host_counters"]["frames_failed"]),
                       ("overruns", port["uart"]["overruns"]),
                       ("frames_received", port["main_cpu"]["frames_received"])):
        got = m.read(c, "port0." + name)
        check(got == want, "port0.%s = %s, the snapshot's %s" % (name, got, want))
    check(m.read(c, "port1.frames_sent") is None, "port 1 has no protocol host: its frames_sent reads not measured")
    t3 = snap["table3"]
    check(abs(m.read(c, "rs232_isr_mean") - t3["rs232_isr_us"]) <= 0.00051, "rs232_isr_mean equals the snapshot's")
    check(abs(m.read(c, "budget") - t3["budget_us"]) <= 0.0005, "budget equals the snapshot's (%s us)" % t3["budget_us"])
    check(abs(m.read(c, "margin") - t3["margin_us"]) <= 0.002, "margin = budget - (isr mean + dpram byte)")
    check(m.read(c, "verdict") == 1, "the verdict so far: passing (1)")

    # A step runs step_ms of simulated time exactly and stays paused.
    c.write_register(m.addr("step_ms"), 25, slave=1)
    c.write_coil(m.addr("step"), True, slave=1)
    # (sim_time is in whole ms, rounded: the step of exactly 25 ms may show as 24..26)
    check(wait(lambda: abs(sim_time_ms(c) - p0 - 25) <= 1), "the step coil runs step_ms (25) of simulated time")
    time.sleep(0.1)
    p1 = sim_time_ms(c)
    check(abs(p1 - p0 - 25) <= 1 and c.read_coils(m.addr("pause"), 1, slave=1).bits[0], "... and the run stays paused")

    # Written while paused: the servo coil and "go" are held until the next step.
    c.write_coil(m.addr("axis0.servo_on"), True, slave=1)
    seq = mailbox(c, m, "SV", [1])
    time.sleep(0.2)
    h = c.read_holding_registers(m.addr("mailbox.go"), 4, slave=1).registers
    check(h[0] == 1 and h[3] != seq, "paused: the mailbox's go stays 1 and the command waits (%s)" % h)
    c.write_coil(m.addr("step"), True, slave=1)
    h = wait(lambda: done(c, m, seq))
    check(h is not None and h[1] == 0, "the step executes the held command: SV 1 -> BCH 0 (%s)" % h)
    c.write_coil(m.addr("pause"), False, slave=1)
    check(wait(lambda: m.read(c, "axis0.state") == 1), "axis 0 is powered: Standstill (1)")
    check(c.read_coils(m.addr("axis0.servo_on"), 1, slave=1).bits[0], "the servo coil of axis 0 reads 1")

    # A motion command through the mailbox moves the axis to its target.
    seq = mailbox(c, m, "MA", [0, 2000, 20000, 200000, 200000])
    h = wait(lambda: done(c, m, seq))
    check(h is not None and h[1] == 0, "MA 0,2000,20000,200000,200000 -> BCH 0 (%s)" % h)
    check(wait(lambda: m.read(c, "axis0.actual_position") == 2000), "axis 0's actual position reaches 2000")
    check(m.read(c, "axis0.command_position") == 2000, "... its command position is 2000")
    check(wait(lambda: c.read_discrete_inputs(m.addr("axis0.done"), 3, slave=1).bits[:3] == [True, False, False]),
          "axis 0: Done, not Busy, no Error")
    check(m.read(c, "axis0.velocity") == 0, "axis 0 stands still: velocity 0")
    # A bad parameter: BCH 02 with the ErrorID (docs/motion.md).
    seq = mailbox(c, m, "MA", [0, 2000, -5, 200000, 200000])
    h = wait(lambda: done(c, m, seq))
    check(h is not None and h[1] == 2 and h[2] != 0, "MA with a negative velocity -> BCH 2 and an ErrorID (%s)" % h)
    seq = mailbox(c, m, "ZZ", [])
    h = wait(lambda: done(c, m, seq))
    check(h is not None and h[1] == 1, "an unknown token -> BCH 1 (%s)" % h)

    # Exception responses.
    r = c.read_input_registers(m.addr("axis3.error_id") + 1, 1, slave=1)
    check(r.isError() and r.exception_code == 2, "a read past the input registers: exception 02")
    r = c.read_holding_registers(0, 126, slave=1)
    check(r.isError() and r.exception_code == 3, "a read of 126 registers: exception 03")
    r = c.write_register(m.addr("mailbox.result"), 0, slave=1)
    check(r.isError() and r.exception_code == 2, "a write to the read-only mailbox.result: exception 02")
    r = c.write_register(m.addr("step_ms"), 0, slave=1)
    check(r.isError() and r.exception_code == 3, "step_ms = 0: exception 03")
    r = c.read_input_registers(0, 2, slave=7)
    check(r.isError() and r.exception_code == 0x0B, "unit id 7: exception 0B (no such device)")
    for fc in (0x07, 0x11, 0x16, 0x17, 0x2B, 0x64):
        resp = raw(run.port, adu(9, 1, bytes([fc, 0, 0, 0, 1])))
        check(resp[7:9] == bytes([fc | 0x80, 1]), "function 0x%02X: exception 01 (%s)" % (fc, resp.hex()))
    # 0x80..0xFF are the codes of exception responses, no request's: exception 01 with the code as
    # it came (it has the high bit already; adding 0x80 to a byte wrapped 0x80 to 0x00).
    for fc in (0x80, 0x81, 0x84, 0xFF):
        resp = raw(run.port, adu(10, 1, bytes([fc, 0, 0, 0, 1])))
        check(resp[:9] == adu(10, 1, bytes([fc, 1])), "function 0x%02X: exception 01, function 0x%02X (%s)"
              % (fc, fc, resp.hex()))
    # Addresses inside a table that the map does not name (docs/monitor.md: the gaps) are illegal,
    # alone or in a read that spans one; what the map names around them reads as before.
    for a in (5, 20, 50, 99, 160, 208):
        r = c.read_input_registers(a, 1, slave=1)
        check(r.isError() and r.exception_code == 2, "input register %d, unmapped: exception 02" % a)
    r = c.read_input_registers(m.addr("latency_over_budget"), 3, slave=1)
    check(r.isError() and r.exception_code == 2, "a read of input registers 18..20 (20 unmapped): exception 02")
    r = c.read_input_registers(m.addr("verdict"), 2, slave=1)
    check(r.isError() and r.exception_code == 2, "a read of input registers 4..5 (5 unmapped): exception 02")
    r = c.read_input_registers(m.addr("rs232_isr_mean"), 14, slave=1)
    check(not r.isError() and len(r.registers) == 14, "a read of the mapped input registers 6..19: served")
    r = c.read_holding_registers(0, 23, slave=1)
    check(not r.isError() and len(r.registers) == 23, "the whole mailbox, holding registers 0..22: served")
    # One axis's servo coil: MC_Power.Enable of that axis only.
    c.write_coil(m.addr("axis2.servo_on"), False, slave=1)
    check(wait(lambda: m.read(c, "axis2.state") == 0), "axis 2's servo coil 0: axis 2 Disabled (0)")
    check(m.read(c, "axis0.state") == 1 and not c.read_coils(m.addr("axis2.servo_on"), 1, slave=1).bits[0],
          "... axis 0 stays in Standstill, the coil reads 0")
    c.write_coil(m.addr("axis2.servo_on"), True, slave=1)
    check(wait(lambda: m.read(c, "axis2.state") == 1), "axis 2's servo coil 1: Standstill again")
    check(sim_time_ms(c) > p1, "the run went on")


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
