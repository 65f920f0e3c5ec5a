#!/usr/bin/env bash
# `rcsim bench soak --motion` (docs/performance.md "Motion soak", issue #48 item 3), cut short: the
# motion soak's circles for 20 and for 100 simulated seconds. Memory is flat: the longer run's peak
# resident size is within 4 MB of the shorter's (before the fix every control cycle's sample was
# kept, about 0.14 MB per simulated second: 11 MB more over the 80 s between them). trajectory.csv
# streams every 100th sample (csv_every: 100): 100 s of 1 ms cycles is samples 0 .. 100000, rows
# for 0, 100, .. 100000 of 4 axes each.
#
# Usage: bench_soak_motion.sh RCSIM SOAK_MOTION_YAML SOAK_YAML
set -u
RCSIM=$(realpath "${1:?usage: bench_soak_motion.sh RCSIM SOAK_MOTION_YAML SOAK_YAML}")
SOAK=$(realpath "${2:?usage: bench_soak_motion.sh RCSIM SOAK_MOTION_YAML SOAK_YAML}")
BOARD=$(realpath "${3:?usage: bench_soak_motion.sh RCSIM SOAK_MOTION_YAML SOAK_YAML}")
export SC_COPYRIGHT_MESSAGE=DISABLE
W=$(mktemp -d "${TMPDIR:-/tmp}/rcsim_soak_motion.XXXXXX")
trap 'rm -rf "$W"' EXIT
cd "$W" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

peak() { sed -n 's/.*resident memory: .* peak \([0-9]*\) MB.*/\1/p' "$1"; }
for s in 20 100; do
    "$RCSIM" bench soak --motion "$SOAK" --seconds $s --out out$s > soak$s.txt 2>&1
    rc=$?
    cat soak$s.txt
    [ $rc -eq 0 ] || fail "--seconds $s: exit $rc, not 0 (PASSED)"
    grep -q "^soak: soak_motion, $s s simulated" soak$s.txt || fail "no 'soak: soak_motion, $s s simulated' line"
    grep -qE "^  motion: $((s * 1000 + 1)) trajectory samples, state " soak$s.txt || fail "no motion line of $s s"
done
p20=$(peak soak20.txt) p100=$(peak soak100.txt)
[ -n "$p20" ] && [ -n "$p100" ] || fail "no peak resident memory"
[ $((p100 - p20)) -le 4 ] || fail "memory grew: peak ${p20} MB at 20 s, ${p100} MB at 100 s"
rows=$(($(wc -l < out100/trajectory.csv) - 1))
[ "$rows" -eq $((1001 * 4)) ] || fail "trajectory.csv: $rows rows, expected 4004"
tail -n 1 out100/trajectory.csv | grep -q '^100.000000,3,' || fail "trajectory.csv does not end at 100 s: $(tail -n 1 out100/trajectory.csv)"
for f in trajectory.svg trajectory_time.svg report.json; do
    [ -s out100/$f ] || fail "no out100/$f"
done
[ "$(stat -c %s out100/trajectory_time.svg)" -lt 2097152 ] || fail "trajectory_time.svg over 2 MB"

# The board soak's scenario is not a motion scenario, and the other way round.
"$RCSIM" bench soak --motion "$BOARD" --seconds 1 > bad.txt 2>&1
[ $? -eq 2 ] || fail "--motion with soak.yaml: not exit 2"
grep -q "soak.yaml: --motion needs a scenario with a 'motion:' section" bad.txt || fail "--motion with soak.yaml: $(cat bad.txt)"
"$RCSIM" bench soak "$SOAK" --seconds 1 > bad2.txt 2>&1
[ $? -eq 2 ] || fail "soak_motion.yaml without --motion: not exit 2"
grep -q "soak_motion.yaml: a 'motion:' scenario is soaked with --motion" bad2.txt || fail "without --motion: $(cat bad2.txt)"

if [ "$failures" -ne 0 ]; then
    echo "$failures failure(s)"
    exit 1
fi
echo "bench soak --motion: memory flat, trajectory.csv streamed"
