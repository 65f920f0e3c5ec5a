"""The monitor's JSON API (docs/monitor.md) driven through a short run of tests/scenarios/monitor/board.yaml:
subscribe, pause, step, resume, a motion command that moves an axis, a frame sent as the host,
a line fault, several clients, and the clients the server must drop (garbage, a huge message, a
disconnect) while the run goes on.

usage: api_test.py RCSIM SCENARIO"""
import os
import signal
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import check, failures  # noqa: E402
from wsclient import HANG_S, Rcsim, http_get  # noqa: E402


def updates(ws, n, timeout=HANG_S):
    out = []
    while len(out) < n:
        out.append(ws.recv_until(lambda m: m.get("type") == "update", timeout))
    return out


def wait_state(ws, pred, timeout=HANG_S):
    """The first update whose data satisfies pred."""
    return ws.recv_until(lambda m: m.get("type") == "update" and pred(m["data"]), timeout)


def snapshot(ws):
    return ws.request({"op": "snapshot"})["data"]


def wait_snapshot(ws, pred, timeout=HANG_S):
    """The first snapshot that satisfies pred (asked every 20 ms), else the last one."""
    end = time.monotonic() + timeout
    s = snapshot(ws)
    while not pred(s) and time.monotonic() < end:
        time.sleep(0.02)
        s = snapshot(ws)
    return s


def main(rcsim, scenario):
    run = Rcsim(rcsim, scenario)
    try:
        body_checks(run)
    finally:
        if failures:
            run.kill()
            print(run.stderr())
    if failures:
        return 1
    run.proc.send_signal(signal.SIGINT)
    rc, out, err = run.finish(timeout=HANG_S)
    check(rc == 130, "SIGINT ends the monitored run with its reports (exit 130, got %d)" % rc)
    for why in ("disconnected", "sent garbage", "over 65536 bytes"):
        check(why in err, "the log names the dropped client: '%s'" % why)
    check("paused at" in err and "resumed at" in err, "the log records pause and resume")
    if failures:
        print(out, err)
    return 1 if failures else 0


