#!/usr/bin/env bash
# interrupts.csv in proportion to the run (docs/scenarios.md "Output files"): --interrupts-csv plain,
# gz (interrupts.csv.gz, which gzip itself unpacks to the plain file's very bytes) and none; auto
# writes plain for a run of up to 60 simulated seconds and gz beyond; report.json and report.html
# are the same whichever is chosen; a reused folder keeps no earlier run's rows; a bad mode is bad
# input.
#
# Usage: interrupt_rows.sh RCSIM
set -u
RCSIM=$(realpath "${1:?usage: interrupt_rows.sh RCSIM}")
export SC_COPYRIGHT_MESSAGE=DISABLE
W=$(mktemp -d "${TMPDIR:-/tmp}/rcsim_rows.XXXXXX")
trap 'rm -rf "$W"' EXIT
cd "$W" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

cat > short.yaml <<'YAML'
name: rows
duration_s: 0.3
ports:
  - {host: protocol, traffic: saturate}
  - {host: protocol, traffic: saturate}
YAML
# Over a minute of a quiet board: the idle fast-forward makes it quick.
cat > long.yaml <<'YAML'
name: rows_long
duration_s: 61
YAML

for mode in plain gz none; do
    "$RCSIM" run short.yaml --out "$mode" --reproducible --interrupts-csv "$mode" > "$mode.txt" 2>&1
    rc=$?
    [ $rc -le 1 ] || fail "--interrupts-csv $mode: exit $rc, not a verdict: $(tail -3 "$mode.txt")"
done
[ -s plain/interrupts.csv ] || fail "plain: no interrupts.csv"
[ -e plain/interrupts.csv.gz ] && fail "plain: an interrupts.csv.gz too"
[ -s gz/interrupts.csv.gz ] || fail "gz: no interrupts.csv.gz"
[ -e gz/interrupts.csv ] && fail "gz: an interrupts.csv too"
if ! gzip -dc gz/interrupts.csv.gz | cmp -s - plain/interrupts.csv; then fail "gzip -dc of interrupts.csv.gz differs from interrupts.csv"; fi
rows=$(wc -l < plain/interrupts.csv)
[ "$rows" -gt 100 ] || fail "only $rows rows in interrupts.csv"
[ -e none/interrupts.csv ] || [ -e none/interrupts.csv.gz ] && fail "none: a row file was written"
for mode in gz none; do
    cmp -s plain/report.json "$mode/report.json" || fail "$mode: report.json differs from plain's"
done
# The failures section reads the rows back: the same page from either file.
cmp -s plain/report.html gz/report.html || fail "gz: report.html differs from plain's"

"$RCSIM" run short.yaml --out auto_short --reproducible > auto_short.txt 2>&1
[ -s auto_short/interrupts.csv ] && [ ! -e auto_short/interrupts.csv.gz ] || fail "auto, 0.3 s: not plain"
"$RCSIM" run long.yaml --out auto_long --reproducible > auto_long.txt 2>&1
rc=$?
[ $rc -le 4 ] || fail "auto, 61 s: exit $rc: $(tail -3 auto_long.txt)"
[ -e auto_long/interrupts.csv.gz ] && [ ! -e auto_long/interrupts.csv ] || fail "auto, 61 s: not gz"
gzip -t auto_long/interrupts.csv.gz 2>/dev/null || fail "auto, 61 s: interrupts.csv.gz is not a whole gzip file"

# The same folder again, compressed: the earlier run's plain rows are gone.
"$RCSIM" run short.yaml --out plain --reproducible --interrupts-csv gz > again.txt 2>&1
[ -e plain/interrupts.csv ] && fail "a reused folder kept the earlier run's interrupts.csv"
[ -s plain/interrupts.csv.gz ] || fail "reused folder: no interrupts.csv.gz"

"$RCSIM" run short.yaml --out bad --interrupts-csv zip > bad.txt 2>&1
rc=$?
[ $rc -eq 2 ] || fail "--interrupts-csv zip: exit $rc, expected 2"
grep -q -- "--interrupts-csv" bad.txt || fail "--interrupts-csv zip: the message does not name the option: $(cat bad.txt)"

if [ "$failures" -ne 0 ]; then
    echo "$failures failure(s)"
    exit 1
fi
echo "interrupt rows: plain, gz, none and auto as documented"
