#!/usr/bin/env bash
# rcsim sweep / merge / compare end to end (docs/regression.md):
#   1. --list: one line per run, id TAB the command; the command alone reproduces the run;
#   2. sweep --jobs 2 writes every run and the summary; quiet when not on a terminal; a progress
#      line with an ETA on one;
#   3. the GNU parallel recipe (--list | cut -f2 | parallel, then merge) gives byte-identical
#      reports and summaries;
#   4. merging the same runs split over two directories, named in the other order, gives the same
#      bytes;
#   5. shards from --shard, the Slurm array and the Kubernetes Indexed Job variables: their union
#      is exactly the run list, no run twice, and a shard leaves the other shards' runs alone;
#   6. compare: the same runs pass; a changed figure, a lost check, a missing run regress;
#      --allow-missing; JUnit checked by xmllint against the usual shape, counts consistent;
#   6b. expected failures (expect_fail): a declared check that passes fails the sweep (exit 1);
#   7. bad input: exit 2 and one message naming file:line or the value.
#
# Usage: cli_test.sh RCSIM SOURCE_DIR
set -u
RCSIM=$(realpath "${1:?usage: cli_test.sh RCSIM SOURCE_DIR}")
SRC=$(realpath "${2:?usage: cli_test.sh RCSIM SOURCE_DIR}")
W=$(mktemp -d "${TMPDIR:-/tmp}/rcsim_sweep_cli.XXXXXX")
trap 'rm -rf "$W"' EXIT
cd "$W" || exit 1
unset CI SLURM_ARRAY_TASK_ID SLURM_ARRAY_TASK_COUNT SLURM_ARRAY_TASK_MIN JOB_COMPLETION_INDEX
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# Four short runs: 0.1 s of two saturated ports each.
cat > base.yaml <<'EOF'
duration_s: 0.1
drain_s: 0.3
ports:
  - {host: protocol, traffic: saturate, start_ms: 5, data_size: 16, tokens: {EC: 1}}
  - {host: protocol, traffic: saturate, start_ms: 5, data_size: 16, tokens: {EC: 1}}
EOF
cat > s.yaml <<'EOF'
name: t
base: base.yaml
axes:
  board.wait_states.rom: [0, 2]
  seed: [1, 2]
EOF
IDS="t-rom=0-seed=1 t-rom=0-seed=2 t-rom=2-seed=1 t-rom=2-seed=2"

# --- 1. --list ----------------------------------------------------------------------------------
"$RCSIM" sweep s.yaml --out L --list > list.txt || fail "--list exit $?"
[ "$(cut -f1 list.txt | tr '\n' ' ')" = "$IDS " ] || fail "--list ids: $(cut -f1 list.txt | tr '\n' ' ')"
[ "$(awk -F'\t' 'NF == 2' list.txt | wc -l)" -eq 4 ] || fail "--list lines are not id TAB command"
[ -f "L/t-rom=2-seed=1/scenario.yaml" ] || fail "--list did not write the scenario files"
[ ! -f "L/t-rom=2-seed=1/report.json" ] || fail "--list ran a run"
# The listed command alone: its report is the one the sweep writes (checked in 3).
bash -c "$(sed -n 3p list.txt | cut -f2)" > /dev/null || fail "the listed command of t-rom=2-seed=1 failed"
# --symbols reaches every run, with the path made absolute (the runs start in their own folders).
printf 'start F000:0000\n' > my.sym
"$RCSIM" sweep s.yaml --out LS --list --symbols my.sym > list_sym.txt || fail "--list --symbols exit $?"
[ "$(grep -cF -- "--symbols $PWD/my.sym" list_sym.txt)" -eq 4 ] || fail "--symbols is not in every run: $(cat list_sym.txt)"

