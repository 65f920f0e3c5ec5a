#!/usr/bin/env bash
# Every reference in the repository's code comments and docs must resolve inside the repository:
#  1. no file cites a document that lives outside it (the old specification and reference notes,
#     the source papers by their file names) — docs/system.md and the chip pages replace them;
#  2. every "docs/system.md §N" (or "section N") names a section that docs/system.md has, and so
#     does every "§N" inside docs/system.md itself.
# Lines that locate the SingleStepTests vectors (../shared/sst8086/v1, $RCSIM_SST_DIR,
# RCSIM_SHARED_DIR) name a data location, not a document, and are allowed.
#
# Usage: check_references.sh SOURCE_DIR. Prints each offending FILE:LINE; exit 0 clean, 1 if any
# reference is broken, 2 on bad usage.
set -u
ROOT=${1:-}
if [ -z "$ROOT" ] || [ ! -d "$ROOT" ]; then
    echo "usage: check_references.sh SOURCE_DIR (got '${ROOT}')" >&2
    exit 2
fi
cd "$ROOT" || exit 2
SPEC=docs/system.md
if [ ! -f "$SPEC" ]; then
    echo "$ROOT/$SPEC: missing (the specification every reference points to)" >&2
    exit 1
fi

# The files to check: what git tracks, or (outside a git work tree) every file but build trees.
# The checker's own folder spells the patterns out and is skipped.
list_files() {
    if command -v git > /dev/null && [ "$(git rev-parse --show-toplevel 2> /dev/null)" = "$(pwd -P)" ]; then
        git ls-files -z
    else
        find . \( -name .git -o -name 'build*' \) -prune -o -type f -print0 | sed -z 's|^\./||'
    fi | grep -zv '^tests/docs/'
}

# Documents outside the repository, as they were cited.
OUTSIDE='(^|[^A-Za-z0-9_])shared/|SYSTEM\.md|chips\.md|virtual-platforms|reference/[A-Za-z-]+\.md|reference/motion|(^|[^/A-Za-z])motion\.md §|seeds/|seed paper|the seed'"'"'s|00[0-9]_[0-9a-f]{16}|UPSTREAM_README'
# Data locations of the 8086 test vectors, not citations.
ALLOWED='sst8086/v1|RCSIM_SST_DIR|RCSIM_SHARED_DIR'

bad=0
while IFS= read -r hit; do
    echo "$hit: cites a document outside the repository (use docs/system.md §N or a chip page)"
    bad=1
done < <(list_files | xargs -0 -r grep -nIE "$OUTSIDE" -- | grep -vE "^[^:]*:[0-9]+:.*($ALLOWED)")

# Section numbers docs/system.md defines: headings "## §4 ..." / "### §4.3 ...".
sections=$(grep -oE '^#+ §[0-9]+(\.[0-9]+)*' "$SPEC" | sed 's/^#* §//')
has_section() { printf '%s\n' "$sections" | grep -qxF "$1"; }

# A reference: "docs/system.md §4", "docs/system.md §4.3", "docs/system.md §4 to §6",
# "docs/system.md section 2, section 3" (C comments keep to ASCII).
NUM='(§|section )[0-9]+(\.[0-9]+)*'
REF="(docs/)?system\.md $NUM(((,|;)? (and |to |or )?| ?[-–] ?)$NUM)*"
while IFS= read -r hit; do
    file=${hit%%:*}
    rest=${hit#*:}
    line=${rest%%:*}
    for n in $(printf '%s\n' "${rest#*:}" | grep -oE "$NUM" | grep -oE '[0-9]+(\.[0-9]+)*'); do
        if ! has_section "$n"; then
            echo "$file:$line: cites docs/system.md §$n, which docs/system.md does not have"
            bad=1
        fi
    done
done < <(list_files | xargs -0 -r grep -noIE "$REF" --)

# References inside docs/system.md itself ("(§4.5)", "§10, item 6").
while IFS=: read -r line ref; do
    n=${ref#§}
    if ! has_section "$n"; then
        echo "$SPEC:$line: refers to §$n, which this page does not have"
        bad=1
    fi
done < <(grep -v '^#' -n "$SPEC" | grep -oE '^[0-9]+:|§[0-9]+(\.[0-9]+)*' | awk '/:$/ {l=$0; next} {print l $0}')

exit $bad
