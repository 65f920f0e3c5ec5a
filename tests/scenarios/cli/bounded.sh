#!/usr/bin/env bash
# Valid scenarios at the edges of the schema's ranges run in bounded memory and time
# (docs/scenarios.md "Limits"): traffic patterns that generate far more commands than a 9600-baud
# line carries fill the host's bounded command queue instead of the heap.
#
# Usage: bounded.sh RCSIM SANITIZE(0|1). Memory is capped with `ulimit -v` (not in sanitizer
# builds, whose shadow memory reserves terabytes of address space).
set -u
RCSIM=$(realpath "${1:?usage: bounded.sh RCSIM SANITIZE}")
SANITIZE=${2:-0}
export SC_COPYRIGHT_MESSAGE=DISABLE
W=$(mktemp -d "${TMPDIR:-/tmp}/rcsim_bounded.XXXXXX")
trap 'rm -rf "$W"' EXIT
cd "$W" || exit 1
failures=0

# bounded NAME TEXT: the run must end within 60 s in 600 MB of address space, exit 0, 1 or 4 (the
# checks may fail, or measure nothing: the line is overloaded on purpose, or idle) with no error.
bounded() {
    printf "$2" > "$1.yaml"
    (
        [ "$SANITIZE" = 1 ] || ulimit -v 600000
        exec timeout 60 "$RCSIM" run "$1.yaml"
    ) > "$1.out" 2> "$1.err"
    local rc=$?
    if { [ "$rc" -gt 1 ] && [ "$rc" -ne 4 ]; } || [ -s "$1.err" ]; then
        failures=$((failures + 1))
        echo "FAIL: $1: exit $rc"
        sed 's/^/    stderr: /' "$1.err" | head -3
    fi
}

# Before the queue was bounded: 10^6 commands of 8192 bytes queued at once (8 GB).
bounded burst 'duration_s: 1\ndrain_s: 0\nports:\n  - host: protocol\n    traffic: burst\n    burst_size: 1000000\n    data_size: 8192\n'
# 10^6 commands a second, each queued (1.6 GB after 0.2 s).
bounded fixed 'duration_s: 1\ndrain_s: 0\nports:\n  - host: protocol\n    traffic: fixed\n    rate_hz: 1e6\n    data_size: 8192\n'
bounded poisson 'duration_s: 1\ndrain_s: 0\nports:\n  - host: protocol\n    traffic: poisson\n    rate_hz: 1e6\n    count: 1000000000000\n'
# A burst every picosecond.
bounded burst_ps 'duration_s: 1\ndrain_s: 0\nports:\n  - host: protocol\n    traffic: burst\n    burst_size: 1000\n    burst_period_ms: 1e-9\n'
# The shortest control cycle the schema takes, with the fastest main-CPU bus.
bounded cycle 'duration_s: 1\nmain_cpu: {cycle_period_us: 10, cycle_time_us: 5, bus_clock_hz: 1e9}\n'
[ "$failures" -eq 0 ] && echo "bounded: every edge-of-range scenario ran in bounded memory and time"
[ "$failures" -eq 0 ]
