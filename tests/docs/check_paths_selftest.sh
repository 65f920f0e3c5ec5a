#!/usr/bin/env bash
# The path checker (tests/docs/check_paths.py) must fail on each kind of broken path and pass a
# clean tree, and must leave alone what is not a repository path: run it on small trees made
# here, one fault at a time, with and without git.
#
# Usage: check_paths_selftest.sh CHECKER
set -u
CHECK=$(realpath "${1:?usage: check_paths_selftest.sh CHECKER}")
CHECK_COMMAND=(/usr/bin/python3 "$CHECK")
TAG=pathcheck
# shellcheck source=selftest_lib.sh
source "$(dirname "$0")/selftest_lib.sh"

# A clean tree: docs naming files, folders, a glob, the .h/.cpp shorthand, and things that are
# not repository paths (build outputs, user paths, placeholders); code citing a page.
clean_tree() {
    T=$W/tree; rm -rf "$T"; mkdir -p "$T/docs" "$T/models" "$T/scenarios/run" "$T/.ci"
    printf '# Models\n' > "$T/docs/models.md"
    printf 'int x;\n' > "$T/models/stats.h"
    printf 'int y;\n' > "$T/models/stats.cpp"
    printf 'run: x\n' > "$T/scenarios/run/a.yaml"
    printf '#!/bin/sh\n' > "$T/.ci/run"
    cat > "$T/README.md" << 'EOF'
See `models/stats.h` (and models/stats.h/.cpp), docs/models.md. The folders scenarios/run and
models/, the CI script .ci/run; every scenarios/run/*.yaml. Not the repository's: build/models/x.h,
/tmp/docs/out.md, $DIR/models/y.h, ../shared/docs/z.md, tests/<dir>/, scenarios/${folder}/,
docs/{a,b}.md, scenarios/DIR/report.json, my_scenarios/mine.yaml.
EOF
    printf '// The statistics (docs/models.md; models/gone.h is not checked in code).\n' > "$T/models/stats.cpp"
    printf '<p>docs/models.md.</p>\n' > "$T/models/page.html"
}

for mode in find git; do
    if [ "$mode" = git ] && ! command -v git > /dev/null; then echo "git not installed: git mode skipped"; break; fi
    case_name="$mode: clean tree"; setup; expect 0

    case_name="$mode: a missing file in a doc"; setup
    printf '# Serial\n\nThe codec: `main_cpu/frame.h`.\n' > "$T/docs/serial.md"; track
    expect 1 "docs/serial.md:3: names main_cpu/frame.h, which does not exist"

    case_name="$mode: a missing folder in a README"; setup
    printf 'The log is in scenarios/board/.\n' > "$T/scenarios/run/README.md"; track
    expect 1 "scenarios/run/README.md:1: names scenarios/board/, which does not exist"

    case_name="$mode: a missing file without an extension, at the end of a sentence"; setup
    printf 'CI runs .ci/test.\n' >> "$T/README.md"; track
    expect 1 "README.md:5: names .ci/test, which does not exist"

    case_name="$mode: half of a .h/.cpp shorthand missing"; setup
    printf 'See models/hex.h/.cpp and models/stats.h/.c.\n' > "$T/docs/hex.md"; track
    expect 1 "docs/hex.md:1: names models/hex.h, which does not exist"
    expect 1 "docs/hex.md:1: names models/stats.c, which does not exist"

    case_name="$mode: a glob matching nothing"; setup
    printf 'Each scenarios/run/*.json is kept.\n' > "$T/docs/g.md"; track
    expect 1 "docs/g.md:1: names scenarios/run/*.json, which does not exist"

    case_name="$mode: a code comment citing a missing page"; setup
    printf '# the window (docs/monitor.md "Windows")\n' > "$T/scenarios/run/b.yaml"; track
    expect 1 "scenarios/run/b.yaml:1: names docs/monitor.md, which does not exist"

    case_name="$mode: a top-level folder that is gone whole"; setup
    printf 'The chip model: `pic8259/pic.h`.\n' > "$T/docs/pic.md"; track
    expect 1 "docs/pic.md:1: names pic8259/pic.h, which does not exist"
done

# Only tracked files count in a git tree: an untracked file does not make a path resolve.
if command -v git > /dev/null; then
    case_name="git: an untracked file is not the repository's"; clean_tree
    printf 'See models/scratch.h.\n' > "$T/docs/s.md"
    (cd "$T" && git init -q . && git add -A)
    printf 'int z;\n' > "$T/models/scratch.h"
    expect 1 "docs/s.md:1: names models/scratch.h, which does not exist"
fi

case_name="bad usage"; T=$W/nonexistent; expect 2 "usage"

finish
