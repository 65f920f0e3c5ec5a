#!/usr/bin/env bash
# The reference checker must fail on each kind of broken reference and pass a clean tree: run it
# on small trees made here, one fault at a time, with and without git.
#
# Usage: check_references_selftest.sh CHECKER
set -u
CHECK=$(realpath "${1:?usage: check_references_selftest.sh CHECKER}")
CHECK_COMMAND=(bash "$CHECK")
TAG=refcheck
# shellcheck source=selftest_lib.sh
source "$(dirname "$0")/selftest_lib.sh"

# A clean tree: a spec with §1 and §1.2, code citing them, the SST data location.
clean_tree() {
    T=$W/tree; rm -rf "$T"; mkdir -p "$T/docs" "$T/src"
    printf '# Spec\n\n## §1 One\n\nSee §1.2.\n\n### §1.2 One two\n' > "$T/docs/system.md"
    printf '// docs/system.md §1.2 and §1\n/* docs/system.md section 1 */\n' > "$T/src/good.cpp"
    printf 'Vectors: `../shared/sst8086/v1` or `$RCSIM_SST_DIR`.\n' > "$T/README.md"
}

for mode in find git; do
    if [ "$mode" = git ] && ! command -v git > /dev/null; then echo "git not installed: git mode skipped"; break; fi
    case_name="$mode: clean tree"; setup; expect 0

    case_name="$mode: old specification"; setup
    printf 'int x;\n// as SYSTEM.md §3 says\n' > "$T/src/bad.cpp"; track
    expect 1 "src/bad.cpp:2:"

    case_name="$mode: reference notes"; setup
    printf 'Facts: ../shared/reference/chips.md §2.\n' > "$T/docs/chip.md"; track
    expect 1 "docs/chip.md:1:"

    case_name="$mode: a source paper by its file name"; setup
    printf '// from 001_42c08beb1586f69e\n' > "$T/src/p.h"; track
    expect 1 "src/p.h:1:"

    case_name="$mode: the vectors' README is a document, not the data location"; setup
    printf 'Format: ../shared/sst8086/UPSTREAM_README.md\n' > "$T/docs/f.md"; track
    expect 1 "docs/f.md:1:"

    case_name="$mode: missing section"; setup
    printf '// docs/system.md §1 and §7\n' > "$T/src/s.h"; track
    expect 1 "src/s.h:1: cites docs/system.md §7"

    case_name="$mode: missing subsection in a C comment"; setup
    printf '/* docs/system.md section 1.3 */\n' > "$T/src/s.c"; track
    expect 1 "src/s.c:1: cites docs/system.md §1.3"

    case_name="$mode: the spec refers to a section it does not have"; setup
    printf 'Also (§9).\n' >> "$T/docs/system.md"; track
    expect 1 "docs/system.md:8: refers to §9"
done

# Only tracked files count in a git tree: an untracked scratch file is not the repository's.
if command -v git > /dev/null; then
    case_name="git: untracked file ignored"; clean_tree; (cd "$T" && git init -q . && git add -A)
    printf '// SYSTEM.md\n' > "$T/src/scratch.cpp"
    expect 0
fi

case_name="no spec"; clean_tree; rm "$T/docs/system.md"; expect 1 "docs/system.md: missing"
case_name="bad usage"; T=$W/nonexistent; expect 2 "usage"

finish