# --- 2. sweep --jobs 2 --------------------------------------------------------------------------
"$RCSIM" sweep s.yaml --out A --jobs 2 > a_out.txt 2> a_err.txt || fail "sweep exit $?: $(cat a_err.txt)"
for id in $IDS; do [ -f "A/$id/report.json" ] || fail "sweep: no A/$id/report.json"; done
for f in summary.json summary.csv summary.html; do [ -s "A/$f" ] || fail "sweep: no A/$f"; done
[ "$(wc -l < a_err.txt)" -eq 1 ] && grep -q "^sweep: 4 runs, 0 failed" a_err.txt ||
    fail "not on a terminal the sweep prints one line: $(cat a_err.txt)"
grep -q "ETA" a_err.txt && fail "a progress line outside a terminal"
if command -v script > /dev/null; then
    script -qec "$RCSIM sweep s.yaml --out T --jobs 2" /dev/null > tty.txt 2>&1
    grep -q "ETA" tty.txt || fail "no progress line on a terminal"
    CI=1 script -qec "$RCSIM sweep s.yaml --out T --jobs 2" /dev/null > ci.txt 2>&1
    grep -q "ETA" ci.txt && fail "a progress line with CI set"
fi
cmp -s "L/t-rom=2-seed=1/report.json" "A/t-rom=2-seed=1/report.json" ||
    fail "the listed command's report differs from the sweep's"
[ "$(head -1 A/summary.csv | cut -d, -f1-5)" = "id,entry,status,param:board.wait_states.rom,param:seed" ] ||
    fail "summary.csv header: $(head -1 A/summary.csv | cut -c1-80)"
[ "$(tail -n +2 A/summary.csv | wc -l)" -eq 4 ] || fail "summary.csv: not one row per run"

# --- 3. GNU parallel ----------------------------------------------------------------------------
if command -v parallel > /dev/null; then
    "$RCSIM" sweep s.yaml --out P --list | cut -f2 | parallel -j2 > /dev/null
    "$RCSIM" merge P > /dev/null || fail "merge P exit $?"
    for f in summary.json summary.csv summary.html; do cmp -s "A/$f" "P/$f" || fail "parallel recipe: $f differs"; done
    for id in $IDS; do cmp -s "A/$id/report.json" "P/$id/report.json" || fail "parallel recipe: $id/report.json differs"; done
else
    fail "GNU parallel is not installed (scripts/install-deps.sh)"
fi

# --- 4. merge: order and split ------------------------------------------------------------------
mkdir -p X Y
cp -r "A/t-rom=0-seed=1" "A/t-rom=2-seed=2" X/
cp -r "A/t-rom=0-seed=2" "A/t-rom=2-seed=1" Y/
"$RCSIM" merge Y X --out M > /dev/null || fail "merge Y X exit $?"
for f in summary.json summary.csv summary.html; do cmp -s "A/$f" "M/$f" || fail "split merge: $f differs"; done

# --- 5. shards ----------------------------------------------------------------------------------
shard_ids() { # prints the ids every shard lists, one per line
    for k in 0 1 2; do "$@" "$k"; done | cut -f1 | sort
}
all=$(echo $IDS | tr ' ' '\n' | sort)
got=$(shard_ids sh -c '"$0" sweep s.yaml --out S1 --list --shard "$1/3"' "$RCSIM")
[ "$got" = "$all" ] || fail "--shard K/3: union is not the run list: $got"
got=$(shard_ids sh -c 'SLURM_ARRAY_TASK_ID=$(($1 + 1)) SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_COUNT=3 "$0" sweep s.yaml --out S2 --list' "$RCSIM")
[ "$got" = "$all" ] || fail "Slurm array: union is not the run list: $got"
got=$(shard_ids sh -c 'JOB_COMPLETION_INDEX=$1 "$0" sweep s.yaml --out S3 --list --shards 3' "$RCSIM")
[ "$got" = "$all" ] || fail "Indexed Job: union is not the run list: $got"
[ "$(JOB_COMPLETION_INDEX=0 "$RCSIM" sweep s.yaml --out S3 --list --shards 3 | wc -l)" -eq 2 ] ||
    fail "shard 0 of 3 of 4 runs is not runs 0 and 3"
