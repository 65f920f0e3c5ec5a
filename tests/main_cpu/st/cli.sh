#!/usr/bin/env bash
# ST programs through the rcsim executable (tests/main_cpu/st/cases): the st_program_error_free check fails
# for a runtime error and for a program never started; a syntax error and a missing file are bad
# input (exit 2) with one message naming the file, line and column, in a motion scenario and in
# the whole board (main_cpu.program).
# Usage: cli.sh RCSIM CASES_DIR
set -u
rcsim=$1 cases=$2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail=0
expect() { # name, wanted exit code, wanted text on stdout+stderr, command...
    local name=$1 code=$2 text=$3
    shift 3
    local got rc
    got=$("$@" 2>&1)
    rc=$?
    if [ "$rc" != "$code" ]; then echo "FAIL $name: exit $rc, wanted $code"; echo "$got" | tail -5; fail=1; return; fi
    if ! grep -qF -- "$text" <<<"$got"; then echo "FAIL $name: no '$text' in:"; echo "$got" | tail -8; fail=1; return; fi
    echo "ok   $name"
}
expect crash 1 "FAIL  st_program_error_free" "$rcsim" run "$cases/crash.yaml" --out "$out/a"
expect crash_message 1 "crash.st:6:12: division by zero" "$rcsim" run "$cases/crash.yaml" --out "$out/b"
expect crash_errorstop 1 "PASS  final_state" "$rcsim" run "$cases/crash.yaml" --out "$out/c"
expect never_run 1 "the program never ran (no RN token?)" "$rcsim" run "$cases/never_run.yaml" --out "$out/d"
expect syntax 2 "syntax.st:4:1: expected ';', found 'END_PROGRAM'" "$rcsim" run "$cases/syntax.yaml" --out "$out/e"
expect missing 2 "missing.yaml:3: cannot read the Structured Text program" "$rcsim" run "$cases/missing.yaml" --out "$out/f"
# main_cpu.program in the whole board: the same two messages, exit 2.
expect serial_syntax 2 "syntax.st:4:1: expected ';', found 'END_PROGRAM'" "$rcsim" run "$cases/serial_syntax.yaml" --out "$out/g"
expect serial_missing 2 "serial_missing.yaml:4: cannot read the Structured Text program" "$rcsim" run "$cases/serial_missing.yaml" --out "$out/h"
exit $fail
