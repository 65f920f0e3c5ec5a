#!/usr/bin/env bash
# Debian's gdb against `rcsim run --gdb` in batch mode (docs/tools.md "gdb"), with no `set
# architecture` or `set osabi`: the stub's target description and symbols.elf make gdb use i8086
# by themselves (x/i shows 16-bit `push %cx`, no warning). Break at the RS-232
# ISR by name, check registers and a RAM variable, stepi, a watchpoint on a firmware variable,
# continue to the end; the run's report.json and interrupts.csv must be byte-identical to a run
# without gdb (breakpoints and stops do not alter simulated timing).
#
# usage: gdb_session.sh RCSIM GDB SCENARIO FW_JSON WORKDIR     (exit 77: skipped)
#
# The expected values come from the firmware, not from the stub: the address of rs232_isr and
# tick_div from comm_fw.json (comm_fw_mkrom's reading of the ld86 map), CS = F000 (the code
# segment the ROM is linked for), tick_div = TICK_DIV = 9216 = 0x2400 (fw.h), and rs232_isr's
# first instruction `push cx` (isr.s; opcode 51, one byte: IP + 1, SP - 2). In rs232_isr, called
# from port 0's handler (the only port with a host), the 8259A has IR0 in service (ISR 01) and
# IMR = PIC_OCW1 = F0, vector base PIC_ICW2 = 20, edge triggered, normal EOI (PIC_ICW1 LTIM = 0,
# PIC_ICW4 AEOI = 0; fw.h); the 82510 #0 runs 9600,8E1 with LCR = 1B (8 bits, even parity, 1
# stop: the firmware's set-up).
set -euo pipefail
. "$(dirname "$0")/gdb_port.sh"
rcsim=$1 gdb=$2 scenario=$3 fw_json=$4 work=$5
if ! command -v "$gdb" >/dev/null 2>&1; then
  echo "SKIP: gdb not found ($gdb); scripts/install-deps.sh installs it"
  exit 77
fi
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*"; echo "--- gdb output"; cat "$work/gdb.log" 2>/dev/null || true;
         echo "--- rcsim stdout"; cat "$work/dbg.out" 2>/dev/null || true;
         echo "--- rcsim stderr"; cat "$work/dbg.err" 2>/dev/null || true; exit 1; }

read -r isr tick cs < <(python3 -c '
import json, sys
j = json.load(open(sys.argv[1]))
s = j["symbols"]
print("%x %x %x" % (s["rs232_isr"]["linear"], s["tick_div"]["linear"], j["code_segment"]))' "$fw_json")

"$rcsim" run "$scenario" --out "$work/ref" --reproducible > "$work/ref.out" || fail "the run without gdb failed"

# The background job opens its redirections after the fork: made here first, so that the polling
# below never reads a file the child has not created yet.
: > "$work/dbg.out"
"$rcsim" run "$scenario" --out "$work/dbg" --reproducible --gdb 127.0.0.1:0 --gdb-wait \
  > "$work/dbg.out" 2> "$work/dbg.err" &
pid=$!
trap 'kill $pid 2>/dev/null || true' EXIT
port=$(gdb_port "$work/dbg.out" $pid) || fail "rcsim ended before printing its gdb port"

cat > "$work/script.gdb" <<GDB
set pagination off
set confirm off
set width 0
file $work/dbg/symbols.elf
target remote 127.0.0.1:$port
break rs232_isr
continue
printf "AT-ISR pc=%x cs=%x sp=%x\n", (unsigned) \$pc, (unsigned) \$cs, (unsigned) \$sp
x/i \$pc
printf "TICK-DIV %x\n", *(unsigned short *) &tick_div
monitor irq
monitor pic
monitor uart 0
monitor time
stepi
printf "AFTER-STEPI pc=%x sp=%x\n", (unsigned) \$pc, (unsigned) \$sp
delete
watch *(unsigned short *) &rx_len
continue
printf "WATCH pc=%x\n", (unsigned) \$pc
delete
monitor cycles
continue
GDB
timeout 60 "$gdb" -nx -batch -x "$work/script.gdb" > "$work/gdb.log" 2>&1 || fail "gdb failed"
wait $pid || fail "rcsim exited $? with gdb attached"
trap - EXIT

grep -q "^AT-ISR pc=$isr cs=$cs " "$work/gdb.log" || fail "not stopped at rs232_isr ($isr) with CS $cs"
sp=$(sed -n 's/^AT-ISR .* sp=\([0-9a-f]*\)$/\1/p' "$work/gdb.log")
grep -Eq "^=> 0x$isr <rs232_isr>:[[:space:]]+push +%cx$" "$work/gdb.log" || fail "x/i \$pc is not 16-bit push cx"
grep -q "^8259A IRR [0-9A-F]* ISR 01 IMR F0" "$work/gdb.log" || fail "monitor irq: want ISR 01, IMR F0"
grep -q "^8259A: [a-z ]*, vector base 20, edge triggered$" "$work/gdb.log" || fail "monitor pic: mode"
grep -q "^82510 #0 (I/O 0080): bank [0-3], 9600,8E1," "$work/gdb.log" || fail "monitor uart 0: format"
grep -q "^bank 0: RXD=[0-9A-F]* GER=[0-9A-F]* GIR=[0-9A-F]* LCR=1B " "$work/gdb.log" || fail "monitor uart 0: LCR"
grep -Eq "^simulated time [0-9]+\.[0-9]{3} us \(kernel [0-9.]+ us\)$" "$work/gdb.log" || fail "monitor time"
grep -q "^TICK-DIV 2400$" "$work/gdb.log" || fail "tick_div is not TICK_DIV (0x2400)"
want_pc=$(printf '%x' $((0x$isr + 1))) want_sp=$(printf '%x' $((0x$sp - 2)))
grep -q "^AFTER-STEPI pc=$want_pc sp=$want_sp$" "$work/gdb.log" || fail "stepi over push cx: want pc=$want_pc sp=$want_sp"
grep -q "Hardware watchpoint 2: \*(unsigned short \*) &rx_len" "$work/gdb.log" || fail "no hardware watchpoint"
grep -q "^New value = " "$work/gdb.log" || fail "the watchpoint did not trigger"
wpc=$(sed -n 's/^WATCH pc=\([0-9a-f]*\)$/\1/p' "$work/gdb.log")
[ -n "$wpc" ] && [ $((0x$wpc)) -ge $((0xF0000)) ] || fail "watchpoint stop outside the ROM (pc=$wpc)"
grep -q "^cycles [0-9]*, instructions [0-9]*" "$work/gdb.log" || fail "monitor cycles"
grep -q "exited normally" "$work/gdb.log" || fail "gdb did not see the run end"
! grep -q "^warning" "$work/gdb.log" || fail "gdb warned"
cmp "$work/ref/report.json" "$work/dbg/report.json" || fail "report.json differs with gdb attached"
cmp "$work/ref/interrupts.csv" "$work/dbg/interrupts.csv" || fail "interrupts.csv differs with gdb attached"
echo "gdb session: breakpoint, registers, RAM, stepi, watchpoint, end of run; report unchanged"
