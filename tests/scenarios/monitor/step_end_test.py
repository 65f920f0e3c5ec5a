"""The monitor's `step` op never passes the run's end (issue #48 item 1; docs/monitor.md "WebSocket
API"): on tests/scenarios/monitor/short.yaml (duration_s 1, paced at 0.1) a client pauses at
once and asks for a step of 60 s, then another. The first reply says the step stopped at 1 s, the
scenario's end; the run ends there and drains what is in flight (report.json sim_time_s at
most 2 s), says so on stderr, and exits with its verdict's code, passed. (tests/scenarios/modbus/step_test.py does the same through the step coil, and checks
that reads stay fresh while a long step runs.)

usage: step_end_test.py RCSIM SCENARIO"""
import json
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import check, failures  # noqa: E402
from wsclient import HANG_S, Rcsim  # noqa: E402

EXIT_OF = {"passed": 0, "failed": 1, "inconclusive": 4}  # docs/scenarios.md "Verdicts and exit codes"


def main(rcsim, scenario):
    out = tempfile.TemporaryDirectory(prefix="rcsim-step-end-")
    run = Rcsim(rcsim, scenario, "--out", out.name)
    ws = run.ws()
    try:
        r = ws.request({"op": "pause"})
        check(r["type"] == "ok" and r["sim_time_s"] < 0.9, "paused at %s s, before the end at 1 s" % r.get("sim_time_s"))
        ws.send({"op": "step", "ms": 60000, "id": "first"})
        ws.send({"op": "step", "ms": 60000, "id": "second"})  # queued behind it: would run 60 s more
        r = ws.recv_until(lambda m: m.get("id") == "first")
        check(r["type"] == "ok" and r["sim_time_s"] == 1.0 and r["at_end"] is True,
              "the reply: stopped at 1 s, at the end (%s)" % r)
        check("the scenario's end (duration_s)" in r.get("note", "") and "the run ends" in r.get("note", ""),
              "... and says why: %r" % r.get("note"))
    finally:
        ws.close()
    rc, _, err = run.finish(timeout=HANG_S)
    with open(os.path.join(out.name, "report.json")) as f:
        report = json.load(f)
    check(1.0 <= report["sim_time_s"] <= 2.0, "the run ends at %.6f s (1 s and a drain of at most 1 s)"
          % report["sim_time_s"])
    check("monitor: a step of 60000 ms from " in err and "stopped at 1 s, the scenario's end (duration_s); the run ends "
          "there" in err, "stderr says so:\n" + err)
    # Passed as the scenario does when run to its end: the step took nothing from it.
    check(report["verdict"] == "passed" and rc == EXIT_OF[report["verdict"]],
          "the run ends as any run does: exit %d for verdict %s" % (rc, report["verdict"]))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
