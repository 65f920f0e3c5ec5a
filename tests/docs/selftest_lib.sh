# The harness the docs checkers' self-tests share (sourced): a scratch folder $W, `expect` on the
# tree in $T, `setup`/`track` for the two modes a tree is read in ($mode: find, or git where only
# tracked files count) and `finish`. The sourcing script sets CHECK_COMMAND (an array: the
# checker's command line without the tree), TAG (the scratch folder's name) and defines
# clean_tree, which builds a clean tree in $T.
W=$(mktemp -d "${TMPDIR:-/tmp}/rcsim_${TAG:?}.XXXXXX")
trap 'rm -rf "$W"' EXIT
failures=0

# expect RC [SUBSTRING]: runs the checker on the tree in $T, checks its exit code and output.
expect() {
    local want_rc=$1 want=${2:-}
    "${CHECK_COMMAND[@]}" "$T" > "$W/out.txt" 2>&1
    local rc=$?
    if [ "$rc" -ne "$want_rc" ]; then
        echo "FAIL ($case_name): exit $rc, want $want_rc"; sed 's/^/    /' "$W/out.txt"; failures=$((failures + 1))
    elif [ -n "$want" ] && ! grep -qF -- "$want" "$W/out.txt"; then
        echo "FAIL ($case_name): output lacks '$want'"; sed 's/^/    /' "$W/out.txt"; failures=$((failures + 1))
    fi
}

# setup: a clean tree, put under git in git mode; track: what a case added, tracked in git mode.
setup() {
    clean_tree
    if [ "$mode" = git ]; then (cd "$T" && git init -q . && git add -A); fi
}
track() { if [ "$mode" = git ]; then (cd "$T" && git add -A); fi; }

finish() {
    if [ "$failures" -ne 0 ]; then echo "$failures case(s) failed"; exit 1; fi
    echo "all cases passed"
}
