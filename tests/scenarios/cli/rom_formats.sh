#!/usr/bin/env bash
# The shipped ROM as a firmware team has it (docs/tools.md "ROM images"): a raw 64 KB image, Intel
# HEX with segment (02) records as Debian's objcopy writes it, Intel HEX with linear (04) records
# written here from the specification's layout, and an even/odd EPROM pair; each run gives the same
# report, but for the ROM's name and format. A 32 KB image runs mirrored and says so; the scenario's
# `rom: {even, odd}` is the pair; each is the built firmware by its bytes and gets its map; an ELF, text and a lone --rom-odd are bad input (exit 2).
#
# Usage: rom_formats.sh RCSIM ROM SCENARIO MAP (MAP: the built ROM's ld86 map)
set -u
RCSIM=$(realpath "${1:?usage}")
ROM=$(realpath "${2:?usage}")
SCENARIO=$(realpath "${3:?usage}")
MAP=$(realpath "${4:?usage}")
export SC_COPYRIGHT_MESSAGE=DISABLE
W=$(mktemp -d "${TMPDIR:-/tmp}/rcsim_rom_formats.XXXXXX")
trap 'rm -rf "$W"' EXIT
cd "$W" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# A copy: the same bytes are the built firmware in every format (scenarios/debug/rom_symbols.h),
# so every run here names its causes from the built firmware's map.
cp "$ROM" raw.rom
objcopy -I binary -O ihex --change-addresses 0xF0000 raw.rom segment.hex || fail "objcopy"
grep -q '^:02000002F0000C' segment.hex || fail "objcopy wrote no segment record F000"
/usr/bin/python3 - raw.rom linear.hex even.bin odd.bin <<'PY'
import sys
rom = open(sys.argv[1], "rb").read()
def record(kind, address, data):
    b = [len(data), address >> 8, address & 0xFF, kind] + list(data)
    return ":" + "".join("%02X" % x for x in b + [(-sum(b)) & 0xFF]) + "\n"
with open(sys.argv[2], "w") as f:
    f.write(record(0x04, 0, [0x00, 0x0F]))          # upper 16 bits of the address: 000F
    for at in range(0, len(rom), 32):
        f.write(record(0x00, at, rom[at:at + 32]))   # F0000 + at
    f.write(record(0x05, 0, [0x00, 0x0F, 0xFF, 0xF0]))  # a start address: ignored
    f.write(":00000001FF\n")
open(sys.argv[3], "wb").write(rom[0::2])
open(sys.argv[4], "wb").write(rom[1::2])
PY

run() { # NAME ARGS...: a reproducible run into NAME/
    local name=$1
    shift
    "$RCSIM" run "$SCENARIO" --out "$name" --reproducible "$@" > "$name.txt" 2>&1
}
same_as_raw() { # NAME: its report is the raw run's but for rom, rom_format and whose symbols
    /usr/bin/python3 - raw/report.json "$1/report.json" <<'PY' || fail "$1: the report differs from the raw image's"
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
for r in (a, b):
    r.pop("rom"), r.pop("rom_format"), r.pop("symbols")
assert a == b, [k for k in a if a[k] != b.get(k)]
PY
}
format_is() { # NAME TEXT
    local got
    got=$(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["rom_format"])' "$1/report.json")
    [ "$got" = "$2" ] || fail "$1: rom_format '$got', expected '$2'"
}

