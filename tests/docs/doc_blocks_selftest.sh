#!/usr/bin/env bash
# The docs-that-run checker fails on each kind of broken block (tests/docs/doc_blocks.py): a block
# nobody annotated, a skip without a reason, a command that exits otherwise than the page says,
# output that differs from what the page quotes, and a synopsis of a command rcsim does not have;
# and it passes a page whose blocks hold.
#
# Usage: doc_blocks_selftest.sh DOC_BLOCKS_PY BUILD_DIR
set -u
CHECK=$(realpath "${1:?usage}")
BUILD=$(realpath "${2:?usage}")
W=$(mktemp -d "${TMPDIR:-/tmp}/rcsim_doc_selftest.XXXXXX")
trap 'rm -rf "$W"' EXIT
mkdir -p "$W/src/docs"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

page() { cat > "$W/src/docs/page.md"; }
# expect_fail WHAT: the checker exits 1 and its report names WHAT
expect_fail() {
    /usr/bin/python3 "$CHECK" "$W/src" "$BUILD" docs/page.md > "$W/out.txt" 2>&1
    local rc=$?
    [ "$rc" -eq 1 ] || fail "$1: exit $rc, expected 1: $(cat "$W/out.txt")"
    grep -q -- "$1" "$W/out.txt" || fail "the report does not say '$1': $(cat "$W/out.txt")"
}

printf 'Run it:\n\n    echo hello\n' | page
expect_fail "page.md:3: an indented block without <!-- doc-test"

printf '<!-- doc-test: skip -->\n```\nmake run\n```\n' | page
expect_fail "page.md:2: doc-test skip without a reason"

printf '<!-- doc-test: run -->\n\n    true\n    false\n' | page
expect_fail 'page.md:3: `false` exits 1, the page says 0'

printf '<!-- doc-test: run exits=0,3 -->\n\n    true\n    exit 3\n' | page
/usr/bin/python3 "$CHECK" "$W/src" "$BUILD" docs/page.md > "$W/out.txt" 2>&1 || fail "exits=0,3 held, yet: $(cat "$W/out.txt")"

printf '<!-- doc-test: run -->\n\n    printf "one\\ntwo\\n"\n\n<!-- doc-test: output -->\n```\none\nthree\n...\n```\n' | page
expect_fail "page.md:6: output line 2: the page quotes"

printf '<!-- doc-test: run -->\n\n    printf "one\\ntwo\\nthree\\n"\n\n<!-- doc-test: output -->\n```\none\ntwo\n...\n```\n' | page
/usr/bin/python3 "$CHECK" "$W/src" "$BUILD" docs/page.md > "$W/out.txt" 2>&1 || fail "a quoted prefix held, yet: $(cat "$W/out.txt")"

printf '<!-- doc-test: synopsis -->\n\n    rcsim frobnicate FILE\n' | page
expect_fail 'rcsim frobnicate --help'

# The scratch clone: build/rcsim and rcsim alone are the build's; what a command writes stays there.
printf '<!-- doc-test: run -->\n\n    build/rcsim --help > /dev/null\n    rcsim --help > build/help.txt\n    test -s build/help.txt\n' | page
/usr/bin/python3 "$CHECK" "$W/src" "$BUILD" docs/page.md > "$W/out.txt" 2>&1 || fail "the scratch clone: $(cat "$W/out.txt")"
[ -e "$BUILD/help.txt" ] && fail "a command wrote into the real build folder"

[ "$failures" -eq 0 ] && echo "doc blocks self-test: ok"
[ "$failures" -eq 0 ]
