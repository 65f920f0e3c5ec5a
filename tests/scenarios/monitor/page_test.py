"""The live page in headless Chromium at 1280 px, driven through Chromium's DevTools protocol and
checked from its DOM and geometry (not pixel by pixel); a screenshot is saved.

  motion: it draws the X-Y plot of the circle the scenario commands (tests/scenarios/monitor/plot.yaml),
          shows the same axis positions as the API and the function blocks as readable states.
  comm:   a communication-only run (tests/scenarios/monitor/comm.yaml) shows no motion panel; per interrupt
          source the latency and service max / p99 as the API has them, each red only over its own
          limit (issue #51), the worst case, its time and its cause each in a cell of one unit; the
          verdict so far; the margin strip; the ports table fits 1280 px; no empty log box.

usage: page_test.py RCSIM SCENARIO SCREENSHOT.png [motion|comm]
Exit 77 (skipped) when Chromium is not installed."""
import base64
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import check, failures  # noqa: E402
from wsclient import HANG_S, Rcsim, WebSocket, http_get  # noqa: E402


# report.json's names of the interrupt sources, by level (the blocking check's detail).
SOURCE_KEYS = ["rs232_0", "rs232_1", "rs232_2", "dpram"]

# The circle of tests/scenarios/monitor/plot.yaml: centre (-5000, 0), radius 5000 pulses.
CX, CY, R = -5000, 0, 5000
# The commanded path stays within 1 pulse of the circle (docs/motion.md, circle_radial_error_pulses).
MAX_RADIAL_ERROR = 1.0

# What the page shows, read from its DOM.
DOM_STATE = """JSON.stringify({
  status: document.getElementById("status").textContent,
  points: Number(document.getElementById("plot").dataset.points),
  drawn: (() => { const c = document.getElementById("plot"), d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
                  let n = 0; for (let i = 0; i < d.length; i += 4) if (d[i + 3] > 0 && d[i + 2] > 150 && d[i] < 90) n++; return n; })(),
  axes: [0, 1].map(a => { const e = (k) => document.getElementById("axis-" + a + "-" + k);
                           return e("cmd") ? {cmd: e("cmd").textContent, act: e("act").textContent, state: e("state").textContent} : null; })
})"""


# The page's layout and what it shows besides the plot.
DOM_LAYOUT = """JSON.stringify({
  status: document.getElementById("status").textContent,
  motion_shown: getComputedStyle(document.getElementById("motion-panels")).display !== "none",
  motion_height: document.getElementById("motion-panels").getBoundingClientRect().height,
  client_width: document.documentElement.clientWidth,
  scroll_width: document.documentElement.scrollWidth,
  ports_right: document.getElementById("ports").getBoundingClientRect().right,
  ports_rows: document.querySelectorAll("#ports tr").length,
  budget: document.getElementById("budget").textContent,
  verdict: document.getElementById("verdict").textContent,
  irq: [0, 1, 2, 3].map(l => { const r = document.getElementById("irq-" + l);
                               return r ? Array.from(r.cells).map(c => c.textContent) : null; }),
  irq_red: [0, 1, 2, 3].map(l => { const r = document.getElementById("irq-" + l);
                                   return r ? Array.from(r.cells).map(c => c.classList.contains("over") ||
                                                                      c.querySelector(".over") !== null) : null; }),
  log_height: document.getElementById("log").getBoundingClientRect().height,
  strip: Number(document.getElementById("margin-strip").dataset.points),
  worst_margin: document.getElementById("worst-margin") ? document.getElementById("worst-margin").textContent : null,
  margin: document.getElementById("margin") ? document.getElementById("margin").textContent : null,
  fb_states: Array.from(document.querySelectorAll(".fbstate")).map(e => e.textContent),
  fb_ids: Array.from(document.querySelectorAll(".fbstate")).map(e => e.id)
})"""
# What a function block may read as (page.html fbState).
FB_STATE = re.compile(r"^(Idle|Triggered|Busy|Active|Done|Aborted|Error( 0x[0-9a-f]+)?|Off|Powering up|Powered)$")


def find_chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


