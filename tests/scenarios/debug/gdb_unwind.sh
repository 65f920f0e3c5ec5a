#!/usr/bin/env bash
# gdb's bt, up and finish through the 8086's frames (docs/tools.md "gdb"): Debian's gdb with the
# rcsim-gdb.py unwinder rcsim writes beside symbols.elf, and no `set` command.
#
# Expected frames, from the firmware's source: main() calls main_loop() (comm_cpu/firmware/main.c),
# main_loop() calls to_dpram(), to_dpram() calls mb_post() — C functions with bcc's BP frames. The
# RS-232 interrupt of port 0 (the only port with a host) enters at _isr_port0, which calls
# _rs232_isr (isr.s, an assembly routine without a BP frame), and whatever it interrupted runs
# under main(). The watchpoint is on pflag[0] of the DP-RAM (left port D0000 + 0*340 + 339,
# docs/system.md §4), which the comm CPU sets to EXT_USE (1) when the host's ENQ arrives.
#
# usage: gdb_unwind.sh RCSIM GDB SCENARIO FW_JSON WORKDIR     (exit 77: skipped)
set -euo pipefail
. "$(dirname "$0")/gdb_port.sh"
rcsim=$1 gdb=$2 scenario=$3 fw_json=$4 work=$5
if ! command -v "$gdb" >/dev/null 2>&1; then
  echo "SKIP: gdb not found ($gdb); scripts/install-deps.sh installs it"
  exit 77
fi
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*"; echo "--- gdb output"; cat "$work/gdb.log" 2>/dev/null || true;
         echo "--- rcsim stdout"; cat "$work/dbg.out" 2>/dev/null || true; exit 1; }

: > "$work/dbg.out"
"$rcsim" run "$scenario" --out "$work/dbg" --gdb 127.0.0.1:0 --gdb-wait > "$work/dbg.out" 2> "$work/dbg.err" &
pid=$!
trap 'kill $pid 2>/dev/null || true' EXIT
port=$(gdb_port "$work/dbg.out" $pid) || fail "rcsim ended before printing its gdb port"
grep -q "^source $work/dbg/rcsim-gdb.py$" "$work/dbg/rcsim.gdb" ||
  fail "the gdb command file rcsim writes does not load the unwinder"

cat > "$work/script.gdb" <<GDB
set pagination off
set confirm off
set width 0
file $work/dbg/symbols.elf
source $work/dbg/rcsim-gdb.py
target remote 127.0.0.1:$port
break mb_post
continue
echo BT-C\n
bt
finish
echo AFTER-FINISH\n
info symbol \$pc
up
echo UP-DONE\n
delete
break rs232_isr
continue
echo BT-ISR\n
bt
delete
watch *(unsigned char *) 0xD0153
continue
echo WATCH-DONE\n
kill
GDB
timeout 60 "$gdb" -nx -batch -x "$work/script.gdb" > "$work/gdb.log" 2>&1 || fail "gdb failed"

section() { sed -n "/^$1\$/,/^[A-Z-]*-[A-Z]*\$/p" "$work/gdb.log"; }
c_bt=$(section BT-C)
echo "$c_bt" | grep -Eq '^#0 +0x[0-9a-f]+ in mb_post \(\)' || fail "bt: #0 is not mb_post"
echo "$c_bt" | grep -Eq '^#1 +0x[0-9a-f]+ in to_dpram \(\)' || fail "bt: #1 is not to_dpram"
echo "$c_bt" | grep -Eq '^#2 +0x[0-9a-f]+ in main_loop \(\)' || fail "bt: #2 is not main_loop"
echo "$c_bt" | grep -Eq '^#3 +0x[0-9a-f]+ in main \(\)' || fail "bt: #3 is not main"
echo "$c_bt" | grep -q '0x00000000 in ??' && fail "bt shows a frame at 0"
sed -n '/^AFTER-FINISH$/,/^UP-DONE$/p' "$work/gdb.log" | grep -q "^to_dpram + [0-9]* in section .text" ||
  fail "finish did not stop in to_dpram"
sed -n '/^AFTER-FINISH$/,/^UP-DONE$/p' "$work/gdb.log" | grep -Eq '^#1 +0x[0-9a-f]+ in main_loop \(\)' ||
  fail "up from to_dpram is not main_loop"
