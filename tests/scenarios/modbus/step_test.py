"""The step coil and the write log (issue #48 item 1, issue #51 item 6; docs/monitor.md "Modbus
TCP"), through the rcsim executable with Debian's pymodbus as the client:
  - tests/scenarios/modbus/short.yaml (duration_s 1, paced at 0.1): paused at once, then
    step_ms 60000 and the step coil written three times. The step stops at the scenario's end:
    the run ends at 1 s of simulated time and drains what is in flight (report.json sim_time_s
    at most 2 s), says so on stderr, writes its report and exits with its verdict's code,
    passed; the queued steps run nothing.
  - tests/scenarios/modbus/board.yaml (60 s): the pause coil written 120 times in a row is logged as
    "modbus:" lines, at most 10 a second, the rest counted in one "... and N more" line; then a
    step of 60 s: while it runs, sim_time read over Modbus and the monitor's GET /api/v1/snapshot
    advance (they froze for the whole step); SIGTERM ends the run within seconds.

usage: step_test.py RCSIM SHORT_SCENARIO BOARD_SCENARIO"""
import json
import os
import re
import signal
import sys
import time

from pymodbus.client import ModbusTcpClient

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import HANG_S, check, failures  # noqa: E402
from mbrun import Rcsim, sim_time_ms  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "monitor"))
from wsclient import http_get  # noqa: E402

PAUSE, STEP, STEP_MS = 0, 1, 22  # coils and the holding register (rcsim modbus-map; modbus.cli checks the map)
EXIT_OF = {"passed": 0, "failed": 1, "inconclusive": 4}  # docs/scenarios.md "Verdicts and exit codes"
LINES_PER_SECOND = 10  # docs/monitor.md "Modbus TCP": the write log's rate


def step_past_the_end(rcsim, scenario):
    run = Rcsim(rcsim, scenario)
    c = ModbusTcpClient("127.0.0.1", port=run.port, timeout=3)
    try:
        c.connect()
        c.write_coil(PAUSE, True, slave=1)
        paused_at = sim_time_ms(c)
        check(paused_at < 900, "paused at %d ms, before the end at 1000 ms" % paused_at)
        c.write_register(STEP_MS, 60000, slave=1)
        for _ in range(3):  # queued behind the first: each would run 60 s more
            try:
                c.write_coil(STEP, True, slave=1)
            except Exception:  # noqa: BLE001 -- the run may have ended and closed the connection
                break
    finally:
        c.close()
    rc, _, err = run.finish(timeout=HANG_S)
    with open(os.path.join(run.out.name, "report.json")) as f:
        report = json.load(f)
    check(1.0 <= report["sim_time_s"] <= 2.0, "a 60 s step on a 1 s scenario: the run ends at %.6f s (1 s and a "
          "drain of at most 1 s)" % report["sim_time_s"])
    m = re.search(r"^modbus: a step of 60000 ms from [0-9.e-]+ s stopped at 1 s, the scenario's end \(duration_s\); "
                  r"the run ends there$", err, re.M)
    check(m is not None, "stderr says the step stopped at the scenario's end:\n" + err)
    check(err.count("stopped at") == 1, "... once, though three steps were written")
    # Passed as the scenario does when run to its end: the step took nothing from it.
    check(report["verdict"] == "passed" and rc == EXIT_OF[report["verdict"]],
          "the run ends as any run does: exit %d for verdict %s" % (rc, report["verdict"]))
    check(os.path.exists(os.path.join(run.out.name, "report.html")), "... with its report.html")


def logged_writes(err):
    """The "modbus:" lines of pause and resume writes, and the count the summary lines left out."""
    lines = re.findall(r"^modbus: (?:paused|resumed) at ", err, re.M)
    more = [int(n) for n in re.findall(r"^modbus: \.\.\. and (\d+) more writes in that second, not logged", err, re.M)]
    return len(lines), sum(more), len(more)


def write_log_and_fresh_reads(rcsim, scenario):
    run = Rcsim(rcsim, scenario, "--monitor", "127.0.0.1:0")
    c = ModbusTcpClient("127.0.0.1", port=run.port, timeout=3)
    try:
        c.connect()
        t0 = time.monotonic()
        for i in range(120):  # pause, resume, ...: every write changes the state
            c.write_coil(PAUSE, i % 2 == 0, slave=1)
        spent = time.monotonic() - t0
        end = time.monotonic() + 10
        while time.monotonic() < end and sum(logged_writes(run.stderr())[:2]) < 120:
            time.sleep(0.05)
        err = run.stderr()
        shown, left_out, summaries = logged_writes(err)
        check(summaries >= 1 and shown + left_out == 120,
              "120 pause writes: %d lines, %d counted in %d summary lines (120 in all)" % (shown, left_out, summaries))
        check(shown <= LINES_PER_SECOND * (int(spent) + 1),
              "at most %d lines a second (%d in %.2f s)" % (LINES_PER_SECOND, shown, spent))
        check("monitor: paused" not in err and "monitor: resumed" not in err, "Modbus writes are logged as modbus:, "
              "not monitor:")

        # A long step: the reads stay fresh.
        c.write_coil(PAUSE, True, slave=1)
        c.write_register(STEP_MS, 60000, slave=1)
        c.write_coil(STEP, True, slave=1)
        seen, api_seen = [], []
        end = time.monotonic() + 1.5
        while time.monotonic() < end:
            seen.append(sim_time_ms(c))
            status, body = http_get("127.0.0.1", run.http_port, "/api/v1/snapshot")
            if status == 200:
                api_seen.append(json.loads(body)["sim_time_s"])
            time.sleep(0.1)
        check(len(set(seen)) >= 3 and seen == sorted(seen) and seen[-1] < seen[0] + 60000,
              "during a 60 s step sim_time advances over Modbus: %s ms" % seen)
        check(len(set(api_seen)) >= 3 and api_seen == sorted(api_seen),
              "... and in the monitor's snapshot: %s s" % api_seen)
    finally:
        c.close()
        run.proc.send_signal(signal.SIGTERM)
        t_term = time.monotonic()
        rc, _, err = run.finish(timeout=HANG_S)
    check(rc == 128 + signal.SIGTERM and time.monotonic() - t_term < 5,
          "SIGTERM during the step ends the run: exit %d in %.2f s" % (rc, time.monotonic() - t_term))
    if failures:
        print(err)


def main(rcsim, short, board):
    step_past_the_end(rcsim, short)
    write_log_and_fresh_reads(rcsim, board)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2], sys.argv[3]))
