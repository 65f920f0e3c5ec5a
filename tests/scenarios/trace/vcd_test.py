#!/usr/bin/env python3
"""Tests of `rcsim run --vcd` (scenarios/trace/vcd_trace.h, docs/tools.md "VCD waveforms").

Usage: vcd_test.py CASE RCSIM SCENARIO WORKDIR, CASE one of
  toggles    the trace declares every signal of docs/tools.md, each toggles at least once, the
             first character on port 0's RXD and TXD decodes (9600,8E1 sampling at bit centres)
             as ENQ and ACK, and GTKWave's own reader (vcd2fst, Debian gtkwave) loads the file
  silent     the same check on a run whose port 2 has no host: it must fail, naming port2_txd
             and port2_rxd (the check can fail)
  identical  report.json and interrupts.csv are byte-identical with and without --vcd
"""
import filecmp
import os
import shutil
import subprocess
import sys

EXPECTED = ["ir0", "ir1", "ir2", "ir3_int_l", "int_r", "intr", "inta",
            "port0_txd", "port0_rxd", "port1_txd", "port1_rxd", "port2_txd", "port2_rxd",
            "dpram_busy_l", "dpram_busy_r"]
UNITS = {"s": 10**12, "ms": 10**9, "us": 10**6, "ns": 10**3, "ps": 1, "fs": 1e-3}


class VcdError(Exception):
    pass


def read_vcd(path):
    """IEEE 1364 §18 VCD: returns (names by id, {id: [(time_ps, value)]}). Strict: every
    section closed, changes only for declared ids, times increasing."""
    with open(path) as f:
        tokens = f.read().split()
    i, names, unit_ps = 0, {}, None
    while True:
        if i >= len(tokens):
            raise VcdError("no $enddefinitions")
        t = tokens[i]
        if t == "$enddefinitions":
            if tokens[i + 1] != "$end":
                raise VcdError("$enddefinitions without $end")
            i += 2
            break
        if not t.startswith("$"):
            raise VcdError("stray header token %r" % t)
        end = tokens.index("$end", i)
        body = tokens[i + 1:end]
        if t == "$var":
            if len(body) < 4:
                raise VcdError("short $var: %r" % body)
            names[body[2]] = body[3]
        elif t == "$timescale":
            text = "".join(body)
            digits = text.rstrip("abcdefghijklmnopqrstuvwxyz")
            unit_ps = int(digits) * UNITS[text[len(digits):]]
        i = end + 1
    if unit_ps is None:
        raise VcdError("no $timescale")
    changes = {k: [] for k in names}
    now = -1
    while i < len(tokens):
        t = tokens[i]
        i += 1
        if t.startswith("#"):
            time = int(t[1:])
            if time <= now:
                raise VcdError("time %d after %d" % (time, now))
            now = time
        elif t == "$comment":
            i = tokens.index("$end", i) + 1
        elif t in ("$dumpvars", "$end", "$dumpall", "$dumpon", "$dumpoff"):
            continue
        elif t[0] in "01xXzZ":
            if t[1:] not in changes:
                raise VcdError("change for undeclared id %r" % t[1:])
            changes[t[1:]].append((now * unit_ps, t[0]))
        elif t[0] in "bBrR":
            ident = tokens[i]
            i += 1
            if ident not in changes:
                raise VcdError("change for undeclared id %r" % ident)
            changes[ident].append((now * unit_ps, t[1:]))
        else:
            raise VcdError("bad token %r" % t)
    return names, changes


def toggles(changes):
    """Value changes after the initial value (a re-write of the same value is no toggle)."""
    n, last = 0, None
    for _, v in changes:
        if last is not None and v != last:
            n += 1
        last = v
    return n