isr_bt=$(section BT-ISR)
echo "$isr_bt" | grep -Eq '^#0 +0x[0-9a-f]+ in rs232_isr \(\)' || fail "bt in the ISR: #0 is not rs232_isr"
echo "$isr_bt" | grep -Eq '^#1 +0x[0-9a-f]+ in isr_port0 \(\)' || fail "bt in the ISR: #1 is not isr_port0"
echo "$isr_bt" | grep -Eq '^#[2-9] +0x[0-9a-f]+ in main \(\)$' || fail "bt in the ISR does not reach main"
echo "$isr_bt" | grep -q "Backtrace stopped" && fail "bt in the ISR stopped early"
grep -q "^Hardware watchpoint [0-9]*: \*(unsigned char \*) 0xD0153" "$work/gdb.log" || fail "no watchpoint on pflag[0]"
sed -n '/^Hardware watchpoint [0-9]*: \*(unsigned char \*) 0xD0153$/,/^WATCH-DONE$/p' "$work/gdb.log" |
  grep -q "^New value = 1 " || fail "the watchpoint on pflag[0] did not see EXT_USE (1)"
! grep -q "^warning\|Python Exception" "$work/gdb.log" || fail "gdb warned"
kill $pid 2>/dev/null || true
wait $pid 2>/dev/null || true

# The same firmware with a locator's "Publics by Value" map (docs/tools.md "Symbols"), written here
# from the built firmware's symbols with C's leading underscores: gdb breaks on `mb_post` by its C
# name, shows 16-bit code, and bt reaches main_loop and main (to_dpram, a static function, has no
# public name: its frame shows as the public symbol before it, and is still unwound).
python3 - "$fw_json" "$work/fw.map" <<'PY'
import json, sys
syms = json.load(open(sys.argv[1]))["symbols"]
with open(sys.argv[2], "w") as m:
    m.write("Paradigm LOCATE  Version 5.00  Absolute locator map of COMM_FW.AXE\n\n")
    m.write(" Start  Stop   Length Name               Class\n")
    m.write(" 00000H 0FFFFH 10000H _DATA              DATA\n")
    m.write(" F0000H FFFFFH 10000H _TEXT              CODE\n\n")
    m.write("  Address         Publics by Value\n\n")
    for name, s in sorted(syms.items(), key=lambda kv: kv[1]["linear"]):
        seg = 0xF000 if s["linear"] >= 0xF0000 else 0
        m.write(" %04X:%04X       _%s\n" % (seg, s["linear"] - seg * 16, name))
PY
: > "$work/pub.out"
"$rcsim" run "$scenario" --out "$work/pub" --gdb 127.0.0.1:0 --gdb-wait --symbols "$work/fw.map" > "$work/pub.out" 2>&1 &
pid=$!
port=$(gdb_port "$work/pub.out" $pid) || { cat "$work/pub.out"; fail "rcsim ended before printing its gdb port (Publics map)"; }
cat > "$work/pub.gdb" <<GDB
set pagination off
set confirm off
file $work/pub/symbols.elf
source $work/pub/rcsim-gdb.py
target remote 127.0.0.1:$port
break mb_post
continue
x/i \$pc
bt
kill
GDB
timeout 60 "$gdb" -nx -batch -x "$work/pub.gdb" > "$work/gdb.log" 2>&1 || fail "gdb failed (Publics map)"
# gdb stops after bcc's prologue (push bp; mov bp,sp; push di; push si), at `dec %sp`: an i386
# reading would say %esp.
grep -Eq "^=> 0x[0-9a-f]+ <mb_post\+5>:[[:space:]]+dec +%sp$" "$work/gdb.log" || fail "Publics map: not 16-bit code at mb_post"
grep -Eq '^#0 +0x[0-9a-f]+ in mb_post \(\)' "$work/gdb.log" || fail "Publics map: #0 is not mb_post"
grep -Eq '^#[1-9] +0x[0-9a-f]+ in main_loop \(\)' "$work/gdb.log" || fail "Publics map: bt does not reach main_loop"
grep -Eq '^#[2-9] +0x[0-9a-f]+ in main \(\)$' "$work/gdb.log" || fail "Publics map: bt does not reach main"
! grep -q "^warning\|Python Exception" "$work/gdb.log" || fail "gdb warned (Publics map)"
echo "gdb unwind: bt, finish and up through C frames and the interrupt entry; a DP-RAM watchpoint; a Publics map"
