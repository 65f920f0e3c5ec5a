#!/usr/bin/env bash
# Bad input to `rcsim run --gdb` (docs/tools.md "gdb"): each gets one line naming the value or
# FILE:LINE and exit code 2 (docs/scenarios.md, exit codes), before anything runs. And the good
# case: a --symbols file of your own becomes OUT/symbols.elf, and a run nobody connects to runs
# to its end, its report.json that of the run without --gdb.
# usage: gdb_cli.sh RCSIM SCENARIO WORKDIR
set -u
rcsim=$1 scenario=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
failed=0
expect() { # expect "MESSAGE PART" ARGS...
  local want=$1; shift
  "$rcsim" run "$scenario" "$@" > "$work/out" 2> "$work/err"
  local rc=$?
  if [ $rc -ne 2 ] || ! grep -qF -- "$want" "$work/err"; then
    echo "FAIL: rcsim run $* -> exit $rc, stderr:"; cat "$work/err"; echo "(wanted exit 2 and: $want)"
    failed=1
  fi
}
printf 'ok 0xF0000\nx F0000\n' > "$work/bad.sym"
expect "$work/bad.sym:2: bad address 'F0000'" --gdb 0 --symbols "$work/bad.sym"
expect "$work/none.sym: cannot open the symbol file" --gdb 0 --symbols "$work/none.sym"
# A linker's Publics map (docs/tools.md "Symbols"): a bad row, a bad load segment, a load
# segment for NAME ADDRESS lines.
printf '  Address         Publics by Value\n\n 0000:0010       _main\n 0000:00G0       _bad\n' > "$work/bad.map"
expect "$work/bad.map:4: bad address '0000:00G0'" --gdb 0 --symbols "$work/bad.map@F000"
expect "$work/bad.map@F00X: bad load segment 'F00X'" --gdb 0 --symbols "$work/bad.map@F00X"
expect "$work/bad.sym@F000: a load segment (@SEG) places a map" --gdb 0 --symbols "$work/bad.sym@F000"
expect "--gdb-wait needs --gdb" --gdb-wait
# --symbols alone is read too (for the latency causes): the same message, before the run.
expect "--symbols: $work/bad.sym:2: bad address 'F0000'" --symbols "$work/bad.sym"
expect "--gdb and --profile cannot be used together" --gdb 0 --profile --out "$work/o"
expect "--gdb '127.0.0.1:99999': port 99999 out of range" --gdb 127.0.0.1:99999
expect "--gdb 'foo:12': bad address 'foo'" --gdb foo:12
# A port another program listens on.
exec 3< <(python3 -c 'import socket, sys, time
s = socket.socket(); s.bind(("127.0.0.1", 0)); s.listen(1)
print(s.getsockname()[1], flush=True); time.sleep(30)')
sleeper=$!
read -r busy <&3
expect "--gdb 127.0.0.1:$busy: cannot listen" --gdb "127.0.0.1:$busy"
kill "$sleeper" 2>/dev/null

printf '# my ROM\nmy_entry F000:0000 16\nmy_counter 0x400 2\n' > "$work/good.sym"
if ! "$rcsim" run "$scenario" --gdb 127.0.0.1:0 --symbols "$work/good.sym" --out "$work/o" > "$work/out" 2> "$work/err"; then
  echo "FAIL: a run with --gdb and nobody connecting did not pass:"; cat "$work/err"; failed=1
elif ! grep -q "^gdb: to debug: gdb -x $work/o/rcsim.gdb$" "$work/out" || ! grep -aq my_counter "$work/o/symbols.elf"; then
  echo "FAIL: --symbols did not become $work/o/symbols.elf"; cat "$work/out"; failed=1
elif ! grep -q "^file $work/o/symbols.elf$" "$work/o/rcsim.gdb"; then
  echo "FAIL: $work/o/rcsim.gdb does not load $work/o/symbols.elf"; cat "$work/o/rcsim.gdb"; failed=1
fi
# An .EXE's map at its load segment: gdb gets C's names without the underscore.
printf ' Start  Stop   Length Name    Class\n 00000H 000FFH 00100H _TEXT   CODE\n\n  Address         Publics by Value\n\n 0000:0010       _my_main\n' > "$work/exe.map"
if ! "$rcsim" run "$scenario" --gdb 127.0.0.1:0 --symbols "$work/exe.map@F000" --out "$work/p" > "$work/out" 2> "$work/err"; then
  echo "FAIL: a run with --symbols FILE@F000 did not pass:"; cat "$work/err"; failed=1
elif ! grep -aq my_main "$work/p/symbols.elf" || grep -aq _my_main "$work/p/symbols.elf"; then
  echo "FAIL: $work/p/symbols.elf does not name my_main (without its underscore)"; failed=1
fi
# The stub attached, nobody connecting: the same run, byte for byte.
"$rcsim" run "$scenario" --reproducible --out "$work/ref" > /dev/null 2>&1
"$rcsim" run "$scenario" --reproducible --gdb 127.0.0.1:0 --out "$work/idle" > /dev/null 2>&1
if ! cmp -s "$work/ref/report.json" "$work/idle/report.json"; then
  echo "FAIL: report.json of a run with an idle --gdb differs from the run without it"; failed=1
fi
[ $failed -eq 0 ] && echo "bad --gdb input: exit 2 with the value named"
exit $failed
