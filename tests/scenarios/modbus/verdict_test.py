"""The `verdict` input register (docs/monitor.md "Modbus TCP"): 0 while nothing is measured, 2 once
the worst-case margin is negative (tests/scenarios/modbus/tight.yaml's 50 us budget is below the RS-232
receive service alone); tests/scenarios/modbus/client_test.py reads 1 on a run within its budget.

usage: verdict_test.py RCSIM SCENARIO"""
import os
import signal
import sys
import time

from pymodbus.client import ModbusTcpClient

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import check, failures  # noqa: E402
from mbrun import Rcsim, sim_time_ms  # noqa: E402

VERDICT, WORST_MARGIN = 4, 16  # input registers (rcsim modbus-map; modbus.cli checks the map)


def main(rcsim, scenario):
    run = Rcsim(rcsim, scenario)
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
    finally:
        c.close()
        if failures:
            print(run.stderr())
        run.proc.send_signal(signal.SIGTERM)
        run.finish()
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