class DevTools:
    def __init__(self, port):
        # Chromium announces its DevTools port before its first page exists: ask until it does.
        end = time.monotonic() + HANG_S
        while True:
            status, body = http_get("127.0.0.1", port, "/json/list")
            page = next((t for t in json.loads(body) if t["type"] == "page"), None) if status == 200 else None
            if page or time.monotonic() > end:
                break
            time.sleep(0.05)
        if not page:
            raise RuntimeError("Chromium has no page target: " + body.decode(errors="replace"))
        path = re.sub(r"^ws://[^/]+", "", page["webSocketDebuggerUrl"])
        self.ws = WebSocket("127.0.0.1", port, path)
        self.next = 0

    def call(self, method, **params):
        self.next += 1
        self.ws.send({"id": self.next, "method": method, "params": params})
        m = self.ws.recv_until(lambda m: m.get("id") == self.next)
        if "error" in m:
            raise RuntimeError(method + ": " + json.dumps(m["error"]))
        return m["result"]

    def dom(self, expression=DOM_STATE):
        """The page's state, None while it is not loaded (the expression throws)."""
        r = self.call("Runtime.evaluate", expression=expression, returnByValue=True)
        if "exceptionDetails" in r or "value" not in r["result"]:
            return None
        return json.loads(r["result"]["value"])


