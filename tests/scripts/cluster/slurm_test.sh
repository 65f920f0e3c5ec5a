#!/usr/bin/env bash
# CTest cluster.slurm: the Slurm job array recipe of docs/regression.md "On a cluster", run as the
# page gives it on a real one-node Slurm (scripts/cluster/one-node-slurm.sh) in a scratch folder.
#   1. the submit block, extracted from the page, for the shipped suite; one array task cancelled
#      while it runs: the merge names its interrupted / not run runs; `--missing --shards` prints
#      exactly its index; the resubmit block, from the page; the merged summary.json, .csv and
#      .html byte-identical with a local `rcsim sweep` of the suite;
#   2. bad input in one task: its array element fails with exit 2, the other completes, the merge
#      names the run.
# Every daemon it started is stopped by its pid on the way out, passed or failed (trap).
#
#   slurm_test.sh RCSIM SOURCE_DIR SCRATCH
set -u
RCSIM=$1
SRC=$2
W=$3

skip() { echo "cluster.slurm: skipped: $*"; exit 77; }
[ "$(id -u)" -eq 0 ] || skip "needs root (munged and slurmd run as root)"
for t in munged slurmctld slurmd sbatch scancel scontrol squeue; do
    command -v "$t" >/dev/null 2>&1 || skip "$t is not installed (scripts/install-deps.sh installs Slurm and munge)"
done
# The recipe, not the memory, is under test here; the suite under ASan would take many minutes.
[ -z "${RCSIM_SANITIZED:-}" ] || skip "in the sanitizer build (the Release build runs it)"

failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
die() { echo "FAIL: $*"; exit 1; }

rm -rf "$W"
mkdir -p "$W/clone/build" || die "cannot create $W"
# A folder laid out like the top of a clone, as the page's commands expect (they run from there).
ln -s "$RCSIM" "$W/clone/build/rcsim"
ln -s "$SRC/scenarios" "$W/clone/scenarios"
ln -s "$SRC/scripts" "$W/clone/scripts"
CLONE=$W/clone

trap 'bash "$SRC/scripts/cluster/one-node-slurm.sh" stop "$W/slurm"' EXIT
trap 'exit 143' TERM INT # ctest's timeout: the EXIT trap still stops the daemons
bash "$SRC/scripts/cluster/one-node-slurm.sh" start "$W/slurm" || die "the one-node Slurm did not start"
export SLURM_CONF=$W/slurm/slurm.conf

# The command block after the page's marker "cluster.slurm runs this block (NAME)": its indented lines.
doc_block() {
    awk -v tag="cluster.slurm runs this block ($1)" '
        index($0, tag) { found = 1; next }
        found && /^    / { sub(/^    /, ""); print; inblock = 1; next }
        found && inblock { exit }' "$SRC/docs/regression.md"
}
submit=$(doc_block submit)
resubmit=$(doc_block resubmit)
[ -n "$submit" ] && [ -n "$resubmit" ] || die "docs/regression.md: the submit or resubmit block is missing"

# Waits until job $1 (or array element) has left the queue; 300 s at most.
wait_job() {
    for _ in $(seq 600); do
        [ -z "$(squeue -h -j "$1" 2>/dev/null)" ] && return 0
        sleep 0.5
    done
    die "job $1 still queued after 300 s: $(squeue -j "$1")"
}
job_field() { scontrol show job "$1" | tr ' ' '\n' | sed -n "s/^$2=//p" | head -1; } # JOB FIELD

# --- 1. the suite on Slurm, one task cancelled, recovered -------------------------------------------
cd "$CLONE" || die "no $CLONE"
# The page's block, then its variables for the test (the job ids, the shard count, OUT).
bash -c "set -e; $submit"$'\n''echo "$array $merge $SHARDS $OUT $RCSIM $SWEEP"' >submit.txt 2>submit.err ||
    die "the submit block failed: $(cat submit.err)"
read -r array merge shards out rcsim sweep <submit.txt
[ "$shards" = 4 ] || fail "the page's shard count for the suite's 17 runs: '$shards', expected 4"
[ "$out" = "$CLONE/cluster/suite" ] || fail "OUT: '$out'"

# Cancel array index 2 once it runs and one of its runs has started (its run.log exists).
# Its runs: 2, 6, 10, 14 of the sweep (shard 2 of 4).
ids=$(build/rcsim sweep scenarios/regress/suite.yaml --out "$W/ids" --list | cut -f1)
shard2=$(sed -n '3~4p' <<<"$ids")
for _ in $(seq 1500); do # 300 s: tasks 0 and 1 run first
    state=$(squeue -h -j "${array}_2" -o %T 2>/dev/null)
    if [ "$state" = RUNNING ]; then
        started=0
        for id in $shard2; do [ -f "$out/$id/run.log" ] && started=1; done
        [ "$started" -eq 1 ] && break
    fi
    [ -z "$state" ] && die "array task ${array}_2 ended before it could be cancelled"
    sleep 0.2
done
scancel "${array}_2" || die "scancel ${array}_2 failed"
wait_job "$merge"
[ "$(job_field "${array}_2" JobState)" = CANCELLED ] || fail "the cancelled task: $(job_field "${array}_2" JobState)"
for k in 0 1 3; do
    [ "$(job_field "${array}_$k" ExitCode)" = 0:0 ] || fail "task $k: exit $(job_field "${array}_$k" ExitCode), $(cat "$out/slurm-${array}_$k.err")"
    [ -f "$out/slurm-${array}_$k.out" ] || fail "no per-task output file slurm-${array}_$k.out under OUT"
