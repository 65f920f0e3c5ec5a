#!/bin/sh
# The shortened anchor program of docs/performance.md ("8086 core against libx86emu"), built by
# the commands the doc shows, runs on the core and on libx86emu with the same result (the bench
# fails when they differ): 2000 frames of 128 instructions (protocol_loop.asm's own count),
# 0.26 M; and the sed pattern still matches the FRAMES line (else the doc's count would silently
# be the 7 M one).
#   anchor_short.sh RCSIM NASM SRCDIR WORKDIR
set -eu
RCSIM=$1 NASM=$2 SRC=$3 WORK=$4
mkdir -p "$WORK"
cd "$SRC"
sed 's/^FRAMES  equ     54688/FRAMES  equ     2000/' comm_cpu/tools/protocol_loop.asm > "$WORK/loop2000.asm"
grep -q '^FRAMES  equ     2000$' "$WORK/loop2000.asm" || { echo "FAIL: the sed pattern no longer matches the FRAMES line"; exit 1; }
"$NASM" -f bin -o "$WORK/loop2000.bin" "$WORK/loop2000.asm"
out=$("$RCSIM" bench cpu --anchor --rounds 1 --seconds 0.1 --image "$WORK/loop2000.bin")
echo "$out"
echo "$out" | grep -q '0\.26 M instructions' || { echo "FAIL: expected 0.26 M instructions (256 010)"; exit 1; }
echo "$out" | grep -q '^ratio' || { echo "FAIL: no ratio printed"; exit 1; }
