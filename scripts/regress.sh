#!/usr/bin/env bash
# The regression suite (docs/regression.md): runs scenarios/regress/suite.yaml and compares it with
# scenarios/regress/baseline/, or (--update) rewrites that baseline from a fresh run.
#
#   scripts/regress.sh [--update] RCSIM OUT [JOBS]
#
# OUT receives runs/ (the sweep), compare.html, junit.xml and coverage.info, the suite's firmware
# coverage merged over its runs (coverage/: genhtml's pages of it, when genhtml is installed).
# Exit: the comparison's (0 no regression, 1 regression, 2 bad input); with --update 0 once the
# baseline is rewritten.
set -u
update=0
if [ "${1:-}" = "--update" ]; then update=1; shift; fi
RCSIM=${1:?usage: regress.sh [--update] RCSIM OUT [JOBS]}
OUT=${2:?usage: regress.sh [--update] RCSIM OUT [JOBS]}
JOBS=${3:-$(nproc)}
SRC=$(cd "$(dirname "$0")/.." && pwd)
SUITE=$SRC/scenarios/regress/suite.yaml
BASELINE=$SRC/scenarios/regress/baseline
TOLERANCES=$SRC/scenarios/regress/tolerances.yaml

mkdir -p "$OUT" || exit 2
rm -rf "$OUT/runs"
# A run that fails a check is still a result to compare; only bad input stops here.
"$RCSIM" sweep "$SUITE" --out "$OUT/runs" --jobs "$JOBS" --coverage
rc=$?
if [ "$rc" -ge 2 ]; then echo "regress: the sweep failed (exit $rc)" >&2; exit 2; fi

if [ "$update" -eq 1 ]; then
    # The baseline keeps what compare reads, report.json per run, and the summary for people.
    rm -rf "$BASELINE"
    for run in "$OUT"/runs/*/; do
        id=$(basename "$run")
        [ -f "$run/report.json" ] || { echo "regress: $id has no report.json" >&2; exit 2; }
        mkdir -p "$BASELINE/$id" && cp "$run/report.json" "$BASELINE/$id/"
    done
    cp "$OUT/runs/summary.json" "$BASELINE/"
    echo "regress: baseline rewritten: $BASELINE ($(ls -d "$BASELINE"/*/ | wc -l) runs)"
    exit 0
fi

"$RCSIM" compare "$BASELINE" "$OUT/runs" --tolerances "$TOLERANCES" \
    --html "$OUT/compare.html" --junit "$OUT/junit.xml"
rc=$?
# The suite's coverage beside compare.html (docs/tools.md "Coverage").
cov=""
if [ -f "$OUT/runs/coverage.info" ]; then
    cp "$OUT/runs/coverage.info" "$OUT/coverage.info"
    cov=", $OUT/coverage.info"
    if command -v genhtml >/dev/null 2>&1; then
        rm -rf "$OUT/coverage"
        genhtml --quiet --branch-coverage -o "$OUT/coverage" "$OUT/coverage.info" >"$OUT/genhtml.log" 2>&1 &&
            cov="$cov, $OUT/coverage/index.html"
    fi
fi
echo "regress: $OUT/compare.html, $OUT/junit.xml$cov"
exit $rc
