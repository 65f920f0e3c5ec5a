#!/usr/bin/env bash
# The shipped ROM as a firmware team has it (docs/tools.md "ROM images"): a raw 64 KB image, Intel
# HEX with segment (02) records as Debian's objcopy writes it, Intel HEX with linear (04) records
# written here from the specification's layout, and an even/odd EPROM pair; each run gives the same
# report, but for the ROM's name and format; so do srec_cat's S19, S28 and S37. A 32 KB image runs mirrored and says so; the scenario's
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
# A UTF-8 byte order mark, as an editor writes it, before the records (issue #48: "a raw image of
# the wrong size"): skipped, the same ROM.
{ printf '\xEF\xBB\xBF'; cat segment.hex; } > bom.hex
run bom --rom bom.hex || fail "bom.hex: exit $?"
same_as_raw bom
format_is bom "Intel HEX, 65536 bytes"
run linear --rom linear.hex || fail "linear.hex: exit $?"
same_as_raw linear
# Motorola S-records as Debian's srec_cat writes them (issue #51 item 5; its default format was
# refused as a raw image of the wrong size): S19 with the EPROM's offsets 0000..FFFF, S28 and S37
# with the CPU's F0000..FFFFF; srec_cat's S0 header and S5 record count come with each.
srec_cat raw.rom -binary -o fw.s19 -motorola -address-length=2 || fail "srec_cat S19"
srec_cat raw.rom -binary -offset 0xF0000 -o fw.s28 -motorola -address-length=3 || fail "srec_cat S28"
srec_cat raw.rom -binary -offset 0xF0000 -o fw.s37 -motorola -address-length=4 -execution-start-address=0xFFFF0 || fail "srec_cat S37"
for f in s19:S1 s28:S2 s37:S3; do
    grep -q "^${f#*:}" "fw.${f%:*}" && grep -q '^S0' "fw.${f%:*}" && grep -q '^S5' "fw.${f%:*}" || fail "srec_cat wrote no ${f#*:} records with S0 and S5 in fw.${f%:*}"
    run "${f%:*}" --rom "fw.${f%:*}" || fail "fw.${f%:*}: exit $?"
    same_as_raw "${f%:*}"
    format_is "${f%:*}" "Motorola S-records, 65536 bytes"
    symbols_are "${f%:*}" "built firmware" "$(basename "$MAP")"
done
grep -q '^S7' fw.s37 || fail "srec_cat wrote no S7 (start address) record"
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

# S-records with the errors of Intel HEX, naming the line (the second record of each file here).
sed '2s/..$/00/' fw.s19 > badsum.s19
grep -q '^S1.*00$' badsum.s19 && ! cmp -s fw.s19 badsum.s19 || fail "sed did not break line 2's checksum"
bad "an S-record with a bad checksum" "badsum.s19:2: bad checksum 00, the record's bytes give" --rom badsum.s19
{ sed -n 1,2p fw.s37; sed -n 2p fw.s37; } > overlap.s37
bad "overlapping S-records" "overlap.s37:3: address F0000 again: line 2 wrote it (overlapping records)" --rom overlap.s37
# Issue #48: a NUL in a HEX file is named where it is; EPROMs of two sizes are not a pair.
{ head -n 2 segment.hex; printf ':00000001\0FF\n'; } > nul.hex
bad "a NUL in Intel HEX" "nul.hex:3: byte 00 (NUL) at column 10: Intel HEX is text" --rom nul.hex
head -c 16384 odd.bin > odd16.bin
bad "a 32/16 KB pair" "even/odd EPROM pair of different sizes: even.bin (even) is 32 KB, odd16.bin (odd) is 16 KB" --rom even.bin --rom-odd odd16.bin

[ "$failures" -eq 0 ] && echo "rom formats: raw, Intel HEX (02 and 04), S19/S28/S37, even/odd pair give one report"
[ "$failures" -eq 0 ]
