"""summary.html and compare.html as a person sees them: headless Chromium at 1280 px, each page
read back through a small script added to a copy of it (--dump-dom), not pixel by pixel
(issue #51 item 3).

  compare.html: a delta is coloured by which way the figure is better, not by its sign: a margin
                that shrinks is red (worse) though its delta is negative, one that grows green; an
                ISR time that grows red; a figure of unknown direction neutral.
  summary.html: runs in numeric order of their axes (seed=1, 2, 10, 11), text axes as text; the
                banner counts interrupted and not-run runs apart; the page fits 1280 px.

usage: pages_test.py RCSIM SOURCE_DIR WORK_DIR
Exit 77 (skipped) when Chromium is not installed."""
import copy
import html
import json
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import check, failures  # noqa: E402

WIDTH = 1280
# The colours of compare.html (summary_html.cpp kCss): td.worse, td.better, the body's text.
WORSE, BETTER, NEUTRAL = "rgb(179, 20, 29)", "rgb(10, 122, 40)", "rgb(34, 34, 34)"

# Added to a copy of a page: what it shows, as JSON in <pre id="probe">.
PROBE = """<script>
const delta = (run, key) => {
  const rows = Array.from(document.querySelectorAll("details tr")).filter(r =>
      r.closest("details").querySelector("summary").textContent.startsWith(run + ":") &&
      r.cells[0].textContent === key);
  return rows.length ? getComputedStyle(rows[0].cells[3]).color : null;
};
const runs = document.getElementById("runs") || document.querySelector("table"); // the runs table comes first
const probe = {
  scroll_width: document.documentElement.scrollWidth,
  client_width: document.documentElement.clientWidth,
  tables_right: Math.max(...Array.from(document.querySelectorAll("table")).map(t => t.getBoundingClientRect().right)),
  banner: (document.querySelector(".banner") || {}).textContent,
  ids: runs ? Array.from(runs.rows).slice(1).map(r => r.cells[0].textContent) : [],
  colours: {}
};
for (const run of ["a", "b"])
  for (const key of ["table3.margin_us", "table3.rs232_isr_us", "comm_cpu.instructions"])
    probe.colours[run + " " + key] = delta(run, key);
const pre = document.createElement("pre");
pre.id = "probe";
pre.textContent = JSON.stringify(probe);
document.body.appendChild(pre);
</script>"""


def find_chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


def probe(exe, page, work):
    """The probe's JSON for `page`, rendered at 1280 px."""
    probed = os.path.join(work, "probed-" + os.path.basename(page))
    with open(page) as f:
        text = f.read()
    with open(probed, "w") as f:
        f.write(text.replace("</body>", PROBE + "</body>"))
    profile = os.path.join(work, "chromium-profile")
    out = subprocess.run([exe, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-extensions",
                          "--user-data-dir=" + profile, "--window-size=%d,1000" % WIDTH, "--dump-dom",
                          "file://" + os.path.abspath(probed)],
                         stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, timeout=120)
    m = re.search(r'<pre id="probe">(.*?)</pre>', out.stdout, re.S)
    if not m:
        raise RuntimeError("Chromium gave no probe for %s (exit %d)" % (page, out.returncode))
    return json.loads(html.unescape(m.group(1)))


def write_run(d, report, meta=None):
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "report.json"), "w") as f:
        json.dump(report, f)
    if meta is not None:
        with open(os.path.join(d, "run.json"), "w") as f:
            json.dump(meta, f)


def compare_page(rcsim, template, work):
    """Run a: the margin shrinks 280 -> 250 us and the ISR time grows 82 -> 90 us; run b the
    reverse; comm_cpu.instructions (no direction) grows in both. No tolerances file: the default
    rules judge, the direction comes from the figure."""
    for side, margins, isrs, instructions in (("base", (280, 250), (82, 90), 100), ("cur", (250, 280), (90, 82), 120)):
        for run, margin, isr in (("a", margins[0], isrs[0]), ("b", margins[1], isrs[1])):
            r = copy.deepcopy(template)
            r["scenario"] = run
            r["table3"]["margin_us"], r["table3"]["rs232_isr_us"] = margin, isr
            r["comm_cpu"]["instructions"] = instructions
            write_run(os.path.join(work, side, run), r)
    page = os.path.join(work, "compare.html")
    rc = subprocess.run([rcsim, "compare", os.path.join(work, "base"), os.path.join(work, "cur"), "--html", page],
                        stdout=subprocess.DEVNULL).returncode
    check(rc == 1, "compare exits 1 (the default rules make every change a regression): %d" % rc)
    return page


