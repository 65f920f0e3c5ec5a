"""`rcsim modbus-map` (docs/monitor.md "Modbus TCP"): the CSV is the map docs/monitor.md documents,
row for row; the map is consistent (no two entries share a register, a 32-bit value takes two);
bad --modbus values are refused with exit 2 naming the value.

usage: cli_test.py RCSIM DOCS_MONITOR_MD BOARD_SCENARIO MOTION_SCENARIO"""
import csv
import io
import os
import signal
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from rcsim_test import Rcsim, check, failures  # noqa: E402


def doc_table(md):
    """The rows of the markdown table that follows the '<!-- modbus-map -->' marker."""
    lines = open(md, encoding="utf-8").read().splitlines()
    start = lines.index("<!-- modbus-map -->") + 1
    rows = []
    for line in lines[start:]:
        if not line.startswith("|"):
            if rows:
                break
            continue
        rows.append([c.strip().replace("\\|", "|").strip("`") for c in line.strip().strip("|").split(" | ")])
    return [rows[0]] + rows[2:]  # the header, then the rows after the |---| line


def main(rcsim, md, board, motion_scenario):
    p = subprocess.run([rcsim, "modbus-map"], capture_output=True, text=True)
    check(p.returncode == 0, "rcsim modbus-map exits 0")
    rows = list(csv.reader(io.StringIO(p.stdout)))
    check(rows[0] == ["name", "table", "address", "type", "words", "scale", "unit", "access", "description"],
          "the CSV's columns: %s" % rows[0])
    doc = doc_table(md)
    check(doc == rows, "docs/monitor.md's map table equals `rcsim modbus-map` (%d vs %d rows)" % (len(doc), len(rows)))
    if doc != rows:
        for a, b in zip(doc, rows):
            if a != b:
                print("  doc: %s\n  csv: %s" % (a, b))
                break
    # The doc's example of the command: its first lines are the CSV's.
    text = open(md, encoding="utf-8").read()
    section = text[text.index("## Modbus TCP"):]
    example = section[section.index("$ build/rcsim modbus-map | head -2\n"):].split("\n")[1:3]
    check(example == p.stdout.splitlines()[:2], "docs/monitor.md's `rcsim modbus-map | head -2` is the CSV's start")
    used = {}
    for r in rows[1:]:
        name, table, addr, typ, words = r[0], r[1], int(r[2]), r[3], int(r[4])
        check(words == (2 if typ in ("u32", "i32") else 1), "%s: a %s takes %d register(s)" % (name, typ, words))
        for a in range(addr, addr + words):
            check((table, a) not in used, "%s %d: one entry only (%s)" % (table, a, used.get((table, a))))
            used[(table, a)] = name
    for table, name in (("input_register", "sim_time"), ("coil", "pause"), ("holding_register", "mailbox.go"),
                        ("discrete_input", "port0.in_frame"), ("input_register", "axis3.error_id")):
        check(any(r[0] == name and r[1] == table for r in rows[1:]), "the map has %s (%s)" % (name, table))

    with tempfile.TemporaryDirectory() as out:
        for bad in ("abc", "1.2.3.4:99999", "localhost:1502", "70000"):
            p = subprocess.run([rcsim, "run", board, "--modbus", bad, "--out", out],
                               capture_output=True, text=True, timeout=30)
            check(p.returncode == 2 and "--modbus '%s'" % bad in p.stderr, "--modbus %s: exit 2 naming it (%d: %s)" %
                  (bad, p.returncode, p.stderr.strip()[:160]))
        p = subprocess.run([rcsim, "run", motion_scenario, "--modbus", "0", "--out", out],
                           capture_output=True, text=True, timeout=30)
        check(p.returncode == 2 and "--modbus" in p.stderr and "motion:" in p.stderr,
              "--modbus on a motion-side-only scenario: exit 2 (%d: %s)" % (p.returncode, p.stderr.strip()[:160]))
        # "HOST:" (and --modbus alone) take port 1502; another process may hold it: then the
        # refusal names it.
        run = Rcsim(rcsim, ["run", board, "--modbus", "127.0.0.1:", "--out", out], {"modbus": r"modbus:"},
                    required=False)
        line = run.found["modbus"].string if "modbus" in run.found else ""
        run.proc.send_signal(signal.SIGTERM)
        _, _, err = run.finish(timeout=30)
        check(line.startswith("modbus: 127.0.0.1:1502 ") or "--modbus '127.0.0.1:1502': cannot listen" in err,
              "--modbus 127.0.0.1: listens on the default port 1502 (%s%s)" % (line.strip(), err.strip()[:100]))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:5]))
