"""The `verdict` input register (docs/monitor.md "Modbus TCP"): 0 while nothing is measured, 2 once
the worst-case margin is negative (tests/scenarios/modbus/tight.yaml's 50 us budget is below the RS-232
receive service alone); tests/scenarios/modbus/client_test.py reads 1 on a run within its budget.
One judge (docs/scenarios.md "Checks"): paused, the register, the JSON API's snapshot and, once the
run is stopped, report.json say the same verdict and the same failed checks.

usage: verdict_test.py RCSIM SCENARIO"""
import json
import os
import signal
import sys
import time

from pymodbus.client import ModbusTcpClient

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import check, failures  # noqa: E402
from mbrun import Rcsim, sim_time_ms  # noqa: E402
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "monitor"))
from wsclient import http_get  # noqa: E402

VERDICT, WORST_MARGIN = 4, 16  # input registers (rcsim modbus-map; modbus.cli checks the map)


def main(rcsim, scenario):
    run = Rcsim(rcsim, scenario, "--monitor", "127.0.0.1:0")
    live_failed = []
    c = ModbusTcpClient("127.0.0.1", port=run.port, timeout=3)
    try:
        c.connect()
        c.write_coil(0, True, slave=1)  # pause before the traffic starts at 1 s
        t = sim_time_ms(c)
        v = c.read_input_registers(VERDICT, 1, slave=1).registers[0]
        check(t < 1000 and v == 0, "before any character (%d ms): verdict 0, not measured (%d)" % (t, v))
        w = c.read_input_registers(WORST_MARGIN, 2, slave=1).registers
        check(w == [0x8000, 0], "worst_margin reads not measured: 0x80000000 (%s)" % w)
        c.write_coil(0, False, slave=1)
        end = time.monotonic() + 8
        while time.monotonic() < end and c.read_input_registers(VERDICT, 1, slave=1).registers[0] != 2:
            time.sleep(0.05)
        check(c.read_input_registers(VERDICT, 1, slave=1).registers[0] == 2, "over the budget: verdict 2, failing so far")
        w = c.read_input_registers(WORST_MARGIN, 2, slave=1).registers
        margin = ((w[0] << 16 | w[1]) - (1 << 32)) / 1000.0 if w[0] & 0x8000 else None
        check(margin is not None and margin < 0, "... with a negative worst-case margin (%s us)" % margin)
        c.write_coil(0, True, slave=1)  # paused: the register and the API see the same instant
        v = c.read_input_registers(VERDICT, 1, slave=1).registers[0]
        # GET /api/v1/snapshot serves the snapshot published at most 50 ms of wall time ago: wait
        # for one made while paused.
        snap, end = {}, time.monotonic() + 10
        while time.monotonic() < end:
            status, body = http_get("127.0.0.1", run.http_port, "/api/v1/snapshot")
            if status == 200 and json.loads(body)["paused"]:
                snap = json.loads(body)["verdict"]
                break
            time.sleep(0.02)
        check(v == 2 and snap.get("verdict") == "failed",
              "paused: the register reads %d, the API's verdict is %r" % (v, snap.get("verdict")))
        live_failed = sorted(ch["name"] for ch in snap.get("checks", []) if ch["status"] == "failed")
    finally:
        c.close()
        if failures:
            print(run.stderr())
        run.proc.send_signal(signal.SIGTERM)
        run.finish()
    with open(os.path.join(run.out.name, "report.json")) as f:
        report = json.load(f)
    end_failed = sorted(ch["name"] for ch in report["checks"] if ch["status"] == "failed")
    check(report["verdict"] == "interrupted" and "what completed: failed" in report["verdict_reason"],
          "report.json: %s (%s)" % (report["verdict"], report["verdict_reason"]))
    check(live_failed and set(live_failed) <= set(end_failed),
          "the checks failing live %s fail in report.json too %s" % (live_failed, end_failed))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
