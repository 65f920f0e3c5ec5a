#!/usr/bin/env bash
# `rcsim bench soak` (docs/performance.md "Fault soak"), cut to 40 simulated seconds: it runs the
# soak scenario with the faults it adds (a BREAK from the host on every port by 30 s, characters
# dropped and damaged on both sides), prints the frame books of every port and direction and the
# resident memory, writes report.json under --out, and exits with the run's verdict (0, 1 or 4).
#
# Usage: bench_soak.sh RCSIM SOAK_YAML
set -u
RCSIM=$(realpath "${1:?usage: bench_soak.sh RCSIM SOAK_YAML}")
SOAK=$(realpath "${2:?usage: bench_soak.sh RCSIM SOAK_YAML}")
export SC_COPYRIGHT_MESSAGE=DISABLE
W=$(mktemp -d "${TMPDIR:-/tmp}/rcsim_soak.XXXXXX")
trap 'rm -rf "$W"' EXIT
cd "$W" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

"$RCSIM" bench soak "$SOAK" --seconds 40 --out out > soak.txt 2>&1
rc=$?
cat soak.txt
case $rc in 0 | 1 | 4) ;; *) fail "exit $rc, not a verdict" ;; esac
grep -q '^soak: soak, 4[0-9.]* s simulated' soak.txt || fail "no 'soak: soak, 40 s simulated' line"
rows=$(grep -cE '^ +[0-2]  (commands|responses) ' soak.txt)
[ "$rows" -eq 6 ] || fail "$rows book rows, expected 6 (3 ports x 2 directions)"
grep -q 'frames not delivered exactly once, expected drops aside: [0-9]' soak.txt || fail "no total of mismatches"
grep -qE 'resident memory: [0-9]+ MB after a tenth of the run, [0-9]+ MB at its end, peak [0-9]+ MB' soak.txt ||
    fail "no resident memory line"
[ -s out/report.json ] || fail "no out/report.json"
[ -e out/interrupts.csv ] || [ -e out/interrupts.csv.gz ] && fail "the soak wrote interrupt rows"
# The faults it added: a BREAK from the host on every port (at 30 s), characters damaged on both sides.
/usr/bin/python3 - out/report.json <<'PY' || fail "the report does not show the soak's faults"
import json, sys
r = json.load(open(sys.argv[1]))
for p in r["ports"]:
    assert p["line"]["breaks"] >= 1, p["line"]
    assert p["parity_errors"] + p["framing_errors"] > 0, p
PY
# Nothing lost and nothing misattributed (issue 33): every frame not delivered exactly once has a
# cause the soak made. Drops the faults explain are expected; a duplicate or unexpected frame is
# counted, and its transfer was hit by a fault (after_fault); nothing is lost without a cause or
# reordered.
/usr/bin/python3 - out/report.json <<'PY' || fail "a frame not delivered exactly once has no cause"
import json, sys
r = json.load(open(sys.argv[1]))
for n, p in enumerate(r["ports"]):
    for k in ("commands", "responses"):
        b = p[k]
        assert b["mismatches"] == b["after_fault"], (n, k, b)
        assert b["reordered"] == 0, (n, k, b)
PY
"$RCSIM" bench soak "$SOAK" --seconds 0 > bad.txt 2>&1
[ $? -eq 2 ] || fail "--seconds 0: not exit 2"
grep -q -- "--seconds: '0' is not in 1 .. 36000" bad.txt || fail "--seconds 0: $(cat bad.txt)"

if [ "$failures" -ne 0 ]; then
    echo "$failures failure(s)"
    exit 1
fi
echo "bench soak: books, memory and report as documented"
