#!/usr/bin/env bash
# Every file a run writes goes under its output folder (docs/scenarios.md "Output files"):
# relative log:/record:/port_file: paths land under --out (folders made as needed), an absolute
# one is honoured; without --out the run writes to rcsim-out/<scenario> and says so; --out '' is
# bad input; a reused folder loses the earlier run's report files and keeps the others; two
# outputs in one file are bad input; a read-only scenario folder works.
#
# Usage: output_files.sh RCSIM
set -u
RCSIM=$(realpath "${1:?usage: output_files.sh RCSIM}")
export SC_COPYRIGHT_MESSAGE=DISABLE
W=$(mktemp -d "${TMPDIR:-/tmp}/rcsim_outputs.XXXXXX")
trap 'chmod -R u+w "$W"; rm -rf "$W"' EXIT
cd "$W" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# A scenario in a folder nobody may write into, with a log and a record named relatively.
mkdir ro
cat > ro/s.yaml <<'YAML'
name: outputs
duration_s: 0.05
ports:
  - {host: protocol, traffic: saturate, log: logs/host0.log}
  - {host: raw, record: rx.bin, send: [{at_ms: 30, bytes: "\\x05"}]}
YAML
chmod a-w ro

"$RCSIM" run ro/s.yaml --out out > run1.txt 2>&1
rc=$?
[ "$rc" -le 1 ] || [ "$rc" -eq 4 ] || fail "run 1: exit $rc"
[ -s out/logs/host0.log ] || fail "the relative log: is not at out/logs/host0.log"
[ -s out/rx.bin ] || fail "the relative record: is not at out/rx.bin"
[ -z "$(ls ro | grep -v '^s.yaml$')" ] || fail "the run wrote into the scenario's folder: $(ls ro)"

# A reused folder: the earlier run's fixed-name files go, anything else stays.
echo old > out/profile.txt
echo mine > out/notes.txt
"$RCSIM" run ro/s.yaml --out out > run2.txt 2>&1
[ -e out/profile.txt ] && fail "a reused --out kept the earlier run's profile.txt"
[ "$(cat out/notes.txt 2> /dev/null)" = mine ] || fail "a reused --out lost a file the run does not write"
[ -s out/report.json ] || fail "run 2 wrote no report.json"

# An absolute output path is honoured.
sed "s|logs/host0.log|$W/abs.log|" ro/s.yaml > abs.yaml
"$RCSIM" run abs.yaml --out out_abs > run3.txt 2>&1
[ -s "$W/abs.log" ] || fail "the absolute log: $W/abs.log was not written"

# No --out: rcsim-out/<scenario>, printed.
"$RCSIM" run ro/s.yaml > run4.txt 2>&1
grep -q '^output: rcsim-out/s (no --out given)$' run4.txt || fail "no --out: the default folder is not printed"
[ -s rcsim-out/s/report.json ] && [ -s rcsim-out/s/logs/host0.log ] || fail "no --out: nothing in rcsim-out/s"

# --out '' is bad input.
"$RCSIM" run ro/s.yaml --out '' > run5.txt 2>&1
rc=$?
[ "$rc" -eq 2 ] || fail "--out '': exit $rc, expected 2"
grep -q "^rcsim run: --out '': an empty path" run5.txt || fail "--out '': $(head -1 run5.txt)"

# Two outputs of one run in one file.
cat > same.yaml <<'YAML'
duration_s: 0.05
ports:
  - {host: protocol, traffic: saturate, log: x.log}
  - {host: protocol, traffic: saturate, log: x.log}
YAML
"$RCSIM" run same.yaml --out out_same > run6.txt 2>&1
rc=$?
[ "$rc" -eq 2 ] || fail "two outputs in one file: exit $rc, expected 2"
grep -q "same.yaml: two outputs of the run are the same file '.*out_same/x.log'" run6.txt ||
    fail "two outputs in one file: $(head -1 run6.txt)"

[ "$failures" -eq 0 ] && echo "output_files: every file the run writes is under its folder"
[ "$failures" -eq 0 ]
