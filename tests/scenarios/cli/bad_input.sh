#!/usr/bin/env bash
# Bad input through the rcsim executable: every case must end with the documented exit code and
# one message naming the file and line or the offending value — never a crash, an abort, a hang
# or a run that silently ignores what it was given (docs/scenarios.md "Exit codes").
#
# Usage: bad_input.sh RCSIM SOURCE_DIR
set -u
RCSIM=${1:?usage: bad_input.sh RCSIM SOURCE_DIR}
SRC=${2:?usage: bad_input.sh RCSIM SOURCE_DIR}
RCSIM=$(realpath "$RCSIM")
SRC=$(realpath "$SRC")
export SC_COPYRIGHT_MESSAGE=DISABLE
W=$(mktemp -d "${TMPDIR:-/tmp}/rcsim_bad_input.XXXXXX")
trap 'rm -rf "$W"' EXIT
cd "$W" || exit 1

failures=0
cases=0

# expect RC SUBSTRING -- ARGS...: runs rcsim ARGS, checks the exit code, that stderr holds
# SUBSTRING, that stderr is one line (no "Run with --help" hint: issue #48) and that nothing
# died of a signal or a sanitizer report.
expect() {
    local want_rc=$1 want_msg=$2
    shift 3
    cases=$((cases + 1))
    timeout 60 "$RCSIM" "$@" > out.txt 2> err.txt
    local rc=$?
    local lines
    lines=$(grep -cv -e '^$' err.txt)
    local why=""
    if [ "$rc" -ne "$want_rc" ]; then why="exit $rc, expected $want_rc"; fi
    if ! grep -qF -- "$want_msg" err.txt; then why="$why; stderr does not contain '$want_msg'"; fi
    if [ "$want_rc" -eq 2 ] && [ "$lines" -ne 1 ]; then why="$why; $lines lines on stderr, expected 1"; fi
    if grep -qE 'AddressSanitizer|runtime error:|terminate called|Aborted' err.txt; then why="$why; crash report"; fi
    if [ -n "$why" ]; then
        failures=$((failures + 1))
        echo "FAIL: rcsim $*: ${why#; }"
        sed 's/^/    stderr: /' err.txt | head -5
    fi
}

# A scenario file from its text (printf escapes).
scen() { printf "$2" > "$1"; }

# --- scenario files -------------------------------------------------------------------------
scen syntax.yaml 'name: x\nports: [ {host: protocol\n'
expect 2 "syntax.yaml:3: YAML syntax error" -- run syntax.yaml
scen wrongtype.yaml 'duration_s: abc\n'
expect 2 "wrongtype.yaml:1: bad value for 'duration_s': 'abc'" -- run wrongtype.yaml
scen neg.yaml 'duration_s: -1\n'
expect 2 "neg.yaml:1: 'duration_s' = -1 is out of range" -- run neg.yaml
scen nan.yaml 'duration_s: .nan\n'
expect 2 "nan.yaml:1: 'duration_s' = nan is out of range" -- run nan.yaml
scen huge.yaml 'duration_s: 1e300\n'
expect 2 "huge.yaml:1: 'duration_s' = 1e+300 is out of range" -- run huge.yaml
scen inf.yaml 'duration_s: .inf\n'
expect 2 "inf.yaml:1: 'duration_s' = inf is out of range" -- run inf.yaml
scen tiny.yaml 'duration_s: 1e-300\n'
expect 2 "tiny.yaml:1: 'duration_s' must be 0 or >= 1e-6" -- run tiny.yaml
scen dur0.yaml 'duration_s: 0\n'
expect 2 "dur0.yaml:1: 'duration_s: 0'" -- run dur0.yaml
scen empty.yaml ''
expect 2 "empty.yaml: the scenario file is empty" -- run empty.yaml
scen comments.yaml '# nothing but a comment\n'
expect 2 "comments.yaml: the scenario file is empty" -- run comments.yaml
mkdir -p dir.yaml
expect 2 "dir.yaml: is a directory" -- run dir.yaml
expect 2 "missing.yaml: cannot open scenario file" -- run missing.yaml
scen list.yaml '[1, 2]\n'
expect 2 "list.yaml:1: 'top level' must be a mapping" -- run list.yaml
scen mapkey.yaml '{[a]: 1}\n'
expect 2 "mapkey.yaml:1: a key in 'top level' must be a plain name" -- run mapkey.yaml
scen seedneg.yaml 'seed: -1\n'
expect 2 "seedneg.yaml:1: bad value for 'seed': '-1'" -- run seedneg.yaml
scen boardint.yaml 'board: 5\n'
expect 2 "boardint.yaml:1: 'board' must be a mapping" -- run boardint.yaml
scen cpuhz.yaml 'board: {cpu_hz: 1e300}\n'
expect 2 "cpuhz.yaml:1: 'board.cpu_hz' = 1e+300 must be a whole number in [100000, 100000000]" -- run cpuhz.yaml
scen grade.yaml 'board: {dpram_speed_grade_ns: 30}\n'
expect 2 "grade.yaml:1: 'board.dpram_speed_grade_ns' must be" -- run grade.yaml
scen quantum.yaml 'board: {quantum_us: 0}\n'
expect 2 "quantum.yaml:1: 'board.quantum_us' = 0 must be at least one CPU clock" -- run quantum.yaml
# One CPU clock at 8 MHz is 0.125 us; 1 ps used to end in a two-line SystemC error.
scen quantum_ps.yaml 'board: {quantum_us: 0.000001}\n'
expect 2 "quantum_ps.yaml:1: 'board.quantum_us' = 1e-06 must be at least one CPU clock (0.125 us" -- run quantum_ps.yaml
scen cycle.yaml 'main_cpu: {cycle_time_us: 5000, cycle_period_us: 1000}\n'
expect 2 "cycle.yaml:1: main_cpu: cycle_time" -- run cycle.yaml