def body_checks(run):
    # Plain HTTP: the page and the snapshot.
    status, page = http_get("127.0.0.1", run.port, "/")
    check(status == 200 and b'<canvas id="plot"' in page, "GET / serves the live page")
    check(b"http://" not in page and b"https://" not in page and b"<script src" not in page,
          "the page loads nothing from the network (script inline, no CDN)")
    status, _ = http_get("127.0.0.1", run.port, "/nowhere")
    check(status == 404, "an unknown path is 404")

    a = run.ws()
    hello = a.recv()
    check(hello.get("type") == "hello" and hello.get("api") == 1, "the server greets with API version 1")

    # Subscription in simulated time: one update every 10 ms of simulated time, exactly.
    r = a.request({"op": "subscribe", "clock": "sim", "period_ms": 10})
    check(r["type"] == "ok", "subscribe (sim clock, 10 ms)")
    ts = [u["data"]["sim_time_s"] for u in updates(a, 6)]
    gaps = [round(ts[i + 1] - ts[i], 9) for i in range(len(ts) - 1)]
    check(all(g == 0.010 for g in gaps), "sim-clock updates come 10 ms of simulated time apart: %s" % gaps)
    a.request({"op": "subscribe", "clock": "sim", "period_ms": 100})  # fewer, while it is not read

    # Several clients at once: a second one subscribed in wall time gets its own updates. Their
    # rate by the server's clock (each update's wall_time_s, taken as it is made): what a loaded
    # host adds on the way to this client is not the server's.
    b = run.ws()
    b.recv()
    b.request({"op": "subscribe", "clock": "wall", "period_ms": 50})
    walls = [u["data"]["wall_time_s"] for u in updates(b, 10)]
    rate = (len(walls) - 1) / (walls[-1] - walls[0])
    check(rate >= 10, "a second client's wall-clock updates come at %.1f/s (>= 10/s at a 50 ms period)" % rate)
    check(len(updates(a, 2)) == 2, "the first client is still served")

    # A request that cannot be done is answered, and the client stays.
    r = a.request({"op": "warp"})
    check(r["type"] == "error" and "unknown op" in r["error"], "an unknown op gets an error reply")
    r = a.request({"op": "step", "ms": -5})
    check(r["type"] == "error" and "out of range" in r["error"], "a negative step is refused: " + r.get("error", ""))

    # Pause: simulated time stands still; step advances it by exactly the asked amount.
    r = a.request({"op": "pause"})
    paused_at = r["sim_time_s"]
    time.sleep(0.5)
    s = a.request({"op": "snapshot"})["data"]
    check(s["paused"] and s["sim_time_s"] == paused_at,
          "paused: simulated time stays at %.6f s over 0.5 s of wall time" % paused_at)
    r = a.request({"op": "step", "ms": 20})
    check(abs(r["sim_time_s"] - (paused_at + 0.020)) < 1e-9, "step 20 ms: %.6f -> %.6f s" % (paused_at, r["sim_time_s"]))
    s = a.request({"op": "snapshot"})["data"]
    check(s["paused"], "the run is still paused after a step")

    # A paused run with no client keeps its state: the HTTP snapshot (no client of its own) shows
    # when the server has seen both go.
    b.close()
    a.close()
    end = time.monotonic() + HANG_S
    while True:
        gone = b'"clients":0' in http_get("127.0.0.1", run.port, "/api/v1/snapshot")[1]
        if gone or time.monotonic() > end:
            break
        time.sleep(0.02)
    check(gone, "the server counts no client once both closed")
    a = run.ws()
    a.recv()
    s = snapshot(a)
    check(s["paused"] and abs(s["sim_time_s"] - (paused_at + 0.020)) < 1e-9,
          "with every client gone the run stays paused at the same time")

    r = a.request({"op": "resume"})
    check(r["type"] == "ok", "resume")
    time.sleep(0.2)

    # Pause for a second (no step: nothing else touches the pacer), then resume at real time (rtf
    # 1, the scenario's): the pacer measures from the resume, so the run does not race to make up
    # the second it stood still: over about 0.5 s of wall time, at most as much simulated time
    # passes (+0.15 s for the slices). Both clocks are the server's (a snapshot's sim_time_s and
    # wall_time_s are read together), from a snapshot taken before the resume.
    a.request({"op": "pause"})
    time.sleep(1.0)
    before = snapshot(a)
    a.request({"op": "resume"})
    time.sleep(0.5)
    after = wait_snapshot(a, lambda s: s["sim_time_s"] > before["sim_time_s"])
    sim, wall = after["sim_time_s"] - before["sim_time_s"], after["wall_time_s"] - before["wall_time_s"]
    check(0 < sim <= wall + 0.15, "after resume, %.3f s simulated in %.3f s wall at rtf 1 (pacer rebased)" % (sim, wall))

    # A motion command through the main CPU's dispatcher: servo on, then MA to 2000 pulses.
    a.request({"op": "subscribe", "clock": "wall", "period_ms": 20, "path": False})
    r = a.request({"op": "motion", "token": "SV", "data": "1"})
    check(r["type"] == "ok" and r["bch"] == 0, "SV 1 accepted (BCH 00)")
    wait_state(a, lambda d: d["motion"]["axes"][0]["state"] == "STANDSTILL")
    r = a.request({"op": "motion", "token": "MA", "data": "0,2000,20000,200000,200000"})
    check(r["type"] == "ok" and r["bch"] == 0, "MA 0,2000,... accepted (BCH 00)")
    moving = wait_state(a, lambda d: d["motion"]["axes"][0]["state"] == "DISCRETE_MOTION")
    check(moving is not None, "axis 0 enters DiscreteMotion")
    done = wait_state(a, lambda d: d["motion"]["axes"][0]["state"] == "STANDSTILL", timeout=5)
    ax = done["data"]["motion"]["axes"][0]
    check(ax["cmd"] == 2000, "axis 0's command position ends at the target, 2000 pulses (got %s)" % ax["cmd"])
    r = a.request({"op": "motion", "token": "MA", "data": "9,0,1,1,1"})
    check(r["type"] == "ok" and r["bch"] == 2, "MA on axis 9 is refused with BCH 02 (bad parameter)")

    # A frame sent as port 0's host would: EC echoes its data (docs/system.md §7).
    r = a.request({"op": "send_frame", "port": 0, "token": "EC", "data": "hello"})
    check(r["type"] == "ok", "send_frame EC on port 0")
    d = wait_state(a, lambda d: (d["ports"][0]["last_sent"] or {}).get("data") == "hello", timeout=5)["data"]
    check(d["ports"][0]["last_received"]["token"] == "EC", "the main CPU received the EC frame")
    r = a.request({"op": "send_frame", "port": 1, "token": "EC", "data": "x"})
    check(r["type"] == "error", "send_frame on a port without a protocol host is refused")
    r = a.request({"op": "send_frame", "port": 0.5, "token": "EC"})
    check(r["type"] == "error" and "whole number" in r["error"], "a fractional port is refused")
    r = a.request({"op": "motion", "token": 5})
    check(r["type"] == "error" and "must be a string" in r["error"], "a token that is not a string is refused")

    # A line fault: one data bit of the host's next character flipped, so the 82510 sees one parity
    # error (8E1: the parity bit no longer matches), and the host's frame still gets through on retry.
    pe = a.request({"op": "snapshot"})["data"]["ports"][0]["uart"]["parity_errors"]
    r = a.request({"op": "inject_fault", "port": 0, "kind": "flip_data_bit", "bit": 0})
    check(r["type"] == "ok", "inject_fault flip_data_bit on port 0")
    a.request({"op": "send_frame", "port": 0, "token": "EC", "data": "again"})
    d = wait_state(a, lambda d: (d["ports"][0]["last_sent"] or {}).get("data") == "again", timeout=5)["data"]
    check(d["ports"][0]["uart"]["parity_errors"] == pe + 1,
          "the 82510 counted exactly one parity error (%d -> %d)" % (pe, d["ports"][0]["uart"]["parity_errors"]))

    # Faults wait for the side's next characters; port 1's host sends none, so they would pile up
    # without end (issue #48): 64 are taken, the 65th is refused with the reason, the run goes on.
    replies = [a.request({"op": "inject_fault", "port": 1, "kind": "drop"}) for _ in range(65)]
    check(all(r["type"] == "ok" for r in replies[:64]), "64 faults waiting on port 1 are taken")
    check(replies[64]["type"] == "error" and
          "port 1's line already has 64 faults waiting for characters from the host" in replies[64]["error"],
          "the 65th is refused naming the bound (%s)" % replies[64])
    check(a.request({"op": "inject_fault", "port": 1, "kind": "drop", "from": "controller"})["type"] == "ok",
          "the other side of the line has its own 64")

    # Clients the server must drop; the run and the first client go on.
    for name, payload in (("garbage", b"this is not json"), ("huge", b'"' + b"x" * 100000 + b'"')):
        c = run.ws()
        c.recv()
        try:
            c.send_raw(payload)  # the server may close before the whole huge message is sent
            while True:
                c.recv()
        except ConnectionError:  # closed by the server (a timeout is no disconnection)
            check(True, "the %s client is disconnected" % name)
        except TimeoutError:
            check(False, "the %s client is disconnected (it is still connected after %d s)" % (name, HANG_S))
        c.close()
    c = run.ws()
    c.recv()
    c.sock.close()  # gone without a close frame
    t_before = snapshot(a)["sim_time_s"]
    t_after = wait_snapshot(a, lambda s: s["sim_time_s"] > t_before)["sim_time_s"]
    check(t_after > t_before, "the run goes on after the dropped clients")

    # The HTTP snapshot is the same document as the API's.
    status, body = http_get("127.0.0.1", run.port, "/api/v1/snapshot")
    check(status == 200 and b'"api":1' in body, "GET /api/v1/snapshot")

    # Faster: at rtf 4 simulated time runs faster than the rtf 1 so far. The pacer holds
    # simulated time to 4x the wall time since set_rtf rebased it; a run that fell behind that
    # line may catch up later at full speed, so the upper bound is taken from before set_rtf, not
    # from s0. Both clocks are the server's (a snapshot reads them together). The window is at
    # least 0.6 s (longer than any slice) and grows until the run has shown more than 1.5x: a
    # host too loaded to keep the pace for a moment still gets there, a run held to rtf 1 never.
    pre = snapshot(a)
    r = a.request({"op": "set_rtf", "rtf": 4})
    check(r["type"] == "ok", "set_rtf 4")
    s0 = snapshot(a)
    time.sleep(0.6)

    def faster(s):
        return s["sim_time_s"] - s0["sim_time_s"] > 1.5 * (s["wall_time_s"] - s0["wall_time_s"])
    s1 = wait_snapshot(a, faster)
    sim, wall = s1["sim_time_s"] - s0["sim_time_s"], s1["wall_time_s"] - s0["wall_time_s"]
    check(sim > 1.5 * wall, "at rtf 4, %.3f s simulated in %.3f s wall (more than 1.5x)" % (sim, wall))
    sim, wall = s1["sim_time_s"] - pre["sim_time_s"], s1["wall_time_s"] - pre["wall_time_s"]
    check(sim <= 4 * wall + 0.15,
          "at rtf 4, no more than 4x wall time since set_rtf (+0.15 s): %.3f s simulated in %.3f s wall" % (sim, wall))
    a.close()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