done
[ "$(job_field "$merge" JobState)" = COMPLETED ] || fail "the merge after a cancelled task: $(job_field "$merge" JobState)"
mlog=$out/slurm-merge-$merge.out
grep -q "^incomplete: [1-9][0-9]* of 17 runs did not complete" "$mlog" || fail "the merge does not say it is incomplete: $(cat "$mlog")"
for id in $shard2; do
    status=$(/usr/bin/python3 -c 'import json,sys; print([r["status"] for r in json.load(open(sys.argv[1]))["results"] if r["id"] == sys.argv[2]][0])' "$out/summary.json" "$id")
    case $status in
        "interrupted" | "not run") grep -qF "rcsim merge: run $id: $status (" "$mlog" || fail "the merge does not name $id ($status)" ;;
        *) ;; # completed before the cancel
    esac
done
grep -q "interrupted\|not run" <(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1])))' "$out/summary.json") ||
    fail "summary.json has no interrupted or not run run after the cancel"
missing=$(build/rcsim sweep scenarios/regress/suite.yaml --out "$out" --missing --shards 4)
[ "$missing" = 2 ] || fail "--missing --shards 4 after cancelling index 2: '$missing'"

# The page's resubmit block with what the submit block exported, as in the user's shell.
RCSIM=$rcsim SWEEP=$sweep OUT=$out SHARDS=$shards bash -c "set -e; $resubmit"$'\n''echo "$array $merge"' \
    >resubmit.txt 2>resubmit.err && read -r array2 merge2 <resubmit.txt || die "the resubmit block failed: $(cat resubmit.err)"
wait_job "$merge2"
[ "$(job_field "${array2}_2" ExitCode)" = 0:0 ] || fail "the resubmitted task 2: $(job_field "${array2}_2" ExitCode)"
[ -z "$(build/rcsim sweep scenarios/regress/suite.yaml --out "$out" --missing --shards 4)" ] || fail "--missing after the resubmission is not empty"
grep -q "^incomplete" "$out/slurm-merge-$merge2.out" && fail "the merge after the resubmission: $(cat "$out/slurm-merge-$merge2.out")"

build/rcsim sweep scenarios/regress/suite.yaml --out "$W/local" --jobs 2 >local.txt 2>&1 || fail "the local sweep: $(tail -3 local.txt)"
for f in summary.json summary.csv summary.html; do
    cmp -s "$W/local/$f" "$out/$f" || fail "$f merged on Slurm differs from the local sweep's"
done
echo "slurm: suite in 4 tasks, task 2 cancelled and resubmitted, merged equal to local"

# --- 2. bad input in one task -------------------------------------------------------------------
# Two short runs in two shards; the second's ROM wait states (65) are out of range: its task alone
# fails, with exit 2 and the message naming the file, line and run.
cat >"$W/base.yaml" <<'YAML'
duration_s: 0.1
drain_s: 0.3
ports:
  - {host: protocol, traffic: saturate, start_ms: 5, data_size: 16, tokens: {EC: 1}}
YAML
printf 'base: base.yaml\naxes:\n  board.wait_states.rom: [1, 65]\n' >"$W/bad.yaml"
bad_out=$W/bad
mkdir -p "$bad_out"
bad=$(RCSIM=$CLONE/build/rcsim SWEEP=$W/bad.yaml OUT=$bad_out SHARDS=2 sbatch --parsable --array=0-1 \
    --output="$bad_out/slurm-%A_%a.out" --error="$bad_out/slurm-%A_%a.err" --export=ALL scripts/cluster/sweep.sbatch) ||
    die "sbatch of the bad-input sweep failed"
bad_merge=$(sbatch --parsable --dependency=afterany:"$bad" --output="$bad_out/slurm-merge-%j.out" --wrap "$CLONE/build/rcsim merge $bad_out") ||
    die "sbatch of its merge failed"
wait_job "$bad_merge"
[ "$(job_field "${bad}_0" ExitCode)" = 0:0 ] || fail "the good task: $(job_field "${bad}_0" ExitCode)"
[ "$(job_field "${bad}_1" JobState)" = FAILED ] && [ "$(job_field "${bad}_1" ExitCode)" = 2:0 ] ||
    fail "the bad-input task: $(job_field "${bad}_1" JobState) exit $(job_field "${bad}_1" ExitCode), expected FAILED 2:0"
grep -qF "bad.yaml:3: run 'base-rom=65'" "$bad_out/slurm-${bad}_1.err" || fail "the bad task's .err: $(cat "$bad_out/slurm-${bad}_1.err")"
grep -qF "rcsim merge: run base-rom=65: no report (" "$bad_out/slurm-merge-$bad_merge.out" ||
    fail "the merge does not name the bad run: $(cat "$bad_out/slurm-merge-$bad_merge.out")"
grep -q "^incomplete: 1 of 2 runs" "$bad_out/slurm-merge-$bad_merge.out" || fail "the merge does not count 1 of 2 incomplete"
[ "$(build/rcsim sweep "$W/bad.yaml" --out "$bad_out" --missing)" = base-rom=65 ] || fail "--missing does not list the bad run"
echo "slurm: bad input fails its array element with exit 2, the merge names the run"

[ "$failures" -eq 0 ] || { echo "cluster.slurm: $failures failure(s)"; exit 1; }
echo "cluster.slurm: passed"