def summary_page(rcsim, template, motion, work):
    """Seeds 11, 2, 10, 1 of entry s (numbers), modes b, a of entry t (text); s-seed=10 interrupted,
    s-seed=11 not run; t-mode=b expects a check to fail that passes (a long outcome text)."""
    runs = os.path.join(work, "runs")
    for seed in (11, 2, 10, 1):
        rid = "s-seed=%d" % seed
        meta = {"id": rid, "entry": "s", "parameters": {"seed": seed, "board.wait_states.rom": seed % 3}}
        if seed == 11:
            os.makedirs(os.path.join(runs, rid), exist_ok=True)
            with open(os.path.join(runs, rid, "run.json"), "w") as f:
                json.dump(meta, f)
            with open(os.path.join(runs, rid, "not_run.txt"), "w") as f:
                f.write("not run\n")
            continue
        r = copy.deepcopy(template)
        r["scenario"] = rid
        r["table3"]["margin_us"] = 200.0 + seed
        if seed == 10:
            r["verdict"] = "interrupted"
        write_run(os.path.join(runs, rid), r, meta)
    for mode in ("b", "a"):
        rid = "t-mode=" + mode
        r = copy.deepcopy(motion if mode == "a" else template)
        r["scenario"] = rid
        meta = {"id": rid, "entry": "t", "parameters": {"mode": mode}}
        if mode == "b":
            meta["expect_fail"] = ["overruns", "frames_failed", "commands_delivered_exactly_once"]
        write_run(os.path.join(runs, rid), r, meta)
    out = os.path.join(work, "merged")
    rc = subprocess.run([rcsim, "merge", runs, "--out", out], stdout=subprocess.DEVNULL).returncode
    check(rc == 0, "merge exits 0: %d" % rc)
    return os.path.join(out, "summary.html")


def fits(name, p):
    check(p["scroll_width"] <= WIDTH and p["tables_right"] <= p["client_width"],
          "%s fits %d px: scroll width %d, tables end at %.0f px" % (name, WIDTH, p["scroll_width"], p["tables_right"]))


def main(rcsim, source, work):
    exe = find_chromium()
    if not exe:
        print("SKIP: no Chromium on this machine (scripts/install-deps.sh installs Debian's chromium)")
        return 77
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    with open(os.path.join(source, "scenarios/regress/baseline/three_ports/report.json")) as f:
        template = json.load(f)
    with open(os.path.join(source, "scenarios/regress/baseline/xy_circle/report.json")) as f:
        motion = json.load(f)

    p = probe(exe, compare_page(rcsim, template, work), work)
    c = p["colours"]
    check(c["a table3.margin_us"] == WORSE, "run a: the margin shrinks 280 -> 250 us: red (worse), %s" % c["a table3.margin_us"])
    check(c["a table3.rs232_isr_us"] == WORSE, "run a: the ISR time grows 82 -> 90 us: red, %s" % c["a table3.rs232_isr_us"])
    check(c["b table3.margin_us"] == BETTER, "run b: the margin grows 250 -> 280 us: green, %s" % c["b table3.margin_us"])
    check(c["b table3.rs232_isr_us"] == BETTER, "run b: the ISR time shrinks 90 -> 82 us: green, %s" % c["b table3.rs232_isr_us"])
    check(c["a comm_cpu.instructions"] == NEUTRAL,
          "comm_cpu.instructions (no direction) grows: neutral, %s" % c["a comm_cpu.instructions"])
    fits("compare.html", p)

    p = probe(exe, summary_page(rcsim, template, motion, work), work)
    want = ["s-seed=1", "s-seed=2", "s-seed=10", "s-seed=11", "t-mode=a", "t-mode=b"]
    check(p["ids"] == want, "summary.html lists %s, want %s" % (p["ids"], want))
    check(p["banner"].endswith("; 3 as expected, 1 not, 2 interrupted/not run"),
          "the banner counts the stopped runs apart: %r" % p["banner"])
    fits("summary.html", p)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
