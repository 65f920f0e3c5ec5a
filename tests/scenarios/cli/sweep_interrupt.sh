#!/usr/bin/env bash
# SIGINT / SIGTERM during `rcsim sweep` (docs/regression.md "Interrupted sweeps"): no new run
# starts, the running ones stop as an interrupted `rcsim run` does (report.json with the verdict
# interrupted), the summary files list the completed runs and mark the rest "not run", no run
# directory is left with outputs but no report.json, and the sweep exits 128 + the signal.
#
# Two cases: Ctrl-C on a terminal (SIGINT to the whole process group, --jobs 2) and SIGTERM to
# the sweep process alone (--jobs 1: the sweep must pass the signal on to its run).
#
# Usage: sweep_interrupt.sh RCSIM
set -u
RCSIM=$(realpath "${1:?usage: sweep_interrupt.sh RCSIM}")
export SC_COPYRIGHT_MESSAGE=DISABLE
unset CI SLURM_ARRAY_TASK_ID SLURM_ARRAY_TASK_COUNT SLURM_ARRAY_TASK_MIN JOB_COMPLETION_INDEX
W=$(mktemp -d "${TMPDIR:-/tmp}/rcsim_sweep_interrupt.XXXXXX")
trap 'rm -rf "$W"' EXIT
cd "$W" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# The first run is done in a blink; the other three would take hours: only the signal ends them.
cat > base.yaml <<'YAML'
duration_s: 0.05
drain_s: 0.05
ports:
  - {host: protocol, traffic: saturate, start_ms: 5, data_size: 16, tokens: {EC: 1}}
YAML
cat > s.yaml <<'YAML'
name: t
base: base.yaml
axes:
  duration_s: [0.05, 3600, 3599, 3598]
YAML
FIRST=t-duration_s=0.05

# sweep CASE JOBS SIGNAL WANT_RC TARGET (group: the process group, as Ctrl-C; process: the sweep alone)
sweep() {
    local out=$1 jobs=$2 sig=$3 want=$4 target=$5
    set -m # the sweep in a process group of its own, so that the group can be signalled
    "$RCSIM" sweep s.yaml --out "$out" --jobs "$jobs" > "$out.out" 2> "$out.err" &
    local pid=$!
    set +m
    local waited=0
    while [ ! -f "$out/$FIRST/report.json" ] && [ "$waited" -lt 300 ]; do sleep 0.1; waited=$((waited + 1)); done
    [ -f "$out/$FIRST/report.json" ] || fail "$out: the first run did not complete within 30 s"
    sleep 0.5 # the long runs under way
    if [ "$target" = group ]; then kill "-$sig" -- "-$pid"; else kill "-$sig" "$pid"; fi
    waited=0
    while kill -0 "$pid" 2> /dev/null && [ "$waited" -lt 600 ]; do sleep 0.1; waited=$((waited + 1)); done
    if kill -0 "$pid" 2> /dev/null; then
        kill -KILL -- "-$pid"
        fail "$out: the sweep did not stop within 60 s"
    fi
    wait "$pid"
    local rc=$?
    [ "$rc" -eq "$want" ] || fail "$out: exit $rc, expected $want: $(cat "$out.err")"
    grep -q "sweep: stopped by SIG$sig: 1 of 4 runs completed, [12] interrupted, [12] not run" "$out.err" ||
        fail "$out: no 'stopped by $sig' line: $(cat "$out.err")"
    for f in summary.json summary.csv summary.html; do [ -s "$out/$f" ] || fail "$out: no $f"; done

    # Every run directory: a report.json, or the not-run marker and nothing but the sweep's inputs.
    local d
    for d in "$out"/t-*; do
        if [ -f "$d/report.json" ]; then continue; fi
        [ -f "$d/not_run.txt" ] || fail "$d: neither report.json nor not_run.txt: $(ls "$d" | tr "\n" " ")"
        [ "$(ls "$d" | tr '\n' ' ')" = "not_run.txt run.json scenario.yaml " ] ||
            fail "$d: a run that did not complete left outputs: $(ls "$d" | tr "\n" " ")"
    done

    /usr/bin/python3 - "$out" <<'PY' || fail "$out: summary.json"
import json, sys
s = json.load(open(sys.argv[1] + "/summary.json"))
status = {r["id"]: r["status"] for r in s["results"]}
errors = []
if s["runs"] != 4: errors.append("runs %s, expected 4" % s["runs"])
if status.get("t-duration_s=0.05") != "passed": errors.append("the completed run is %r" % status.get("t-duration_s=0.05"))
# The last run never had its turn; the one that ran at the signal stopped with its report
# (or, caught in its start-up, went back to not run).
if status.get("t-duration_s=3598") != "not run": errors.append("the last run is %r" % status.get("t-duration_s=3598"))
if status.get("t-duration_s=3600") not in ("interrupted", "not run"): errors.append("the second run is %r" % status.get("t-duration_s=3600"))
if "interrupted" not in status.values(): errors.append("no run says interrupted: %s" % status)
if s.get("not run", 0) != list(status.values()).count("not run"): errors.append("the 'not run' count %s" % s.get("not run"))
for e in errors: print(e)
sys.exit(1 if errors else 0)
PY
    grep -q '^t-duration_s=3598,t,not run' "$out/summary.csv" || fail "$out: summary.csv has no 'not run' row"
    grep -q 'not run (the sweep was interrupted)' "$out/summary.html" || fail "$out: summary.html does not say not run"
}

sweep ctrl_c 2 INT 130 group
sweep term 1 TERM 143 process

[ "$failures" -eq 0 ] && echo "sweep_interrupt: ok"
[ "$failures" -eq 0 ]
