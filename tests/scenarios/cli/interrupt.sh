#!/usr/bin/env bash
# SIGINT / SIGTERM during `rcsim run`: the run stops at the simulated time it reached, writes
# every report file with "interrupted": true, the verdict INTERRUPTED and that time, ends the tcp
# host's session log (in the run's --out folder) with its `end` line at the same time, and exits
# 128 + the signal (130, 143; docs/scenarios.md "Exit codes").
#
# Usage: interrupt.sh RCSIM
set -u
RCSIM=$(realpath "${1:?usage: interrupt.sh RCSIM}")
export SC_COPYRIGHT_MESSAGE=DISABLE
W=$(mktemp -d "${TMPDIR:-/tmp}/rcsim_interrupt.XXXXXX")
trap 'rm -rf "$W"' EXIT
cd "$W" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# An hour of simulated time, paced to wall time by the tcp host (realtime 1.0): only a signal
# ends it within the test. Port 1 saturates, so the report has figures to write.
cat > long.yaml <<'YAML'
duration_s: 3600
ports:
  - host: tcp
    record: session.log
  - host: protocol
    traffic: saturate
YAML

# run SIGNAL WANT_RC
run() {
    local sig=$1 want=$2 out="out_$1"
    "$RCSIM" run long.yaml --out "$out" > "$out.txt" 2> "$out.err" &
    local pid=$!
    sleep 1.5
    kill "-$sig" "$pid"
    # The stop comes within a simulated millisecond; give a slow (sanitizer) build 60 s.
    local waited=0
    while kill -0 "$pid" 2> /dev/null && [ "$waited" -lt 600 ]; do sleep 0.1; waited=$((waited + 1)); done
    if kill -0 "$pid" 2> /dev/null; then
        kill -KILL "$pid"
        fail "$sig: rcsim did not stop within 60 s"
    fi
    wait "$pid"
    local rc=$?
    [ "$rc" -eq "$want" ] || fail "$sig: exit $rc, expected $want"
    # An hour-long run keeps its interrupt rows compressed (docs/scenarios.md "Output files"):
    # whole, with its trailer, though a signal stopped it.
    for f in report.json interrupts.csv.gz report.html; do
        [ -s "$out/$f" ] || fail "$sig: $out/$f missing or empty"
    done
    gzip -t "$out/interrupts.csv.gz" 2>/dev/null || fail "$sig: $out/interrupts.csv.gz is not a whole gzip file"
    grep -q '"interrupted": true' "$out/report.json" || fail "$sig: report.json lacks \"interrupted\": true"
    grep -q '"verdict": "interrupted"' "$out/report.json" || fail "$sig: report.json's verdict is not interrupted"
    grep -q '^INTERRUPTED at .*: stopped by SIG'"$sig"'; what completed: ' "$out.txt" ||
        fail "$sig: the summary's verdict line is not 'INTERRUPTED at ...: stopped by SIG$sig; what completed: ...'"
    grep -q 'INTERRUPTED at' "$out.txt" || fail "$sig: the summary does not say INTERRUPTED"
    grep -q 'id="interrupted">INTERRUPTED at' "$out/report.html" || fail "$sig: report.html does not say INTERRUPTED"
    local sim
    sim=$(sed -n 's/^ *"sim_time_s": \([0-9.e+-]*\),*$/\1/p' "$out/report.json" | head -1)
    # Stopped early (not at 3600 s), after a visible stretch of simulated time.
    awk -v s="$sim" 'BEGIN { exit !(s > 0.1 && s < 60) }' || fail "$sig: sim_time_s '$sim' is not the time reached"
    # The session log ends with `<t> end`, t the time the report gives (ps against s).
    local last
    [ -s "$out/session.log" ] || fail "$sig: the session log is not in the run's folder $out"
    last=$(tail -n 1 "$out/session.log")
    case "$last" in
        *" end") awk -v t="${last% end}" -v s="$sim" 'BEGIN { d = t / 1e12 - s; exit !(d < 1e-9 && d > -1e-9) }' ||
                     fail "$sig: session log ends at ${last% end} ps, report says $sim s" ;;
        *) fail "$sig: session log's last line is '$last', not '<t> end'" ;;
    esac
    if [ -s "$out.err" ]; then fail "$sig: stderr not empty"; sed 's/^/    /' "$out.err" | head -5; fi
}

run INT 130
run TERM 143
[ "$failures" -eq 0 ] && echo "interrupt: SIGINT and SIGTERM stop the run and write its reports"
[ "$failures" -eq 0 ]