# --- strict YAML: duplicate keys, one document, whole numbers, escaped echoes ------------------
scen dup_top.yaml 'duration_s: 0.001\nseed: 1\nduration_s: 2\n'
expect 2 "dup_top.yaml:3: duplicate key 'duration_s' (first at line 1)" -- run dup_top.yaml
scen dup_port.yaml 'ports:\n  - host: protocol\n    traffic: fixed\n    traffic: burst\n'
expect 2 "dup_port.yaml:4: duplicate key 'traffic' (first at line 3)" -- run dup_port.yaml
scen dup_flow.yaml 'ports:\n  - host: protocol\n    traffic: saturate\n    tokens: {EC: 1, EC: 2}\n'
expect 2 "dup_flow.yaml:4: duplicate key 'EC' (twice on this line)" -- run dup_flow.yaml
scen dup_motion.yaml 'motion:\n  duration_s: 0.01\n  duration_s: 0.02\n'
expect 2 "dup_motion.yaml:3: duplicate key 'duration_s' (first at line 2)" -- run dup_motion.yaml
scen twodoc.yaml 'duration_s: 0.001\n---\nduration_s: 2\n'
expect 2 "twodoc.yaml:3: a second YAML document" -- run twodoc.yaml
scen index.yaml 'ports:\n  - host: protocol\n    faults: [{kind: drop, index: 1.7}]\n'
expect 2 "index.yaml:3: 'ports[0].faults[0].index' = 1.7 must be a whole number" -- run index.yaml
scen count.yaml 'ports:\n  - host: protocol\n    traffic: fixed\n    count: 2.5\n'
expect 2 "count.yaml:4: 'ports[0].count' = 2.5 must be a whole number" -- run count.yaml
scen burst0.yaml 'ports:\n  - host: protocol\n    traffic: burst\n    burst_size: 0\n'
expect 2 "burst0.yaml:4: 'ports[0].burst_size' = 0 must be a whole number in [1, 1000000]" -- run burst0.yaml
scen data.yaml 'ports:\n  - host: protocol\n    traffic: fixed\n    data_size: 8193\n'
expect 2 "data.yaml:4: 'ports[0].data_size' = 8193 must be a whole number in [0, 8192]" -- run data.yaml
scen ctrl.yaml 'b\001ad\033[2J: 1\n'
expect 2 "ctrl.yaml:1: unknown key 'b\\x01ad\\x1B[2J'" -- run ctrl.yaml
scen realtime.yaml 'realtime: -0.5\n'
expect 2 "realtime.yaml:1: 'realtime' = -0.5 must be 0 (off) or in [0.01, 1e6]" -- run realtime.yaml
scen realtime2.yaml 'realtime: 1e-300\n'
expect 2 "realtime2.yaml:1: 'realtime' = 1e-300 must be 0 (off) or in [0.01, 1e6]" -- run realtime2.yaml
scen budget.yaml 'budget_us: -0.5\n'
expect 2 "budget.yaml:1: 'budget_us' = -0.5 is out of range [0, 1e+09]" -- run budget.yaml
scen budget0.yaml 'budget_us: 0\n'
expect 2 "budget0.yaml:1: 'budget_us' must be > 0" -- run budget0.yaml
scen latency.yaml 'checks: {max_char_latency_us: -0.5}\n'
expect 2 "latency.yaml:1: 'checks.max_char_latency_us' = -0.5 is out of range [0, 1e+09]" -- run latency.yaml
scen period.yaml 'main_cpu: {cycle_period_us: 1e-6, cycle_time_us: 0}\n'
expect 2 "period.yaml:1: 'main_cpu.cycle_period_us' = 1e-06 is out of range [10," -- run period.yaml
# Fault bits against the port's format: 8E1 has data bits 0..7 and cells 0..10 (START, 8 data,
# parity, STOP); 7N2 has data bits 0..6 and cells 0..8 (the line model takes cells through the
# first STOP).
scen cell11.yaml 'ports:\n  - host: protocol\n    faults: [{kind: flip_cell, bit: 11}]\n'
expect 2 "cell11.yaml:3: 'ports[0].faults[0].bit' = 11 is not a cell of a 9600,8E1 character (0..10)" -- run cell11.yaml
scen bit9.yaml 'ports:\n  - host: protocol\n    faults: [{kind: flip_data_bit, bit: 9}]\n'
expect 2 "bit9.yaml:3: 'ports[0].faults[0].bit' = 9 is not a data bit of a 9600,8E1 character (0..7)" -- run bit9.yaml
scen bit7.yaml 'ports:\n  - host: raw\n    format: "9600,7N2"\n    faults: [{kind: flip_data_bit, bit: 7}]\n'
expect 2 "bit7.yaml:4: 'ports[0].faults[0].bit' = 7 is not a data bit of a 9600,7N2 character (0..6)" -- run bit7.yaml
scen cell9.yaml 'ports:\n  - host: raw\n    format: "9600,7N2"\n    faults: [{kind: flip_cell, bit: 9}]\n'
expect 2 "cell9.yaml:4: 'ports[0].faults[0].bit' = 9 is not a cell of a 9600,7N2 character (0..8)" -- run cell9.yaml
scen dropbit.yaml 'ports:\n  - host: protocol\n    faults: [{kind: drop, bit: 3}]\n'
expect 2 "dropbit.yaml:3: 'ports[0].faults[0].bit' applies to flip_data_bit and flip_cell, not drop" -- run dropbit.yaml
expect 2 "/dev/zero: is not a regular file" -- run /dev/zero
truncate -s 5M big.yaml
expect 2 "big.yaml: is 5242880 bytes; a scenario file is at most 4194304 bytes" -- run big.yaml
{ printf 'ports:\n  - host: raw\n    send: [{at_ms: 0, bytes: "'; head -c 1048577 /dev/zero | tr '\0' a; printf '"}]\n'; } > sendbig.yaml
expect 2 "sendbig.yaml:3: 'ports[0].send' holds more than 1048576 bytes in all" -- run sendbig.yaml

