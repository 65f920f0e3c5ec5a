"""The live page in headless Chromium: it loads from rcsim's monitor, draws the X-Y plot of the
circle the scenario commands (tests/monitor/plot.yaml), and shows the same axis positions as the
API. The page is driven through Chromium's DevTools protocol; a screenshot is saved.

usage: page_test.py RCSIM SCENARIO SCREENSHOT.png
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

from wsclient import Rcsim, WebSocket, http_get

# The circle of tests/monitor/plot.yaml: centre (-5000, 0), radius 5000 pulses.
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


def find_chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


class DevTools:
    def __init__(self, port):
        status, body = http_get("127.0.0.1", port, "/json/list")
        page = next(t for t in json.loads(body) if t["type"] == "page")
        path = re.sub(r"^ws://[^/]+", "", page["webSocketDebuggerUrl"])
        self.ws = WebSocket("127.0.0.1", port, path)
        self.next = 0

    def call(self, method, **params):
        self.next += 1
        self.ws.send({"id": self.next, "method": method, "params": params})
        m = self.ws.recv_until(lambda m: m.get("id") == self.next, timeout=10)
        if "error" in m:
            raise RuntimeError(method + ": " + json.dumps(m["error"]))
        return m["result"]

    def dom(self):
        """The page's state, None while it is not loaded (the expression throws)."""
        r = self.call("Runtime.evaluate", expression=DOM_STATE, returnByValue=True)
        if "exceptionDetails" in r or "value" not in r["result"]:
            return None
        return json.loads(r["result"]["value"])


def start_chromium(exe, profile):
    proc = subprocess.Popen([exe, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                             "--disable-extensions", "--remote-debugging-port=0", "--user-data-dir=" + profile,
                             "--window-size=1280,1100", "about:blank"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    end = time.monotonic() + 8
    while time.monotonic() < end:
        line = proc.stderr.readline()
        m = re.search(r"DevTools listening on ws://127\.0\.0\.1:(\d+)/", line)
        if m:
            return proc, int(m.group(1))
        if not line and proc.poll() is not None:
            break
    proc.kill()
    raise RuntimeError("Chromium did not open its DevTools port")


def wait_dom(dt, pred, timeout):
    end = time.monotonic() + timeout
    d = dt.dom()
    while (d is None or not pred(d)) and time.monotonic() < end:
        time.sleep(0.1)
        d = dt.dom()
    if d is None:
        raise RuntimeError("the page did not load")
    return d


def main(rcsim, scenario, screenshot):
    exe = find_chromium()
    if not exe:
        print("SKIP: no Chromium on this machine (scripts/install-deps.sh installs Debian's chromium)")
        return 77
    failures = []

    def check(cond, what):
        print(("ok    " if cond else "FAIL  ") + what)
        if not cond:
            failures.append(what)

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
        # The plot draws as the circle is commanded: wait for a good part of it.
        d = wait_dom(dt, lambda d: d["points"] >= 200 and d["drawn"] >= 200, timeout=6)
        print("page drawn after %.1f s" % (time.monotonic() - t0))
        check(d["points"] >= 200, "the plot has %d points of the commanded path" % d["points"])
        check(d["drawn"] >= 200, "the canvas has %d pixels in the commanded path's blue" % d["drawn"])

        # Pause, then the DOM must show what the API says, and the position must be on the circle.
        api = run.ws()
        api.recv()
        api.request({"op": "pause"})
        snap = api.request({"op": "snapshot"})["data"]
        axes = snap["motion"]["axes"]
        d = wait_dom(dt, lambda d: d["status"] == "paused", timeout=3)
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
        shot = dt.call("Page.captureScreenshot", format="png")
        with open(screenshot, "wb") as f:
            f.write(base64.b64decode(shot["data"]))
        check(os.path.getsize(screenshot) > 10000, "screenshot saved: " + screenshot)
        api.close()
    finally:
        if browser:
            browser.kill()
            browser.communicate()
        shutil.rmtree(profile, ignore_errors=True)
        run.proc.send_signal(signal.SIGINT)
        try:
            run.finish(timeout=20)
        except subprocess.TimeoutExpired:
            run.kill()
            failures.append("rcsim did not end on SIGINT")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
