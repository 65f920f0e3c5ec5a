#!/bin/sh
# docs/performance-history.md "Fifth round": the commands that make the 10 s no-traffic run with a
# 1000 us quantum (run here without valgrind), and the doc's claim that its report.json (but the
# quantum_us field) and interrupts.csv are those of the 100 us default.
set -eu
rcsim=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work" && cd "$src"
sed 's/duration_s: 2.0/duration_s: 10.0/' tests/speed/data/no_traffic.yaml > "$work/nt10.yaml"
cp "$work/nt10.yaml" "$work/nt10_default.yaml"
printf 'board:\n  quantum_us: 1000\n' >> "$work/nt10.yaml"
for v in nt10 nt10_default; do
    rc=0
    "$rcsim" run "$work/$v.yaml" --out "$work/$v" --reproducible > /dev/null || rc=$?
    # INCONCLUSIVE (4): with no traffic, no frame figure is measured
    [ "$rc" -eq 0 ] || [ "$rc" -eq 4 ] || { echo "FAIL: $v exited $rc"; exit 1; }
done
grep -v '"quantum_us"' "$work/nt10/report.json" > "$work/a.json"
grep -v '"quantum_us"' "$work/nt10_default/report.json" > "$work/b.json"
cmp "$work/a.json" "$work/b.json" || { echo "FAIL: report.json differs between quantum 1000 and 100 us"; exit 1; }
cmp "$work/nt10/interrupts.csv" "$work/nt10_default/interrupts.csv" || { echo "FAIL: interrupts.csv differs"; exit 1; }
grep -q '"quantum_us": 1000' "$work/nt10/report.json" || { echo "FAIL: the 1000 us quantum was not applied"; exit 1; }
echo PASS