# Unknown keys at every level.
scen unk_top.yaml 'bogus: 1\n'
expect 2 "unk_top.yaml:1: unknown key 'bogus'" -- run unk_top.yaml
scen unk_board.yaml 'board:\n  bogus: 1\n'
expect 2 "unk_board.yaml:2: unknown key 'board.bogus'" -- run unk_board.yaml
scen unk_ws.yaml 'board:\n  wait_states: {ram: 0, bogus: 1}\n'
expect 2 "unk_ws.yaml:2: unknown key 'board.wait_states.bogus'" -- run unk_ws.yaml
scen unk_main.yaml 'main_cpu:\n  bogus: 1\n'
expect 2 "unk_main.yaml:2: unknown key 'main_cpu.bogus'" -- run unk_main.yaml
scen unk_checks.yaml 'checks:\n  bogus: 1\n'
expect 2 "unk_checks.yaml:2: unknown key 'checks.bogus'" -- run unk_checks.yaml
scen unk_port.yaml 'ports:\n  - host: protocol\n    bogus: 1\n'
expect 2 "unk_port.yaml:3: unknown key 'ports[0].bogus'" -- run unk_port.yaml
scen unk_fault.yaml 'ports:\n  - host: protocol\n    faults:\n      - {kind: drop, index: 1, bogus: 2}\n'
expect 2 "unk_fault.yaml:4: unknown key 'ports[0].faults[0].bogus'" -- run unk_fault.yaml
scen unk_send.yaml 'ports:\n  - host: raw\n    send: [{at_ms: 1, bytes: "a", bogus: 1}]\n'
expect 2 "unk_send.yaml:3: unknown key 'ports[0].send[0].bogus'" -- run unk_send.yaml
scen traffic_none.yaml 'ports:\n  - host: none\n    traffic: saturate\n'
expect 2 "traffic_none.yaml:3: unknown key 'ports[0].traffic'" -- run traffic_none.yaml
scen log_none.yaml 'ports:\n  - host: none\n    log: x.log\n'
expect 2 "log_none.yaml:3: 'ports[0].log' is the protocol host's transaction log" -- run log_none.yaml