# Real shards into one directory: shard 1 must leave shard 0's runs alone; then merge.
SLURM_ARRAY_TASK_ID=0 SLURM_ARRAY_TASK_COUNT=2 "$RCSIM" sweep s.yaml --out D --jobs 2 > d0.txt 2>&1
touch "D/t-rom=0-seed=1/marker"
SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_COUNT=2 "$RCSIM" sweep s.yaml --out D --jobs 2 > d1.txt 2>&1
[ -f "D/t-rom=0-seed=1/marker" ] || fail "shard 1 touched shard 0's run"
[ ! -f D/summary.json ] || fail "a shard merged before every shard was done"
grep -q "rcsim merge" d1.txt || fail "a shard does not say how to merge"
"$RCSIM" merge D > /dev/null
for f in summary.json summary.csv summary.html; do cmp -s "A/$f" "D/$f" || fail "merged shards: $f differs"; done

# The shipped recipes, run here as the cluster would: two Slurm array tasks, then the Indexed Job's
# pods one by one (its command with the paths of this test).
for k in 0 1; do
    SLURM_ARRAY_TASK_ID=$k SLURM_ARRAY_TASK_COUNT=2 SLURM_CPUS_PER_TASK=2 RCSIM=$RCSIM SWEEP=s.yaml OUT=SB \
        bash "$SRC/scripts/cluster/sweep.sbatch" > "sb$k.txt" 2>&1 || fail "sweep.sbatch task $k: $(tail -2 "sb$k.txt")"
