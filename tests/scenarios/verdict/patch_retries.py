#!/usr/bin/env python3
"""Writes a copy of the shipped firmware ROM with its retries patched out (MAX_RETRY 3 -> 0), for
the failing twin of cases/retries_owed.yaml (docs/scenarios.md "Expected drops").

usage: patch_retries.py ROM MAP JSON OUT

The patch site is isr.s's tx_retry_r, found from the build's own records, never a fixed offset
(the firmware changes): its address in the ld86 map (ROM offset: the code segment starts the
ROM), and the instructions there, checked byte for byte —
    inc byte ptr _tx_try[bx]             FE 87 lo hi
    cmp byte ptr _tx_try[bx],#MAX_RETRY  80 BF lo hi 03
with lo hi the offset of tx_try in the symbol table (JSON). The pair must also be the only one in
the ROM. The cmp's immediate becomes 0: the first NAK or T1 timeout gives the frame up."""
import json
import os
import re
import sys

MAX_RETRY = 3  # docs/system.md §6.2, comm_cpu/firmware/fw.h


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    rom_path, map_path, json_path, out_path = sys.argv[1:]
    rom = bytearray(open(rom_path, "rb").read())
    symbols = json.load(open(json_path))
    tx_try = symbols["symbols"]["tx_try"]["offset"]
    lo, hi = tx_try & 0xFF, tx_try >> 8
    code = bytes([0xFE, 0x87, lo, hi, 0x80, 0xBF, lo, hi, MAX_RETRY])
    found = [m.start() for m in re.finditer(re.escape(code), bytes(rom))]
    if len(found) != 1:
        sys.exit("patch_retries.py: %d places with inc/cmp _tx_try[bx],#%d, not one" % (len(found), MAX_RETRY))
    at = None
    with open(map_path) as f:
        for line in f:
            parts = line.split()
            if len(parts) >= 4 and parts[1] == "tx_retry_r":
                at = int(parts[3], 16)
    code_base = symbols["code_segment"] * 16 - symbols["rom_base"]
    if at is None or code_base + at != found[0]:
        sys.exit("patch_retries.py: tx_retry_r in the map (%r) is not where its instructions are (0x%x)" % (at, found[0]))
    rom[found[0] + len(code) - 1] = 0
    os.makedirs(os.path.dirname(os.path.abspath(out_path)), exist_ok=True)
    open(out_path, "wb").write(rom)
    print("patched MAX_RETRY %d -> 0 at ROM offset 0x%x (tx_retry_r + 8)" % (MAX_RETRY, found[0] + len(code) - 1))


if __name__ == "__main__":
    main()
