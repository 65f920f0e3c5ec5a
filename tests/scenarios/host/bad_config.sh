#!/usr/bin/env bash
# Bad pty and tcp-BREAK settings through the rcsim executable: each ends with exit 2 and one
# message naming the scenario file and line (docs/serial.md "A pty as the serial port", "BREAK").
#
# Usage: bad_config.sh RCSIM
set -u
RCSIM=$(realpath "${1:?usage: bad_config.sh RCSIM}")
export SC_COPYRIGHT_MESSAGE=DISABLE
W=$(mktemp -d "${TMPDIR:-/tmp}/rcsim_pty_bad.XXXXXX")
trap 'rm -rf "$W"' EXIT
cd "$W" || exit 1
failures=0

# expect SUBSTRING FILE: `rcsim run FILE` exits 2 with SUBSTRING on stderr, nothing crashed.
expect() {
    timeout 30 "$RCSIM" run "$2" --out out > out.txt 2> err.txt
    local rc=$? why=""
    [ "$rc" -eq 2 ] || why="exit $rc, expected 2"
    grep -qF -- "$1" err.txt || why="$why; stderr does not contain '$1'"
    if grep -qE 'AddressSanitizer|runtime error:|terminate called|Aborted' err.txt; then why="$why; crash report"; fi
    if [ -n "$why" ]; then
        failures=$((failures + 1))
        echo "FAIL: $2: ${why#; }"
        sed 's/^/    stderr: /' err.txt | head -5
    fi
}
pty() { printf 'name: x\nduration_s: 0.01\nports:\n  - {host: pty, link: %s}\n' "$2" > "$1"; }

pty nofolder.yaml "$W/no/such/folder/tty0"
expect "nofolder.yaml:4: 'link' $W/no/such/folder/tty0: no folder $W/no/such/folder" nofolder.yaml
echo mine > afile
pty afile.yaml "$W/afile"
expect "afile.yaml:4: 'link' $W/afile exists and is not a symlink" afile.yaml
grep -qx mine afile || { failures=$((failures + 1)); echo "FAIL: the file at the link path was changed"; }
mkdir adir
pty adir.yaml "$W/adir"
expect "adir.yaml:4: 'link' $W/adir exists and is not a symlink" adir.yaml
# /proc takes no symlinks, whoever asks (root included)
pty proc.yaml /proc/rcsim_tty0
expect "proc.yaml:4: 'link' /proc/rcsim_tty0: cannot make a symlink in /proc" proc.yaml

printf 'ports:\n  - {host: tcp, telnet: true, break_ms: 1}\n' > shortbreak.yaml
expect "shortbreak.yaml:2: 'ports[0].break_ms' must be longer than one 9600,8E1 character" shortbreak.yaml
printf 'ports:\n  - {host: tcp, break_ms: 10}\n' > notelnet.yaml
expect "notelnet.yaml:2: 'ports[0].break_ms' is the length of a telnet IAC BRK: it needs 'telnet: true'" notelnet.yaml

[ "$failures" -eq 0 ] && echo "PASS" && exit 0
exit 1