def start_chromium(exe, profile):
    proc = subprocess.Popen([exe, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                             "--disable-extensions", "--remote-debugging-port=0", "--user-data-dir=" + profile,
                             "--window-size=1280,1100", "about:blank"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    end = time.monotonic() + HANG_S  # a loaded host starts Chromium slowly
    while time.monotonic() < end:
        line = proc.stderr.readline()
        m = re.search(r"DevTools listening on ws://127\.0\.0\.1:(\d+)/", line)
        if m:
            return proc, int(m.group(1))
        if not line and proc.poll() is not None:
            break
    proc.kill()
    raise RuntimeError("Chromium did not open its DevTools port")


def wait_dom(dt, pred, timeout, expression=DOM_STATE):
    end = time.monotonic() + timeout
    d = dt.dom(expression)
    while (d is None or not pred(d)) and time.monotonic() < end:
        time.sleep(0.1)
        d = dt.dom(expression)
    if d is None:
        raise RuntimeError("the page did not load")
    return d


def check_layout(check, lay):
    """What both runs must show: a page no wider than the 1280 px window, the ports table in it."""
    check(lay["client_width"] <= 1280 and lay["scroll_width"] <= lay["client_width"],
          "the page fits the 1280 px window (scroll width %d, window %d)" % (lay["scroll_width"], lay["client_width"]))
    check(lay["ports_right"] <= lay["client_width"] and lay["ports_rows"] == 4,
          "the ports table (3 ports) ends at %.0f px, within the window" % lay["ports_right"])


def shown(text, value):
    """The page shows `value` to one decimal (JavaScript's toFixed rounds a tie up, Python's to even)."""
    try:
        return abs(float(text) - value) <= 0.05 + 1e-9
    except ValueError:
        return False


def comm_checks(check, dt, run, api):
    """A communication-only run: no motion panels; interrupts against the budget as the API has them."""
    lay = wait_dom(dt, lambda d: d["strip"] >= 3 and all(r and r[11] for r in d["irq"][:3]),
                   timeout=HANG_S, expression=DOM_LAYOUT)
    check(not lay["motion_shown"] and lay["motion_height"] == 0, "no motion panel on a communication-only run")
    check(lay["strip"] >= 3, "the margin strip has %d points" % lay["strip"])
    api.request({"op": "pause"})
    snap = api.request({"op": "snapshot"})["data"]
    check(snap["motion"] is None, "the API has no motion layer either")
    # The first update the page shows as paused was made after the pause, of the state the
    # snapshot has (the simulation stands still between them).
    lay = wait_dom(dt, lambda d: d["status"] == "paused", timeout=HANG_S, expression=DOM_LAYOUT)
    check(lay["status"] == "paused", "the page shows the run paused")
    budget = snap["table3"]["budget_us"]
    check(shown(lay["budget"], budget), "the budget on the page: %s us (API %.3f)" % (lay["budget"], budget))
    # One judge: the page says the API's verdict so far.
    words = {"passed": "PASSING", "failed": "FAILING", "inconclusive": "NOT MEASURED YET"}
    check(lay["verdict"] == words[snap["verdict"]["verdict"]],
          "the page's verdict %r is the API's %r" % (lay["verdict"], snap["verdict"]["verdict"]))
    blocking = next(c for c in snap["verdict"]["checks"] if c["name"] == "interrupt_blocking_max_us")
    dpram = snap["interrupts"][3]
    print("DP-RAM service max %.1f us, budget %.1f us, its latencies over budget %d" % (
        dpram["service_us"]["max"], budget, dpram["over_budget"]))
    check(lay["log_height"] == 0, "no empty log box under the buttons (%.0f px high)" % lay["log_height"])
    for src in snap["interrupts"]:
        row = lay["irq"][src["level"]]
        lat, svc = src["latency_us"], src["service_us"]
        check(row is not None and lat is not None and shown(row[3], lat["max"]) and shown(row[4], lat["p99"])
              and shown(row[5], svc["max"]) and shown(row[6], svc["p99"]),
              "%s: latency max/p99 %s/%s, service max/p99 %s/%s as the API's (%s, %s)" % (
                  src["name"], row and row[3], row and row[4], row and row[5], row and row[6], lat, svc))
        # One unit per cell (issue #51: "at 5.1470 s" and "since 5146975.500 us" in one cell).
        worst = src["worst"]
        check(row is not None and worst is not None and row[11] == worst["cause"] and
              shown(row[9], worst["latency_us"]) and re.fullmatch(r"\d+\.\d{4}", row[10]) is not None and
              abs(float(row[10]) - worst["t_s"]) <= 0.00005 + 1e-9,
              "%s: the worst latency %s us, at %s s and its cause, each in its own cell: %s" % (
                  src["name"], row and row[9], row and row[10], row and row[11][:90]))
        # Red only over its own limit: latency over the budget, blocking over the rule's limit; a
        # service time never (the DP-RAM's service is longer than the budget by design).
        red = lay["irq_red"][src["level"]]
        limit = blocking["limit"]
        blocked = blocking["detail"][SOURCE_KEYS[src["level"]]]["blocking_us"]
        want = [lat["max"] > budget, lat["p99"] > budget, False, False, blocked > limit, src["over_budget"] > 0]
        check(red[3:9] == want and shown(row[7], blocked),
              "%s: red cells latency max/p99, service max/p99, blocking %s (limit %.1f), over budget: %s, want %s" % (
                  src["name"], row[7], limit, red[3:9], want))
    check(shown(lay["worst_margin"], snap["table3"]["worst_margin_us"]),
          "the worst-case margin %s us, the API's" % lay["worst_margin"])
    check_layout(check, lay)


def fb_label(f):
    """A block's state from its outputs (PLCopen Part 1 2.4.1: Error, CommandAborted, Busy/Active and
    Done exclude each other; MC_Power: Status is the axis powered)."""
    if f.get("error"):
        return "Error" + (" 0x%x" % f["error_id"] if f.get("error_id") else "")
    if f["name"] == "MC_Power":
        return "Powered" if f["status"] else "Powering up" if f["enable"] else "Off"
    if f["aborted"]:
        return "Aborted"
    if f["busy"]:
        return "Active" if f["active"] else "Busy"
    if f["done"]:
        return "Done"
    return "Triggered" if f["execute"] else "Idle"


def motion_checks(check, dt, snap):
    """A motion run: the panels are there, each function block reads as one state, the API's."""
    lay = wait_dom(dt, lambda d: "Powered" in d["fb_states"], timeout=HANG_S, expression=DOM_LAYOUT)
    check(lay["motion_shown"] and lay["motion_height"] > 500, "the motion panels are shown (%.0f px)" % lay["motion_height"])
    bad = [t for t in lay["fb_states"] if not FB_STATE.match(t)]
    check(lay["fb_states"] and not bad, "every function block reads as one state (%d; not: %s)" % (len(lay["fb_states"]), bad))
    states = dict(zip(lay["fb_ids"], lay["fb_states"]))
    check(all(states.get("fb-MC_Power-%d" % a) == "Powered" for a in range(4)), "MC_Power after SV 1: Powered on every axis")
    wrong = []
    for f in snap["motion"]["fbs"]:
        fid = "fb-" + f["name"] + ("" if f["axis"] < 0 else "-%d" % f["axis"])
        if states.get(fid) != fb_label(f):
            wrong.append((fid, states.get(fid), fb_label(f)))
    check(len(states) == len(snap["motion"]["fbs"]) and not wrong,
          "each of the %d blocks reads as its outputs in the API say (wrong: %s)" % (len(states), wrong))
    check(lay["strip"] == 0 and lay["margin"] == "not measured",
          "no RS-232 receive service: the margin and its strip read 'not measured' (%s)" % lay["margin"])
    check_layout(check, lay)


def main(rcsim, scenario, screenshot, kind="motion"):
    exe = find_chromium()
    if not exe:
        print("SKIP: no Chromium on this machine (scripts/install-deps.sh installs Debian's chromium)")
        return 77
    t0 = time.monotonic()
    run = Rcsim(rcsim, scenario)
    profile = tempfile.mkdtemp(prefix="rcsim-chromium-")
    browser = None
    try:
        browser, port = start_chromium(exe, profile)
        print("Chromium's DevTools up after %.1f s" % (time.monotonic() - t0))
        dt = DevTools(port)
        dt.call("Page.enable")
        dt.call("Page.navigate", url=run.url)
        if kind == "comm":
            api = run.ws()
            api.recv()
            comm_checks(check, dt, run, api)
            api.close()
            save(check, dt, screenshot)
            return 1 if failures else 0
        # The plot draws as the circle is commanded: wait for a good part of it.
        d = wait_dom(dt, lambda d: d["points"] >= 200 and d["drawn"] >= 200, timeout=HANG_S)
        print("page drawn after %.1f s" % (time.monotonic() - t0))
        check(d["points"] >= 200, "the plot has %d points of the commanded path" % d["points"])
        check(d["drawn"] >= 200, "the canvas has %d pixels in the commanded path's blue" % d["drawn"])

        # Pause, then the DOM must show what the API says, and the position must be on the circle.
        api = run.ws()
        api.recv()
        api.request({"op": "pause"})
        snap = api.request({"op": "snapshot"})["data"]
        axes = snap["motion"]["axes"]
        d = wait_dom(dt, lambda d: d["status"] == "paused", timeout=HANG_S)
        check(d["status"] == "paused", "the page shows the run paused")
        d = dt.dom()
        for a in (0, 1):
            check(d["axes"][a] is not None and int(d["axes"][a]["cmd"]) == axes[a]["cmd"]
                  and int(d["axes"][a]["act"]) == axes[a]["act"],
                  "axis %d on the page: command %s actual %s, as the API (%s, %s)"
                  % (a, d["axes"][a] and d["axes"][a]["cmd"], d["axes"][a] and d["axes"][a]["act"],
                     axes[a]["cmd"], axes[a]["act"]))
        x, y = axes[0]["cmd"], axes[1]["cmd"]
        radial = abs(((x - CX) ** 2 + (y - CY) ** 2) ** 0.5 - R)
        check(radial <= MAX_RADIAL_ERROR, "the paused command position (%d, %d) is %.2f pulses off the circle" % (x, y, radial))
        motion_checks(check, dt, snap)
        save(check, dt, screenshot)
        api.close()
    finally:
        if browser:
            browser.kill()
            browser.communicate()
        shutil.rmtree(profile, ignore_errors=True)
        run.proc.send_signal(signal.SIGINT)
        try:
            run.finish(timeout=HANG_S)
        except subprocess.TimeoutExpired:
            run.kill()
            failures.append("rcsim did not end on SIGINT")
    return 1 if failures else 0


def save(check, dt, screenshot):
    # The whole page, not only the window: the screenshot shows every panel.
    metrics = dt.call("Page.getLayoutMetrics")
    h = int(metrics["cssContentSize"]["height"])
    shot = dt.call("Page.captureScreenshot", format="png", captureBeyondViewport=True,
                   clip={"x": 0, "y": 0, "width": 1280, "height": h, "scale": 1})
    with open(screenshot, "wb") as f:
        f.write(base64.b64decode(shot["data"]))
    check(os.path.getsize(screenshot) > 10000, "screenshot saved: " + screenshot)


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:5]))