run raw --rom raw.rom || fail "raw image: exit $?"
format_is raw "raw 64 KB"
symbols_are() { # NAME ORIGIN FILE: report.json "symbols"
    /usr/bin/python3 - "$1/report.json" "$2" "$3" <<'PY' || fail "$1: symbols are not $2 $3"
import json, sys
s = json.load(open(sys.argv[1]))["symbols"]
assert s["origin"] == sys.argv[2] and s["file"] == sys.argv[3] and s["count"] > 0, s
PY
}
symbols_are raw "built firmware" "$(basename "$MAP")"
run segment --rom segment.hex || fail "segment.hex: exit $?"
same_as_raw segment
format_is segment "Intel HEX, 65536 bytes"
run linear --rom linear.hex || fail "linear.hex: exit $?"
same_as_raw linear
run pair --rom even.bin --rom-odd odd.bin || fail "the pair: exit $?"
same_as_raw pair
symbols_are pair "built firmware" "$(basename "$MAP")"
format_is pair "even/odd EPROM pair: even raw 32 KB, odd raw 32 KB"
grep -q '"rom": "even.bin + odd.bin"' pair/report.json || fail "the pair's report does not name both EPROMs"
# The scenario's rom: {even, odd}, relative to the scenario file.
{ echo "rom: {even: even.bin, odd: odd.bin}"; grep -v '^rom:' "$SCENARIO"; } > paired.yaml
"$RCSIM" run paired.yaml --out paired --reproducible > paired.txt 2>&1 || fail "rom: {even, odd}: exit $?"
format_is paired "even/odd EPROM pair: even raw 32 KB, odd raw 32 KB"
# One 27256 (32 KB): the firmware's code (it starts at F000:0000 and fills under 8 KB) with the
# reset stub (JMP FAR F000:0000, the ROM's last 16 bytes) as the chip's own last 16 bytes. Mirrored
# twice across the ROM window, it runs as the whole image does, and the run says it was mirrored.
/usr/bin/python3 -c '
import sys
rom = open("raw.rom", "rb").read()
assert all(b == 0xFF for b in rom[0x7FF0:0xFFF0]), "the firmware no longer fits in 32 KB"
open("27256.bin", "wb").write(rom[:0x7FF0] + rom[0xFFF0:])'
# Its 64 KB differ from the built ROM's (the mirror): the map is the user's to give.
run 27256 --rom 27256.bin --symbols "$MAP" || fail "a 32 KB image: exit $?"
symbols_are 27256 "--symbols" "$(basename "$MAP")"
same_as_raw 27256
format_is 27256 "raw 32 KB, mirrored 2x across 64 KB"
grep -q "ROM: 27256.bin (raw 32 KB, mirrored 2x across 64 KB)" 27256.txt || fail "the summary does not say the image is mirrored"

# Bad input: exit 2, naming the file and what it is.
bad() { # WHAT TEXT ARGS...
    local what=$1 text=$2
    shift 2
    "$RCSIM" run "$SCENARIO" --out bad "$@" > bad.txt 2>&1
    local rc=$?
    [ "$rc" -eq 2 ] || fail "$what: exit $rc, expected 2"
    grep -qF -- "$text" bad.txt || fail "$what: no '$text' in: $(cat bad.txt)"
}
bad "an ELF file" "an ELF file, not a ROM image: take the ROM's bytes out of it with \`objcopy -O binary" --rom "$RCSIM"
head -c 65536 /dev/zero | tr '\0' 'x' > text.rom
bad "text" "text.rom:1: text that is not Intel HEX" --rom text.rom
head -n 5 segment.hex > cut.hex
bad "a cut HEX file" "cut.hex:5: no end-of-file record" --rom cut.hex
bad "--rom-odd alone" "--rom-odd needs --rom" --rom-odd odd.bin
# A linear (04) record's addresses are 32-bit: one running past FFFFF leaves the ROM (issue #48:
# it wrapped to F0000). ULBA 000F, 4 bytes at FFFE: FFFFE, FFFFF, 100000, 100001.
printf ':02000004000FEB\n:04FFFE0001020304F5\n:00000001FF\n' > past_end.hex
bad "a linear record past FFFFF" "past_end.hex:2: address 100000 is outside the ROM (F0000..FFFFF)" --rom past_end.hex

[ "$failures" -eq 0 ] && echo "rom formats: raw, Intel HEX (02 and 04), even/odd pair give one report"
[ "$failures" -eq 0 ]