done
"$RCSIM" merge SB > /dev/null
for f in summary.json summary.csv summary.html; do cmp -s "A/$f" "SB/$f" || fail "Slurm recipe: $f differs"; done
MANIFEST=$SRC/scripts/cluster/sweep-indexed-job.yaml
pods=$(sed -n 's/^ *completions: *\([0-9]*\)$/\1/p' "$MANIFEST")
cmd=$(grep -o '"rcsim sweep [^"]*"' "$MANIFEST" | tr -d '"')
echo "$cmd" | grep -q -- "--shards $pods " || fail "the Indexed Job's --shards is not its completions ($pods): $cmd"
grep -q "completionMode: Indexed" "$MANIFEST" || fail "the Job is not an Indexed Job"
cmd=${cmd/rcsim /\"\$RCSIM\" }
cmd=${cmd/scenarios\/regress\/suite.yaml/s.yaml}
cmd=${cmd/\/results\/suite/K8}
for k in $(seq 0 $((pods - 1))); do
    JOB_COMPLETION_INDEX=$k RCSIM=$RCSIM sh -c "$cmd" > "k8s$k.txt" 2>&1 || fail "Indexed Job pod $k: $(tail -2 "k8s$k.txt")"
done
"$RCSIM" merge K8 > /dev/null
for f in summary.json summary.csv summary.html; do cmp -s "A/$f" "K8/$f" || fail "Indexed Job recipe: $f differs"; done

# --- 6. compare ---------------------------------------------------------------------------------
junit_shape() { # FILE: the usual JUnit shape, counts consistent
    local f=$1
    xmllint --noout "$f" || { fail "$f is not well-formed XML"; return; }
    local x="xmllint --xpath"
    [ "$($x 'count(/testsuites)' "$f")" = 1 ] || fail "$f: no <testsuites> root"
    [ "$($x 'count(/testsuites/testsuite)' "$f")" -ge 1 ] || fail "$f: no <testsuite>"
    [ "$($x 'count(//testcase[not(parent::testsuite)])' "$f")" = 0 ] || fail "$f: a testcase outside a testsuite"
    [ "$($x 'string(/testsuites/@tests)' "$f")" = "$($x 'count(//testcase)' "$f")" ] || fail "$f: tests != testcases"
    [ "$($x 'string(/testsuites/@failures)' "$f")" = "$($x 'count(//testcase/failure)' "$f")" ] || fail "$f: failures"
    [ "$($x 'string(/testsuites/@skipped)' "$f")" = "$($x 'count(//testcase/skipped)' "$f")" ] || fail "$f: skipped"
    [ "$($x 'sum(/testsuites/testsuite/@tests)' "$f")" = "$($x 'string(/testsuites/@tests)' "$f")" ] || fail "$f: suite sums"
    [ "$($x 'count(//testcase[not(@classname) or not(@name)])' "$f")" = 0 ] || fail "$f: testcase without a name"
    for s in $($x 'count(/testsuites/testsuite)' "$f" | xargs seq 1); do
        [ "$($x "string(/testsuites/testsuite[$s]/@failures)" "$f")" = "$($x "count(/testsuites/testsuite[$s]/testcase/failure)" "$f")" ] ||
            fail "$f: testsuite $s failures"
    done
}
"$RCSIM" compare A P --junit same.xml --html same.html > same.txt; rc=$?
[ "$rc" -eq 0 ] || fail "compare A P: exit $rc, expected 0"
junit_shape same.xml
[ "$(xmllint --xpath 'string(/testsuites/@failures)' same.xml)" = 0 ] || fail "same runs: JUnit failures"
[ "$(xmllint --xpath 'count(/testsuites/testsuite)' same.xml)" = 4 ] || fail "not one testsuite per run"
grep -q "<h1>rcsim compare</h1>" same.html || fail "no compare.html"
[ "$(tail -n 2 same.txt)" = "$(printf 'junit: same.xml\nhtml:  same.html')" ] ||
    fail "compare's summary does not end with the paths it wrote: $(tail -n 2 same.txt)"

cp -r A C
# One figure moves, one check stops passing, one run is gone.
sed -i 's/"rs232_isr_us": \([0-9.]*\)/"rs232_isr_us": 999.5/' "C/t-rom=0-seed=1/report.json"
# report.json is written with sorted keys: the first "passed" is checks[0]'s.
sed -i '0,/"passed": true/s//"passed": false/' "C/t-rom=0-seed=2/report.json"
rm -rf "C/t-rom=2-seed=2"
"$RCSIM" compare A C --junit reg.xml --html reg.html > reg.txt; rc=$?
[ "$rc" -eq 1 ] || fail "compare A C: exit $rc, expected 1"
junit_shape reg.xml
grep -q "table3.rs232_isr_us .* t-rom=0-seed=1 .*999.5" reg.txt || fail "the changed figure is not listed: $(cat reg.txt)"
grep -q "run missing from current .* t-rom=2-seed=2" reg.txt || fail "the missing run is not listed"
grep -q "check .* t-rom=0-seed=2 .*PASS .*FAIL" reg.txt || fail "the failing check is not listed"
[ "$(xmllint --xpath 'count(//testcase[@name="figures table3"]/failure[contains(@message, "table3.rs232_isr_us")])' reg.xml)" = 1 ] ||
    fail "JUnit: no failure of the table3 family naming table3.rs232_isr_us"
grep -q 'class="reg"' reg.html || fail "compare.html marks no regression"
rm -rf "C/t-rom=0-seed=1" "C/t-rom=0-seed=2"
cp -r "A/t-rom=0-seed=1" "A/t-rom=0-seed=2" C/
"$RCSIM" compare A C > /dev/null; rc=$?
[ "$rc" -eq 1 ] || fail "a missing run: exit $rc, expected 1"
"$RCSIM" compare A C --allow-missing > allow.txt; rc=$?
[ "$rc" -eq 0 ] || fail "a missing run with --allow-missing: exit $rc, expected 0"
"$RCSIM" compare "A/t-rom=0-seed=1/report.json" "P/t-rom=0-seed=1/report.json" > /dev/null; rc=$?
[ "$rc" -eq 0 ] || fail "two report.json files: exit $rc, expected 0"

# --- 6b. expected failures: a run that passes a check it declares it fails fails the sweep -------
printf 'name: x\nbase: base.yaml\nexpect_fail: [overruns]\n' > xfail.yaml
"$RCSIM" sweep xfail.yaml --out X --jobs 1 > /dev/null 2> x_err.txt; rc=$?
[ "$rc" -eq 1 ] && grep -qF "run x: check overruns: expected to fail, passed" x_err.txt ||
    fail "an expected failure that passed: exit $rc, $(cat x_err.txt)"
grep -q '"outcome": "failed"' X/summary.json && grep -q '"status": "passed"' X/summary.json ||
    fail "summary.json lacks the run's status beside its outcome"

# --- 7. bad input ---------------------------------------------------------------------------------
expect2() { # SUBSTRING ARGS...: exit 2, one line on stderr holding SUBSTRING
    local want=$1
    shift
    timeout 60 "$RCSIM" "$@" > bad_out.txt 2> bad_err.txt
    local rc=$?
    [ "$rc" -eq 2 ] || fail "rcsim $*: exit $rc, expected 2"
    grep -qF -- "$want" bad_err.txt || fail "rcsim $*: stderr lacks '$want': $(cat bad_err.txt)"
    [ "$(grep -cv '^Run with --help' bad_err.txt)" -eq 1 ] || fail "rcsim $*: not one line on stderr"
}
printf 'base: base.yaml\naxes:\n  seed: [1]\n  frob: 3\n' > bad1.yaml
expect2 "bad1.yaml:4: axis 'frob': values must be a non-empty list" sweep bad1.yaml --out B
printf 'base: base.yaml\naxes:\n  board.wait_states.rom: [1, 65]\n' > bad2.yaml
expect2 "bad2.yaml:3: run 'base-rom=65': " sweep bad2.yaml --out B
printf 'base: base.yaml\naxes:\n  seeds: [1]\n' > bad3.yaml
expect2 "unknown key 'seeds'" sweep bad3.yaml --out B
printf 'base: base.yaml\naxes: {seed: [1, 2\n' > bad4.yaml
expect2 "bad4.yaml:3: YAML syntax error" sweep bad4.yaml --out B
printf 'base: base.yaml\nexpect_fail: [overruns, overrun]\n' > bad5.yaml
expect2 "bad5.yaml:2: 'expect_fail': 'overrun' is not a check name" sweep bad5.yaml --out B
expect2 "missing.yaml: cannot open" sweep missing.yaml --out B
expect2 "shard 3/2" sweep s.yaml --out B --shard 3/2
expect2 "--shard 'x' must be K/N" sweep s.yaml --out B --shard x
SLURM_ARRAY_TASK_ID=a SLURM_ARRAY_TASK_COUNT=2 expect2 "SLURM_ARRAY_TASK_ID 'a' is not a number" sweep s.yaml --out B
expect2 "nope.rom: --rom: no such ROM image" sweep s.yaml --out B --rom nope.rom
expect2 "--symbols: nope.map: cannot open the symbol file" sweep s.yaml --out B --symbols nope.map
expect2 "nodir: not a directory of runs" merge nodir
expect2 "nodir: no such report.json or run directory" compare A nodir
mkdir -p empty && expect2 "empty: holds no run" compare A empty
cp -r A J && printf '{\n  "scenario": "x",\n  oops\n}\n' > "J/t-rom=0-seed=1/report.json"
expect2 "J/t-rom=0-seed=1/report.json:3: bad JSON" compare A J
printf '[1, 2]\n' > list.json
expect2 "list.json:1: not an rcsim report.json" compare list.json "A/t-rom=0-seed=1/report.json"
# Reports of the wrong shape compare (a malformed `passed` counts as failed), never crash.
cp -r A O && sed -i '0,/"passed": true/s//"passed": "yes"/' "O/t-rom=0-seed=1/report.json"
"$RCSIM" compare A O > odd.txt 2> odd_err.txt; rc=$?
[ "$rc" -eq 1 ] && grep -q "check .* t-rom=0-seed=1 .*PASS .*FAIL" odd.txt || fail "a check with passed: \"yes\": exit $rc, $(cat odd_err.txt)"
printf '{"scenario": 5, "checks": 3, "passed": []}\n' > odd.json
"$RCSIM" compare odd.json odd.json > /dev/null 2> odd_err.txt; rc=$?
[ "$rc" -eq 0 ] || fail "an odd report against itself: exit $rc, $(cat odd_err.txt)"
printf 'tolerances:\n  - {figure: x, better: sideways}\n' > tol.yaml
expect2 "tol.yaml:2: 'tolerances[0].better' must be" compare A P --tolerances tol.yaml

# --- 8. what a cancelled cluster task leaves: --missing, the merge naming the runs ---------------
# (CTest cluster.slurm does this on a real Slurm; here the directories are made by hand.)
[ -z "$("$RCSIM" sweep s.yaml --out A --missing)" ] || fail "--missing of a complete sweep is not empty"
[ -z "$("$RCSIM" sweep s.yaml --out A --missing --shards 4)" ] || fail "--missing --shards of a complete sweep is not empty"
cp -r A MISS && rm "MISS/t-rom=2-seed=1/report.json" && rm -r "MISS/t-rom=2-seed=2" &&
    sed -i 's/"verdict": "[a-z]*"/"verdict": "interrupted"/' "MISS/t-rom=0-seed=2/report.json" || fail "cannot make MISS"
before=$(find MISS | sort)
[ "$("$RCSIM" sweep s.yaml --out MISS --missing | tr '\n' ' ')" = "t-rom=0-seed=2 t-rom=2-seed=1 t-rom=2-seed=2 " ] ||
    fail "--missing: $("$RCSIM" sweep s.yaml --out MISS --missing)"
# Runs 1, 2 and 3 of the sweep: shards 1, 2, 3 of 4; 1, 0, 1 of 2.
[ "$("$RCSIM" sweep s.yaml --out MISS --missing --shards 4)" = 1,2,3 ] || fail "--missing --shards 4: $("$RCSIM" sweep s.yaml --out MISS --missing --shards 4)"
[ "$("$RCSIM" sweep s.yaml --out MISS --missing --shards 2)" = 0,1 ] || fail "--missing --shards 2"
[ "$(find MISS | sort)" = "$before" ] || fail "--missing wrote or removed files"
"$RCSIM" merge MISS > m_out.txt 2> m_err.txt || fail "merge of an incomplete sweep: exit $?"
grep -qF "rcsim merge: run t-rom=0-seed=2: interrupted (MISS/t-rom=0-seed=2/run.log)" m_err.txt &&
    grep -qF "rcsim merge: run t-rom=2-seed=1: no report (MISS/t-rom=2-seed=1/run.log)" m_err.txt &&
    [ "$(wc -l < m_err.txt)" -eq 2 ] || fail "the merge does not name the unfinished runs: $(cat m_err.txt)"
grep -q "^incomplete: 2 of 3 runs did not complete" m_out.txt || fail "the merge does not say it is incomplete: $(cat m_out.txt)"
"$RCSIM" merge A > m_out.txt 2> m_err.txt && [ ! -s m_err.txt ] && ! grep -q incomplete m_out.txt ||
    fail "the merge of a complete sweep: $(cat m_out.txt m_err.txt)"

if [ "$failures" -eq 0 ]; then echo "sweep cli: ok"; else echo "sweep cli: $failures failures"; fi
[ "$failures" -eq 0 ]
