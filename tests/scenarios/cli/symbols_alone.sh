#!/usr/bin/env bash
# `rcsim run --rom ROM --symbols MAP` alone (no --profile, --coverage or --gdb): the user's symbols
# name the latency causes in report.json and in the summary, and report.json "symbols" says
# whose they are (scenarios/debug/rom_symbols.h, docs/tools.md "Symbols").
#
# The ROM (symbols_rom.asm, nasm) raises port 0's interrupt inside its routine hold_if with IF = 0
# and keeps it waiting there until its STI: the cause of rs232_0's longest latency is that
# routine's CLI and STI. With the map the cause names hold_if; without it, or with the map loaded
# at another segment (FILE@SEG: E000:0000, outside the ROM), it names addresses only.
#
# Usage: symbols_alone.sh RCSIM ROM MAP SCENARIO
set -u
RCSIM=$(realpath "${1:?usage: symbols_alone.sh RCSIM ROM MAP SCENARIO}")
ROM=$(realpath "${2:?}")
MAP=$(realpath "${3:?}")
SCENARIO=$(realpath "${4:?}")
export SC_COPYRIGHT_MESSAGE=DISABLE
W=$(mktemp -d "${TMPDIR:-/tmp}/rcsim_symbols_alone.XXXXXX")
trap 'rm -rf "$W"' EXIT
cd "$W" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

run() { # NAME ARGS...: a reproducible run into NAME/; no host sends traffic: INCONCLUSIVE, exit 4
    local name=$1
    shift
    "$RCSIM" run "$SCENARIO" --rom "$ROM" --out "$name" --reproducible "$@" > "$name.txt" 2> "$name.err"
    local rc=$?
    [ "$rc" -eq 4 ] || { fail "$name: exit $rc, expected 4 (INCONCLUSIVE: no traffic)"; sed 's/^/    /' "$name.err" | head -5; }
}
# check NAME PYTHON-EXPR...: each expression holds over r = NAME/report.json and out = the summary
check() {
    local name=$1
    shift
    /usr/bin/python3 - "$name/report.json" "$name.txt" "$@" <<'PY' || fail "$name: see above"
import json, sys
r = json.load(open(sys.argv[1]))
out = open(sys.argv[2]).read()
worst = r["interrupts"]["rs232_0"]["worst"]
text = worst[0]["text"] if worst else ""
bad = [e for e in sys.argv[3:] if not eval(e)]
for e in bad:
    print("  does not hold:", e)
if bad:
    print("  symbols:", r.get("symbols"), "\n  cause:", text)
sys.exit(1 if bad else 0)
PY
}

run with --symbols "$MAP"
# The cause names the routine that held IF = 0: its CLI is hold_if's first byte, its STI inside.
check with "'hold_if' in text" "'hold_if+0x' in text" \
    "r['symbols'] == {'origin': '--symbols', 'file': 'symbols_rom.map', 'count': 4}" \
    "'hold_if' in out"

run without
check without "worst and 'hold_if' not in text and 'F000:00' in text" \
    "r['symbols'] == {'origin': 'none', 'file': '', 'count': 0}" "'hold_if' not in out"

run elsewhere --symbols "$MAP@E000"
check elsewhere "worst and 'hold_if' not in text" \
    "r['symbols'] == {'origin': '--symbols', 'file': 'symbols_rom.map@E000', 'count': 4}"

# Only the symbols differ: every figure of the three runs is the same.
/usr/bin/python3 - with/report.json without/report.json elsewhere/report.json <<'PY' || fail "the figures differ"
import json, sys
def figures(path):
    r = json.load(open(path))
    r.pop("symbols")
    # The causes' words and details name symbols; their latencies are figures.
    latencies = {k: [w["latency_us"] for w in v.get("worst", [])] + [v.get("latency_us")]
                 for k, v in r.pop("interrupts").items() if isinstance(v, dict)}
    # So do the checks' explanations (interrupt_blocking_max_us: the routines that ran).
    for c in r["checks"]:
        c.pop("why", None)
        for v in (c.get("detail") or {}).values() if isinstance(c.get("detail"), dict) else []:
            if isinstance(v, dict):
                v.pop("path", None)
    return r, latencies
a, b, c = (figures(p) for p in sys.argv[1:])
assert a == b == c, [k for k in a[0] if a[0][k] != b[0].get(k) or a[0][k] != c[0].get(k)]
PY

echo "symbols alone: $failures failed"
[ "$failures" -eq 0 ]