# Ports, serial formats, raw bytes, faults, tokens.
scen ports4.yaml 'ports: [{host: none}, {host: none}, {host: none}, {host: none}]\n'
expect 2 "ports4.yaml:1: 'ports' must be a list of at most 3 ports" -- run ports4.yaml
scen portelem.yaml 'ports:\n  - 5\n'
expect 2 "portelem.yaml:2: 'ports[0]' must be a mapping" -- run portelem.yaml
scen host.yaml 'ports:\n  - host: modem\n'
expect 2 "host.yaml:2: unknown host 'modem'" -- run host.yaml
scen fmt.yaml 'ports:\n  - host: protocol\n    format: "9600,9X1"\n'
expect 2 "fmt.yaml:3: bad serial format '9600,9X1'" -- run fmt.yaml
scen fmt0.yaml 'ports:\n  - host: protocol\n    format: "0,8E1"\n'
expect 2 "fmt0.yaml:3: bad serial format '0,8E1'" -- run fmt0.yaml
scen fmtbig.yaml 'ports:\n  - host: protocol\n    format: "99999999999,8E1"\n'
expect 2 "fmtbig.yaml:3: bad serial format '99999999999,8E1'" -- run fmtbig.yaml
scen fmtstop.yaml 'ports:\n  - host: raw\n    format: "9600,8N3"\n'
expect 2 "fmtstop.yaml:3: bad serial format '9600,8N3'" -- run fmtstop.yaml
scen esc.yaml 'ports:\n  - host: raw\n    send:\n      - {at_ms: 1, bytes: "\\\\xZZ"}\n'
expect 2 "esc.yaml:4: bad escape '\\xZZ'" -- run esc.yaml
scen esc2.yaml 'ports:\n  - host: raw\n    send: [{at_ms: 1, bytes: "abc\\\\"}]\n'
expect 2 "esc2.yaml:3: bad escape '\\' at offset 3" -- run esc2.yaml
scen esc3.yaml 'ports:\n  - host: raw\n    send: [{at_ms: 1, bytes: "\\\\q"}]\n'
expect 2 "esc3.yaml:3: bad escape '\\q'" -- run esc3.yaml
scen send.yaml 'ports:\n  - host: raw\n    send: {at_ms: 1}\n'
expect 2 "send.yaml:3: 'ports[0].send' must be a list" -- run send.yaml
scen fault.yaml 'ports:\n  - host: protocol\n    faults:\n      - {kind: zap, index: 1}\n'
expect 2 "fault.yaml:4: unknown fault kind 'zap'" -- run fault.yaml
scen faultfrom.yaml 'ports:\n  - host: protocol\n    faults: [{kind: drop, from: both}]\n'
expect 2 "faultfrom.yaml:3: 'from' must be host or controller, not 'both'" -- run faultfrom.yaml
scen faultkind.yaml 'ports:\n  - host: protocol\n    faults: [{index: 3}]\n'
expect 2 "faultkind.yaml:3: missing required key 'ports[0].faults[0].kind'" -- run faultkind.yaml
scen tokneg.yaml 'ports:\n  - host: protocol\n    traffic: saturate\n    tokens: {EC: -1}\n'
expect 2 "tokneg.yaml:4: token 'EC' must be two characters with a finite weight > 0" -- run tokneg.yaml
scen tokinf.yaml 'ports:\n  - host: protocol\n    traffic: saturate\n    tokens: {EC: .inf, ST: 1}\n'
expect 2 "tokinf.yaml:4: token 'EC' must be two characters with a finite weight > 0" -- run tokinf.yaml
scen toknan.yaml 'ports:\n  - host: protocol\n    traffic: saturate\n    tokens: {EC: .nan}\n'
expect 2 "toknan.yaml:4: token 'EC' must be two characters with a finite weight > 0" -- run toknan.yaml
scen tokstr.yaml 'ports:\n  - host: protocol\n    traffic: saturate\n    tokens: {EC: abc}\n'
expect 2 "tokstr.yaml:4: bad weight for token 'EC'" -- run tokstr.yaml
scen toklen.yaml 'ports:\n  - host: protocol\n    traffic: saturate\n    tokens: {ECX: 1}\n'
expect 2 "toklen.yaml:4: token 'ECX' must be two characters" -- run toklen.yaml
scen tokkey.yaml 'ports:\n  - host: protocol\n    traffic: saturate\n    tokens: {[a]: 1}\n'
expect 2 "tokkey.yaml:4: a token must be two characters" -- run tokkey.yaml
scen tokempty.yaml 'ports:\n  - host: protocol\n    traffic: saturate\n    tokens: {}\n'
expect 2 "tokempty.yaml:4: 'ports[0].tokens' must map tokens to weights" -- run tokempty.yaml
scen traffic.yaml 'ports:\n  - host: protocol\n    traffic: warp\n'
expect 2 "traffic.yaml:3: unknown traffic pattern 'warp'" -- run traffic.yaml
scen rate.yaml 'ports:\n  - host: protocol\n    traffic: fixed\n    rate_hz: 0\n'
expect 2 "rate.yaml:4: 'ports[0].rate_hz' = 0 is out of range" -- run rate.yaml
scen listen.yaml 'ports:\n  - host: tcp\n    listen: "127.0.0.1:99999"\n'
expect 2 "listen.yaml:3: bad 'listen': port 99999 out of range" -- run listen.yaml
scen replay.yaml 'ports:\n  - host: replay\n    file: nope.log\n'
expect 2 "nope.log: cannot open the session log" -- run replay.yaml
printf 'garbage line\n' > garbage.log
scen replay2.yaml 'ports:\n  - host: replay\n    file: garbage.log\n'
expect 2 "garbage.log:1: expected" -- run replay2.yaml
# Replay logs: a regular file, times as plain unsigned decimals up to 3600 s, nothing after an event.
replay_case() { # NAME LOG-TEXT RC MESSAGE
    printf "$2" > "$1.log"
    scen "$1.yaml" "duration_s: 0\nports:\n  - host: replay\n    file: $1.log\n"
    expect "$3" "$4" -- run "$1.yaml"
}
replay_case r_neg 'format 9600,8E1\n-5 end\n' 2 "r_neg.log:2: expected '<time ps> <event>'"
replay_case r_plus 'format 9600,8E1\n+5 end\n' 2 "r_plus.log:2: expected '<time ps> <event>'"
replay_case r_exp 'format 9600,8E1\n1e3 end\n' 2 "r_exp.log:2: expected '<time ps> <event>'"
replay_case r_far 'format 9600,8E1\n3600000000000001 end\n' 2 "r_far.log:2: time 3600000000000001 ps is beyond 3600000000000000 ps"
replay_case r_wrap 'format 9600,8E1\n18446744073709551621 end\n' 2 "r_wrap.log:2: time 18446744073709551621 ps is beyond"
replay_case r_extra 'format 9600,8E1\n5 in 05 P junk\n' 2 "r_extra.log:2: unexpected 'junk' at the end of the line"
replay_case r_byte 'format 9600,8E1\n5 in +5\n' 2 "r_byte.log:2: bad byte '+5' (two hex digits)"
replay_case r_back 'format 9600,8E1\n5 in 05\n4 end\n' 2 "r_back.log:3: time 4 ps goes backwards"
replay_case r_ctrl 'format 9600,8E1\n5 \033[2Jx\n' 2 "r_ctrl.log:2: unknown event '\\x1B[2Jx'"
scen r_zero.yaml 'duration_s: 0\nports:\n  - host: replay\n    file: /dev/zero\n'
expect 2 "/dev/zero: is not a regular file (a session log)" -- run r_zero.yaml
truncate -s 65M r_big.log
scen r_big.yaml 'duration_s: 0\nports:\n  - host: replay\n    file: r_big.log\n'
expect 2 "r_big.log: session log is 68157440 bytes; at most 67108864 are read" -- run r_big.yaml
touch a_file
# A relative output lands under --out (made as needed); an absolute one is honoured: under a file.
scen record.yaml "ports:\n  - host: raw\n    record: $W/a_file/x.bin\n"
expect 2 "a_file/x.bin: cannot create its folder" -- run record.yaml

