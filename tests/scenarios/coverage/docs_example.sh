#!/usr/bin/env bash
# docs/tools.md "Coverage": runs the commands of the section's example as the page shows them
# (rcsim from the build, the output folder in the test's work folder) and checks what they say
# they give: coverage.info that lcov summarises and genhtml renders with isr.s's lines.
#   docs_example.sh RCSIM SOURCE_DIR WORK
set -euo pipefail
rcsim=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
# The section's first command block, its "$ " lines.
cmds=$(awk '/^## Coverage/ {s=1} s && /^```/ {if (b) exit; b=1; next} s && b && /^\$ / {print substr($0, 3)}' "$src/docs/tools.md")
[ "$(printf '%s\n' "$cmds" | wc -l)" -eq 3 ] || { echo "expected 3 commands in docs/tools.md Coverage, got: $cmds"; exit 1; }
cd "$src"
n=0
while IFS= read -r cmd; do
    n=$((n + 1))
    cmd=${cmd//build\/rcsim/$rcsim}
    cmd=${cmd//--out out/--out $work/out}
    cmd=${cmd// out\// $work/out/}
    echo "+ $cmd"
    eval "$cmd" > "$work/cmd$n.txt" 2>&1 || { cat "$work/cmd$n.txt"; echo "failed: $cmd"; exit 1; }
    cat "$work/cmd$n.txt"
done <<< "$cmds"
# lcov's summary: some lines hit.
grep -Eq 'lines\.+: [0-9.]+% \([1-9][0-9]* of [0-9]+ lines\)' "$work/cmd2.txt" || { echo "lcov --summary: no lines hit"; exit 1; }
[ -s "$work/out/coverage.info" ] || { echo "no coverage.info"; exit 1; }
page=$(find "$work/out/html" -name 'isr.s.gcov.html' | head -1)
[ -n "$page" ] || { echo "genhtml wrote no page for isr.s"; exit 1; }
grep -q "line_status:" "$page" || { echo "the isr.s page lacks its source lines"; exit 1; }
grep -q '<section id="coverage">' "$work/out/report.html" || { echo "report.html has no coverage section"; exit 1; }
echo "docs example: ok"