def first_char(changes, bps=9600, data_bits=8):
    """The first character on a serial wire: START at the first falling edge, each cell sampled
    at its centre (docs/serial.md "What the receiver sees"). Returns (data, parity, stop)."""
    edges = [(t, v) for t, v in changes]
    start = next(t for k, (t, v) in enumerate(edges) if v == "0" and k > 0)

    def level(t):
        value = "1"
        for et, v in edges:
            if et > t:
                break
            value = v
        return int(value)

    bit_ps = 10**12 / bps
    cells = [level(start + (k + 0.5) * bit_ps) for k in range(1 + data_bits + 2)]
    data = sum(b << k for k, b in enumerate(cells[1:1 + data_bits]))
    return data, cells[1 + data_bits], cells[2 + data_bits]


def run(rcsim, scenario, out, vcd=None):
    cmd = [rcsim, "run", scenario, "--out", out, "--reproducible"] + (["--vcd", vcd] if vcd else [])
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
    if p.returncode not in (0, 1, 4):
        print(p.stdout)
        sys.exit("FAIL: rcsim exit code %d" % p.returncode)


def check(vcd):
    """Returns the problems found, [] when every expected signal is declared and toggles."""
    names, changes = read_vcd(vcd)
    by_name = {names[k]: changes[k] for k in names}
    problems = ["%s is not declared" % n for n in EXPECTED if n not in by_name]
    for name in sorted(by_name):
        n = toggles(by_name[name])
        print("%-14s %8d toggles" % (name, n))
        if n == 0:
            problems.append("%s never toggles" % name)
    return problems, by_name


def case_toggles(rcsim, scenario, work):
    vcd = os.path.join(work, "trace.vcd")
    run(rcsim, scenario, os.path.join(work, "out"), vcd)
    problems, by_name = check(vcd)
    # The host opens every transfer with ENQ (0x05) and the firmware answers ACK (0x06), both
    # 9600,8E1: even parity of two 1 bits is 0, STOP is 1 (docs/system.md §5.1, §5.2).
    for sig, want in (("port0_rxd", 0x05), ("port0_txd", 0x06)):
        got = first_char(by_name[sig])
        if got != (want, 0, 1):
            problems.append("%s: first character (data, parity, stop) = %r, expected (0x%02X, 0, 1)" % (sig, got, want))
    vcd2fst = shutil.which("vcd2fst")
    if vcd2fst:
        fst = os.path.join(work, "trace.fst")
        p = subprocess.run([vcd2fst, vcd, fst], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if p.returncode != 0 or not os.path.getsize(fst):
            problems.append("GTKWave's vcd2fst could not load the trace: " + p.stdout)
    else:
        print("note: vcd2fst (Debian gtkwave) not installed: the GTKWave load is not checked")
    if problems:
        sys.exit("FAIL: " + "; ".join(problems))


def case_silent(rcsim, scenario, work):
    vcd = os.path.join(work, "trace.vcd")
    run(rcsim, scenario, os.path.join(work, "out"), vcd)
    problems, _ = check(vcd)
    want = {"port2_txd never toggles", "port2_rxd never toggles"}
    if not want <= set(problems):
        sys.exit("FAIL: the check did not flag port 2's silent wires: %r" % problems)


def case_identical(rcsim, scenario, work):
    plain, traced = os.path.join(work, "plain"), os.path.join(work, "traced")
    run(rcsim, scenario, plain)
    run(rcsim, scenario, traced, os.path.join(work, "trace.vcd"))
    for f in ("report.json", "interrupts.csv"):
        if not filecmp.cmp(os.path.join(plain, f), os.path.join(traced, f), shallow=False):
            sys.exit("FAIL: %s differs with --vcd" % f)


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    case, rcsim, scenario, work = sys.argv[1:]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    try:
        {"toggles": case_toggles, "silent": case_silent, "identical": case_identical}[case](rcsim, scenario, work)
    except VcdError as e:
        sys.exit("FAIL: not a valid VCD file: %s" % e)
    print("PASS")


if __name__ == "__main__":
    main()