# --- ROM images -----------------------------------------------------------------------------
scen ok.yaml '{duration_s: 0.001}\n'
: > empty.rom
head -c 65535 /dev/zero > short.rom
head -c 65537 /dev/zero > long.rom
mkdir -p romdir
expect 2 "missing.rom: cannot open ROM image" -- run ok.yaml --rom missing.rom
expect 2 "empty.rom: ROM image is 0 bytes" -- run ok.yaml --rom empty.rom
expect 2 "short.rom: ROM image is 65535 bytes" -- run ok.yaml --rom short.rom
expect 2 "long.rom: ROM image is 65537 bytes" -- run ok.yaml --rom long.rom
expect 2 "romdir: is a directory, not a ROM image" -- run ok.yaml --rom romdir
scen romkey.yaml 'rom: nothere.rom\nduration_s: 0.001\n'
expect 2 "nothere.rom: cannot open ROM image" -- run romkey.yaml
# Checked before reading: a device would be read forever, a huge file into memory.
expect 2 "--rom '': an empty path" -- run ok.yaml --rom ''
expect 2 "/dev/zero: is not a regular file (a ROM image)" -- run ok.yaml --rom /dev/zero
expect 2 "/dev/urandom: is not a regular file (a ROM image)" -- run ok.yaml --rom /dev/urandom
truncate -s 3G sparse.rom
expect 2 "sparse.rom: ROM image is 3221225472 bytes" -- run ok.yaml --rom sparse.rom
expect 2 "/proc/self/mem: ROM image is 0 bytes" -- run ok.yaml --rom /proc/self/mem

