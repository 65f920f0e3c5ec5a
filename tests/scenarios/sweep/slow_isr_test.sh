#!/usr/bin/env bash
# The firmware team's loop in miniature (docs/regression.md): a ROM (the shipped or the frozen C firmware) and the same ROM with
# a delay loop of LOOPS iterations in the RS-232 interrupt entry (slow_isr_rom), one short
# two-port run each; `rcsim compare` must exit 1 and name table3.rs232_isr_us as a regression,
# slower by at least what the loop costs. A second entry searches the longest rs232_0 service
# (docs/regression.md "Searched worst cases"): compare judges its witness's figure like any other,
# a regression by at least the loop too.
#
# Usage: slow_isr_test.sh RCSIM SLOW_ISR_ROM ROM SYMBOLS_JSON SOURCE_DIR
set -u
RCSIM=$(realpath "${1:?usage}")
TOOL=$(realpath "${2:?usage}")
ROM=$(realpath "${3:?usage}")
SYMS=$(realpath "${4:?usage}")
SRC=$(realpath "${5:?usage}")
W=$(mktemp -d "${TMPDIR:-/tmp}/rcsim_slow_isr.XXXXXX")
trap 'rm -rf "$W"' EXIT
cd "$W" || exit 1
LOOPS=20

"$TOOL" "$ROM" "$SYMS" slow.rom $LOOPS || { echo "FAIL: slow_isr_rom"; exit 1; }
cmp -s "$ROM" slow.rom && { echo "FAIL: the slowed ROM is the built one"; exit 1; }
cat > mini.yaml <<YAML
name: mini
set: {duration_s: 0.3, drain_s: 0.5}
sweeps:
  - {name: mini, base: $SRC/scenarios/regress/grid_base.yaml}
  - name: worst
    base: $SRC/scenarios/regress/grid_base.yaml
    search: {maximize: interrupts.rs232_0.service_us.max, runs: 6}
YAML
"$RCSIM" sweep mini.yaml --out built --jobs 2 --rom "$ROM" > /dev/null 2>&1
"$RCSIM" sweep mini.yaml --out slow --jobs 2 --rom slow.rom > /dev/null 2>&1
for r in built/mini slow/mini built/worst slow/worst; do
    [ -f $r/report.json ] || { echo "FAIL: $r has no report"; exit 1; }
done

"$RCSIM" compare built slow --tolerances "$SRC/scenarios/regress/tolerances.yaml" > out.txt 2> err.txt
rc=$?
cat out.txt
failures=0
if [ "$rc" -ne 1 ]; then echo "FAIL: compare exit $rc, expected 1"; failures=$((failures + 1)); fi
# The regression row: figure, runs, worst run, baseline, current, delta, rel.
row=$(sed -n '/^regressions/,/^$/p' out.txt | awk '$1 == "table3.rs232_isr_us"')
if [ -z "$row" ]; then
    echo "FAIL: table3.rs232_isr_us is not among the regressions"
    failures=$((failures + 1))
else
    delta=$(echo "$row" | awk '{print $6}')
    # The loop's own cost, from the 8086 instruction timings: MOV CX,imm16 4 clocks, LOOP 17 clocks
    # taken (LOOPS-1 times) and 5 not taken; at the board's 8 MHz. Fetch wait states and the two
    # JMPs only add to it.
    bound=$(awk -v n=$LOOPS 'BEGIN { printf "%.3f", (4 + 17 * (n - 1) + 5) / 8.0 }')
    if ! awk -v d="$delta" -v b="$bound" 'BEGIN { exit !(d + 0 >= b + 0) }'; then
        echo "FAIL: table3.rs232_isr_us grew by $delta us, the loop alone costs $bound us"
        failures=$((failures + 1))
    fi
fi
# The searched worst case: the witness of each search stands for its run.
"$RCSIM" compare built/worst/report.json slow/worst/report.json --tolerances "$SRC/scenarios/regress/tolerances.yaml" > worst.txt
rc=$?
if [ "$rc" -ne 1 ]; then echo "FAIL: compare of the search entry's witnesses: exit $rc, expected 1"; failures=$((failures + 1)); fi
row=$(sed -n '/^regressions/,/^$/p' worst.txt | awk '$1 == "interrupts.rs232_0.service_us.max"')
if [ -z "$row" ]; then
    echo "FAIL: the searched interrupts.rs232_0.service_us.max of run worst is not among the regressions"
    failures=$((failures + 1))
elif ! awk -v d="$(echo "$row" | awk '{print $6}')" -v b="$bound" 'BEGIN { exit !(d + 0 >= b + 0) }'; then
    echo "FAIL: the searched longest service grew by less than the loop's $bound us: $row"
    failures=$((failures + 1))
fi
grep -q '"witness"' built/worst/run.json || { echo "FAIL: the search entry's run.json names no witness"; failures=$((failures + 1)); }
# The same ROM twice: no regression (the comparison is not just noise).
"$RCSIM" compare built built --tolerances "$SRC/scenarios/regress/tolerances.yaml" > same.txt
rc=$?
if [ "$rc" -ne 0 ]; then echo "FAIL: the built ROM against itself: exit $rc"; failures=$((failures + 1)); fi
# A ROM that is not a firmware slow_isr_rom knows (all 0xFF: room for trampolines, no entry) is refused.
head -c 65536 /dev/zero | tr '\0' '\377' > blank.rom
"$TOOL" blank.rom "$SYMS" x.rom $LOOPS 2> tool_err.txt
rc=$?
if [ "$rc" -ne 2 ] || ! grep -q "are not push ax; in al,GIR" tool_err.txt; then
    echo "FAIL: slow_isr_rom patched a ROM without the expected entry (exit $rc)"
    failures=$((failures + 1))
fi
[ "$failures" -eq 0 ] && echo "slow_isr: ok" || echo "slow_isr: $failures failures"
[ "$failures" -eq 0 ]
