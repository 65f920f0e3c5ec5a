"""Every request is validated before it is acted on (issue #33 items 1 and 8): a request with a
field of the wrong type, out of range, not a whole number where one is needed, or missing, gets an
error reply naming the field and its value, and the run goes on; it ends by a signal with its
report. Through tests/scenarios/monitor/abuse.yaml.

usage: requests_test.py RCSIM SCENARIO"""
import json
import os
import shutil
import signal
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import check, failures  # noqa: E402
from wsclient import Rcsim  # noqa: E402


# (request, text the refusal must contain): the field and the value it names.
FLIP = {"op": "inject_fault", "port": 0, "kind": "flip_data_bit"}
REFUSED = [
    ({"op": "subscribe", "path": "x"}, '"path" = "x"'),
    ({"op": "subscribe", "path": None}, '"path" = null'),
    ({"op": "subscribe", "path": 1}, '"path" = 1'),
    ({"op": "subscribe", "period_ms": "fast"}, '"period_ms" = "fast"'),
    ({"op": "subscribe", "period_ms": -1}, '"period_ms" = -1'),
    ({"op": "subscribe", "period_ms": 1e9}, '"period_ms" = 1000000000'),
    ({"op": "subscribe", "clock": "moon"}, '"clock"'),
    ({"op": "subscribe", "clock": 3}, '"clock" = 3'),
    ({"op": "inject_fault", "port": 1, "kind": "flip_cell", "bit": 11, "from": "controller"}, '"bit" = 11'),
    ({"op": "inject_fault", "port": 0, "kind": "flip_cell", "bit": 11}, '"bit" = 11'),
    (dict(FLIP, bit=2.7), '"bit" = 2.7'),
    (dict(FLIP, bit=8), '"bit" = 8'),
    (dict(FLIP, bit=-1), '"bit" = -1'),
    (dict(FLIP, bit="3"), '"bit" = "3"'),
    (dict(FLIP, bit=None), '"bit" = null'),
    (dict(FLIP, bit=[1]), '"bit" = [1]'),
    (dict(FLIP, bit=1e300), '"bit" = 1e+300'),
    ({"op": "inject_fault", "port": 0, "kind": "drop", "bit": 3}, '"bit" applies to'),
    (dict(FLIP, bit=0, port=3), '"port" = 3'),
    (dict(FLIP, bit=0, port=-1), '"port" = -1'),
    (dict(FLIP, bit=0, port=1.5), '"port" = 1.5'),
    (dict(FLIP, bit=0, port="0"), '"port" = "0"'),
    (dict(FLIP, bit=0, port=True), '"port" = true'),
    (dict(FLIP, bit=0, **{"from": "both"}), '"from"'),
    ({"op": "inject_fault", "port": 0}, 'missing "kind"'),
    ({"op": "inject_fault", "port": 0, "kind": 5}, '"kind" = 5'),
    ({"op": "inject_fault", "port": 0, "kind": "melt"}, "'melt'"),
    ({"op": "inject_fault", "port": 0, "kind": "break", "duration_ms": 0}, '"duration_ms" = 0'),
    ({"op": "inject_fault", "port": 0, "kind": "break", "duration_ms": -3}, '"duration_ms" = -3'),
    ({"op": "inject_fault", "port": 0, "kind": "break", "duration_ms": "5"}, '"duration_ms" = "5"'),
    ({"op": "inject_fault", "port": 0, "kind": "break", "duration_ms": 1e6}, '"duration_ms" = 1000000'),
    ({"op": "step"}, 'missing "ms"'),
    ({"op": "step", "ms": "1"}, '"ms" = "1"'),
    ({"op": "step", "ms": 0}, '"ms" = 0'),
    ({"op": "step", "ms": 1e9}, '"ms" = 1000000000'),
    ({"op": "step", "ms": True}, '"ms" = true'),
    ({"op": "set_rtf"}, 'missing "rtf"'),
    ({"op": "set_rtf", "rtf": -1}, '"rtf" = -1'),
    ({"op": "set_rtf", "rtf": 0.001}, '"rtf"'),
    ({"op": "set_rtf", "rtf": "x"}, '"rtf" = "x"'),
    ({"op": "send_frame", "port": 0}, 'missing "token"'),
    ({"op": "send_frame", "port": 0, "token": "ABC"}, '"token"'),
    ({"op": "send_frame", "port": 0, "token": "EC", "data": 5}, '"data" = 5'),
    ({"op": "send_frame", "port": 2.5, "token": "EC"}, '"port" = 2.5'),
    ({"op": "send_frame", "port": 1, "token": "EC"}, "port 1 has no protocol host"),
    ({"op": "motion"}, 'missing "token"'),
    ({"op": "motion", "token": 5}, '"token" = 5'),
    ({"op": "motion", "token": "SV", "data": []}, '"data" = []'),
    ({"op": "warp"}, "unknown op 'warp'"),
]


def main(rcsim, scenario):
    out = tempfile.mkdtemp(prefix="rcsim-monitor-requests-")
    run = Rcsim(rcsim, scenario, "--out", out)
    try:
        ws = run.ws()
        ws.recv()
        for req, expect in REFUSED:
            try:
                r = ws.request(req)
            except (ConnectionError, TimeoutError, OSError) as e:
                check(False, "%s: answered, the client stays (%s)" % (json.dumps(req), e))
                if run.proc.poll() is not None:
                    break
                ws = run.ws()
                ws.recv()
                continue
            check(r.get("type") == "error" and expect in r.get("error", ""),
                  "%s refused naming %s: %s" % (json.dumps(req), expect, r.get("error", r)))
        # In range and whole: accepted (port 1 has no host; the controller's 8E1 has cells 0..10).
        if run.proc.poll() is not None:
            raise RuntimeError("the run ended")
        r = ws.request({"op": "inject_fault", "port": 1, "kind": "flip_cell", "bit": 10, "from": "controller"})
        check(r.get("type") == "ok", "flip_cell bit 10 of the controller's 8E1 character is accepted: %s" % r)
        r = ws.request({"op": "subscribe", "clock": "sim", "period_ms": 5.0, "path": False})
        check(r.get("type") == "ok", "subscribe with path false is accepted: %s" % r)
        t0 = ws.request({"op": "snapshot"})["data"]["sim_time_s"]
        time.sleep(0.3)
        t1 = ws.request({"op": "snapshot"})["data"]["sim_time_s"]
        check(t1 > t0, "the run goes on after the refused requests (%.3f -> %.3f s)" % (t0, t1))
    except (RuntimeError, ConnectionError, TimeoutError, OSError) as e:
        check(False, "the run goes on: %s" % e)
    finally:
        if failures:
            run.kill()
            print(run.stderr())
            return 1
    if run.proc.poll() is None:
        run.proc.send_signal(signal.SIGINT)
    rc, _, err = run.finish()
    check(rc == 130, "SIGINT ends the run with exit 130 (got %d)" % rc)
    try:
        with open(os.path.join(out, "report.json")) as f:
            verdict = json.load(f).get("verdict")
    except (OSError, ValueError) as e:
        verdict = "no report.json: %s" % e
    check(verdict == "interrupted", "report.json is written with verdict interrupted (%s)" % verdict)
    check("internal error" not in err, "no internal error")
    if failures:
        print(err)
    shutil.rmtree(out, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