# --- symbols: --symbols FILE[@SEG] alone or with any option (scenarios/debug/rom_symbols.h) ---
# Read before the run: a bad file is one message naming it, whatever else the run does.
printf 'start F000:0000\nbroken line with too many words here\n' > bad.sym
expect 2 "--symbols: bad.sym:2: " -- run ok.yaml --symbols bad.sym
expect 2 "--symbols: nothere.map: cannot open the symbol file" -- run ok.yaml --symbols nothere.map
head -c 65536 /dev/zero > zero.rom
expect 2 "--symbols: nothere.map: cannot open the symbol file" -- run ok.yaml --rom zero.rom --symbols nothere.map
expect 2 "--symbols '': an empty path" -- run ok.yaml --symbols ''

# --- exit 3: legal 8259A modes the model does not implement -----------------------------------
# A ROM whose reset code (FFFF:0000 = offset 0xFFF0) writes ICW1 0x11 to the 8259A at I/O 0xC0:
# IC4=1 but SNGL=0, cascade mode (8259A data sheet, ICW1 bit 1), then HLT.
rom_with_code() { # FILE CODE-BYTES(printf escapes)
    head -c 65520 /dev/zero | tr '\0' '\364' > "$1"
    printf "$2" >> "$1"
    head -c $((65536 - $(stat -c %s "$1"))) /dev/zero | tr '\0' '\364' >> "$1"
}
rom_with_code cascade.rom '\260\021\346\300\364'
expect 3 "unsupported by the model: rcsim/pic8259/unsupported in world.controller.comm.cpu.run at 2625 ns: world.controller.comm.pic: ICW1 0x11 has SNGL=0" -- run ok.yaml --rom cascade.rom
# ICW1 0x13 (single, IC4), ICW2 0x20, ICW4 0x00: uPM=0 selects MCS-80/85 mode.
rom_with_code mcs80.rom '\260\023\346\300\260\040\346\302\260\000\346\302\364'
expect 3 "unsupported by the model: rcsim/pic8259/unsupported" -- run ok.yaml --rom mcs80.rom

# --- write failures: a full disk is an error naming the file, not a silent exit 0 ------------
scen w_log.yaml 'duration_s: 0.01\nports:\n  - host: protocol\n    traffic: saturate\n    log: /dev/full\n'
expect 2 "/dev/full: cannot write the host log: No space left on device" -- run w_log.yaml
# The firmware answers an ENQ with ACK: one byte for the record file.
scen w_rec.yaml 'duration_s: 0.3\nports:\n  - host: raw\n    record: /dev/full\n    send: [{at_ms: 100, bytes: "\\\\x05"}]\n'
expect 2 "/dev/full: cannot write the record file: No space left on device" -- run w_rec.yaml
scen w_tcp.yaml 'duration_s: 0.01\nports:\n  - host: tcp\n    record: /dev/full\n'
expect 2 "/dev/full: cannot write the session log: No space left on device" -- run w_tcp.yaml
ln -s /dev/full full.vcd
expect 2 "full.vcd: cannot write the VCD file: No space left on device" -- run ok.yaml --vcd full.vcd
for f in report.json interrupts.csv report.html; do
    mkdir -p "full_$f" && ln -s /dev/full "full_$f/$f"
    expect 2 "full_$f/$f: cannot write" -- run ok.yaml --out "full_$f"
done

