#!/usr/bin/env bash
# gdb as one command (issue #51 item 4; docs/tools.md "gdb"): `rcsim run --gdb` writes DIR/rcsim.gdb
# and prints `gdb -x DIR/rcsim.gdb`; Debian's gdb with that file and nothing else set up breaks
# on a C function, shows main in bt, and prints and watches the firmware's C globals by name
# (symbols.elf's DWARF types, from the C declarations); `kill` ends the run, `detach` leaves it
# running to its end.
#
# Expected values, from the firmware's sources (comm_cpu/firmware/main.c, fw.h): main() calls
# main_loop(), which calls to_dpram(), which calls mb_post(); tick_div = TICK_DIV = 9216;
# area = {0 * AREA, 1 * AREA, 2 * AREA} with AREA = 340; port_lcr = LCR_8E1 (0x1b) three times;
# rx_len is `unsigned rx_len[NO_PORT]` (bcc's int: 2 bytes, NO_PORT = 3); txq_len is
# `unsigned txq_len[NO_PORT][TXQ]` (TXQ = 8); rxbuf is `unsigned char *rxbuf[NO_PORT]` = BUF_BASE
# (0xC00) + 0, BUF_SIZE (0x5000), 2 * BUF_SIZE. Port 0's host sends a frame from 20 ms: rx_len[0]
# goes from 0 to 1 when the RS-232 ISR stores its SOH (the firmware's only other write to it
# stores 0 again after the frame).
#
# usage: gdb_command_file.sh RCSIM GDB SCENARIO WORKDIR     (exit 77: skipped)
set -euo pipefail
rcsim=$1 gdb=$2 scenario=$3 work=$4
if ! command -v "$gdb" >/dev/null 2>&1; then
  echo "SKIP: gdb not found ($gdb); scripts/install-deps.sh installs it"
  exit 77
fi
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*"; echo "--- gdb output"; cat "$work/gdb.log" 2>/dev/null || true;
         echo "--- rcsim stdout"; cat "$work/run.out" 2>/dev/null || true;
         echo "--- rcsim stderr"; cat "$work/run.err" 2>/dev/null || true; exit 1; }

# Starts rcsim run --gdb (DIR $1) in the background; sets pid and cmdfile, the file rcsim prints.
start() {
  : > "$work/run.out"
  "$rcsim" run "$scenario" --out "$work/$1" --gdb 127.0.0.1:0 --gdb-wait > "$work/run.out" 2> "$work/run.err" &
  pid=$!
  cmdfile=
  for _ in $(seq 400); do
    cmdfile=$(sed -n 's/^gdb: to debug: gdb -x \(.*\)$/\1/p' "$work/run.out")
    [ -n "$cmdfile" ] && return 0
    kill -0 $pid 2>/dev/null || fail "rcsim ended before printing the gdb command"
    sleep 0.05
  done
  fail "rcsim printed no 'gdb: to debug: gdb -x FILE'"
}
# Waits up to $1 s for rcsim to end; sets code.
ended_within() {
  for _ in $(seq $(($1 * 20))); do
    kill -0 $pid 2>/dev/null || { code=0; wait $pid || code=$?; return 0; }
    sleep 0.05
  done
  return 1
}
trap 'kill $pid 2>/dev/null || true' EXIT

# 1. The session, then kill.
start k
[ "$cmdfile" = "$work/k/rcsim.gdb" ] || fail "the command file is $cmdfile, not beside symbols.elf"
cat > "$work/k.gdb" <<'GDB'
set pagination off
set confirm off
set width 0
watch rx_len[0]
continue
echo WATCHED\n
print rx_len[0]
delete
break mb_post
continue
echo BT\n
bt
echo VALUES\n
print tick_div
print area
print/x port_lcr
print/x rxbuf
print sizeof(rx_len)
print sizeof(txq_len)
ptype txq_len
kill
GDB
timeout 60 "$gdb" -nx -batch -x "$cmdfile" -x "$work/k.gdb" > "$work/gdb.log" 2>&1 || fail "gdb failed"
sed -n '/^BT$/,/^VALUES$/p' "$work/gdb.log" | grep -Eq '^#0 +0x[0-9a-f]+ in mb_post \(\)' || fail "not stopped in mb_post"
sed -n '/^BT$/,/^VALUES$/p' "$work/gdb.log" | grep -Eq '^#[1-9] +0x[0-9a-f]+ in main \(\)$' || fail "bt does not show main"
grep -q '^\$[0-9]* = 9216$' "$work/gdb.log" || fail "print tick_div: want 9216 (TICK_DIV)"
grep -q '^\$[0-9]* = {0, 340, 680}$' "$work/gdb.log" || fail "print area: want {0, 340, 680}"
grep -q '^\$[0-9]* = {0x1b, 0x1b, 0x1b}$' "$work/gdb.log" || fail "print/x port_lcr: want LCR_8E1 three times"
grep -q '^\$[0-9]* = {0xc00, 0x5c00, 0xac00}$' "$work/gdb.log" || fail "print/x rxbuf: want the three DS offsets"
grep -q '^\$[0-9]* = 6$' "$work/gdb.log" || fail "sizeof(rx_len): want 6 (3 16-bit ints)"
grep -q '^\$[0-9]* = 48$' "$work/gdb.log" || fail "sizeof(txq_len): want 48 (3 x 8 16-bit ints)"
grep -q '^type = unsigned int \[3\]\[8\]$' "$work/gdb.log" || fail "ptype txq_len"
grep -q '^Hardware watchpoint [0-9]*: rx_len\[0\]$' "$work/gdb.log" || fail "watch rx_len[0] by name"
sed -n '/^Hardware watchpoint [0-9]*: rx_len\[0\]$/,/^WATCHED$/p' "$work/gdb.log" | grep -q '^Old value = 0$' &&
  sed -n '/^Hardware watchpoint [0-9]*: rx_len\[0\]$/,/^WATCHED$/p' "$work/gdb.log" | grep -q '^New value = 1$' ||
  fail "the watchpoint did not see rx_len[0] go to 1"
! grep -q "^warning\|Python Exception\|No symbol\|unknown type" "$work/gdb.log" || fail "gdb complained"
ended_within 10 || fail "gdb's kill did not end the run"
[ "$code" = 143 ] || fail "after kill rcsim exited $code, not 143 (as on SIGTERM)"
grep -q '"interrupted": true' "$work/k/report.json" || fail "report.json does not say interrupted"
grep -q "^gdb: the debugger killed the target: the run ends" "$work/run.err" || fail "no line for the kill"

# 2. detach: the run goes on to its end, exit 0.
start d
cat > "$work/d.gdb" <<'GDB'
break main
continue
print tick_div
detach
GDB
timeout 60 "$gdb" -nx -batch -x "$cmdfile" -x "$work/d.gdb" > "$work/gdb.log" 2>&1 || fail "gdb failed (detach)"
grep -q '^\$1 = 9216$' "$work/gdb.log" || fail "print tick_div in main (detach)"
ended_within 30 || fail "the run did not end after detach"
[ "$code" = 0 ] || fail "after detach rcsim exited $code, not 0"
! grep -q '"interrupted": true' "$work/d/report.json" || fail "a detached run says interrupted"
trap - EXIT
echo "gdb -x DIR/rcsim.gdb: break, bt to main, C globals printed and watched by name; kill ends the run, detach does not"