# --- command line ---------------------------------------------------------------------------
expect 2 "unknown command 'frobnicate'" -- frobnicate
expect 2 "unknown command 'frob'" -- bench frob
expect 2 "A subcommand is required" --
expect 2 "scenario is required" -- run
expect 2 "--bogus" -- run ok.yaml --bogus
expect 2 "--seed 'abc' is not a number" -- run ok.yaml --seed abc
expect 2 "--seed '-5' is not a number" -- run ok.yaml --seed -5
expect 2 "--seed '99999999999999999999999' is not a number" -- run ok.yaml --seed 99999999999999999999999
expect 2 "--out 'a_file': cannot create the output directory" -- run ok.yaml --out a_file
expect 2 "--out 'a_file/sub': cannot create the output directory" -- run ok.yaml --out a_file/sub
expect 2 "a_file/x.vcd: cannot write the VCD file" -- run ok.yaml --vcd a_file/x.vcd
expect 2 "--vcd: '/dev/null': a VCD file's name ends in .vcd" -- run ok.yaml --vcd /dev/null
expect 2 "--level: '7' is not in 1 .. 3" -- cputest --level 7 .
expect 2 "--level: '2.7' is not a whole number" -- cputest --level 2.7 .
expect 2 "--min-rate: 'nan' is not a number" -- cputest --min-rate nan .
expect 2 "PATH is required" -- cputest
expect 2 "--seconds: 'nan' is not a number" -- bench cpu --seconds nan
expect 2 "--seconds: 'inf' is not a number" -- bench cpu --seconds inf
expect 2 "--seconds: '1000' is not in 0.1 .. 600" -- bench cpu --seconds 1000
expect 2 "--rounds: '0' is not in 1 .. 100" -- bench cpu --rounds 0
# Each bench's numbers are checked as they are parsed: never an internal error (issue 33).
expect 2 "--lines: '0' is not in 1 .. 64" -- bench serial --lines 0
expect 2 "--lines: '2.5' is not a whole number" -- bench serial --lines 2.5
expect 2 "--baud: '0' is not in 1 .. 576000" -- bench serial --baud 0
expect 2 "--baud: '9601' is not an exact divisor rate of 18.432 MHz / 32" -- bench serial --baud 9601
expect 2 "--seconds: '-5' is not in 0.001 .. 3600" -- bench serial --seconds -5
expect 2 "--seconds: 'nan' is not a number" -- bench serial --seconds nan
expect 2 "--seconds: 'inf' is not a number" -- bench serial --seconds inf
expect 2 "--seconds: '1e9' is not in 0.001 .. 3600" -- bench serial --seconds 1e9
expect 2 "--seconds: 'nan' is not a number" -- bench motion --seconds nan
expect 2 "--seconds: '0' is not in 0.001 .. 36000" -- bench motion --seconds 0
expect 2 "--rounds: '0' is not in 1 .. 100" -- bench system --rounds 0

# --- cputest inputs -------------------------------------------------------------------------
printf '{"x":' | gzip > partial.json.gz
head -c 20 partial.json.gz > trunc.json.gz
echo 'not json' | gzip > nonjson.json.gz
echo '[{"name": "x"}]' | gzip > shape.json.gz
expect 2 "trunc.json.gz: read error" -- cputest --level 1 trunc.json.gz
expect 2 "nonjson.json.gz: malformed or truncated JSON" -- cputest --level 1 nonjson.json.gz
expect 2 "shape.json.gz: test 0: missing" -- cputest --level 1 shape.json.gz
expect 2 "none.json.gz: no such file" -- cputest --level 1 none.json.gz
mkdir -p emptydir
expect 2 "emptydir: no SingleStepTests files" -- cputest --level 1 emptydir
expect 2 "/dev/zero: not a regular file" -- cputest --level 1 /dev/zero
truncate -s 65M huge.json
expect 2 "huge.json: 68157440 bytes; a test file is at most 67108864" -- cputest --level 1 huge.json

# --- the motion section ---------------------------------------------------------------------
scen m_unk.yaml 'motion:\n  duration_s: 0.01\n  bogus: 1\n'
expect 2 "m_unk.yaml:3: unknown key 'motion.bogus'" -- run m_unk.yaml
scen m_dur.yaml 'motion:\n  control_cycle_ms: 1\n'
expect 2 "m_dur.yaml:2: missing required key 'motion.duration_s'" -- run m_dur.yaml
scen m_fb.yaml 'motion:\n  duration_s: 0.01\n  commands:\n    - {at_ms: 0, fb: MC_Fly, axis: 0}\n'
expect 2 "m_fb.yaml:4: unknown function block 'MC_Fly'" -- run m_fb.yaml
scen m_axis.yaml 'motion:\n  duration_s: 0.01\n  commands:\n    - {at_ms: 0, fb: MC_Power, axis: 9}\n'
expect 2 "m_axis.yaml:4: 'motion.commands[0].axis' = 9 is out of range [0, 3]" -- run m_axis.yaml
scen m_frac.yaml 'motion:\n  duration_s: 0.01\n  commands:\n    - {at_ms: 0, fb: MC_MoveAbsolute, axis: 0, position: 1000.5, velocity: 1, acceleration: 1, deceleration: 1}\n'
expect 2 "m_frac.yaml:4: 'motion.commands[0].position' must be a whole number of pulses" -- run m_frac.yaml
scen m_range.yaml 'motion:\n  duration_s: 0.01\n  commands:\n    - {at_ms: 0, fb: MC_LineMove2, x: 1073741824, y: 0, velocity: 1, acceleration: 1, deceleration: 1}\n'
expect 2 "m_range.yaml:4: 'motion.commands[0].x' = 1073741824 pulses is out of the chip's range [-1073741823, 1073741823]" -- run m_range.yaml
scen m_map.yaml 'motion: 5\n'
expect 2 "m_map.yaml:1: 'motion' must be a mapping" -- run m_map.yaml
scen m_nan.yaml 'motion:\n  duration_s: .nan\n'
expect 2 "m_nan.yaml:2: 'motion.duration_s' = nan is out of range" -- run m_nan.yaml
scen m_pos.yaml 'motion:\n  duration_s: 0.01\n  checks: {final_positions: [a]}\n'
expect 2 "m_pos.yaml:3: bad value for 'motion.checks.final_positions[0]': 'a'" -- run m_pos.yaml
scen m_key.yaml 'motion:\n  duration_s: 0.01\n  {[a]: 1}: 2\n'
expect 2 "m_key.yaml:3: a key in 'motion' must be a plain name" -- run m_key.yaml
scen m_clear.yaml 'motion:\n  duration_s: 0.01\n  commands:\n    - {at_ms: 0, inject_fault: 0, clear_after: maybe}\n'
expect 2 "m_clear.yaml:4: 'motion.commands[0].clear_after' must be 'yes' or 'no', got 'maybe'" -- run m_clear.yaml
scen m_ports.yaml 'motion:\n  duration_s: 0.01\nports: []\n'
expect 2 "m_ports.yaml:2: a 'motion' section runs the motion side alone" -- run m_ports.yaml
expect 2 "--out 'a_file': cannot create the output directory" -- run "$SRC/scenarios/xy_plotter_circle.yaml" --out a_file

# --- scripted protocol hosts (docs/scenarios.md "Scripted hosts") ---------------------------
scen s_empty.yaml 'ports:\n  - {host: protocol, traffic: script}\n'
expect 2 "s_empty.yaml:2: 'ports[0].traffic: script' needs a non-empty 'script' list" -- run s_empty.yaml
scen s_nopat.yaml 'ports:\n  - host: protocol\n    traffic: saturate\n    script:\n      - {token: EC}\n'
expect 2 "s_nopat.yaml:5: 'ports[0].script' needs 'traffic: script'" -- run s_nopat.yaml
scen s_two.yaml 'ports:\n  - host: protocol\n    traffic: script\n    script:\n      - {token: EC}\n      - {token: SV, wait_state: STANDSTILL}\n'
expect 2 "s_two.yaml:6: a script step has exactly one of 'token', 'wait_state' and 'delay_ms'" -- run s_two.yaml
scen s_tok.yaml 'ports:\n  - host: protocol\n    traffic: script\n    script:\n      - {token: ECX}\n'
expect 2 "s_tok.yaml:5: this command cannot be sent: " -- run s_tok.yaml
scen s_key.yaml 'ports:\n  - host: protocol\n    traffic: script\n    script:\n      - {token: EC, dat: "1"}\n'
expect 2 "s_key.yaml:5: unknown key 'ports[0].script[0].dat'" -- run s_key.yaml
scen s_bch.yaml 'ports:\n  - host: protocol\n    traffic: script\n    script:\n      - {token: EC, expect_bch: 256}\n'
expect 2 "s_bch.yaml:5: 'ports[0].script[0].expect_bch' = 256 must be a whole number in [0, 255]" -- run s_bch.yaml
scen s_wait.yaml 'ports:\n  - host: protocol\n    traffic: script\n    script:\n      - {token: EC, wait: maybe}\n'
expect 2 "s_wait.yaml:5: 'ports[0].script[0].wait' must be" -- run s_wait.yaml
scen s_poll.yaml 'ports:\n  - host: protocol\n    traffic: script\n    script:\n      - {wait_state: STANDSTILL, poll_ms: 0}\n'
expect 2 "s_poll.yaml:5: 'ports[0].script[0].poll_ms' must be > 0" -- run s_poll.yaml
scen s_circ.yaml 'checks:\n  circle: {center_x: 0, center_y: 0, radius: 1}\n'
expect 2 "s_circ.yaml:2: 'checks.circle' judges the motion layer: it needs 'main_cpu: {motion: true}'" -- run s_circ.yaml

echo "$cases bad-input cases, $failures failed"
[ "$failures" -eq 0 ]
