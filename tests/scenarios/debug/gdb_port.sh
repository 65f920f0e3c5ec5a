# Sourced by the gdb tests: gdb_port OUTFILE PID prints the port `rcsim run --gdb 127.0.0.1:0`
# printed to OUTFILE ("gdb: listening on 127.0.0.1:PORT"), waiting up to 10 s; returns 1 when
# the run ended first or printed none.
gdb_port() {
  local out=$1 pid=$2 port=
  for _ in $(seq 200); do
    port=$(sed -n 's/^gdb: listening on 127\.0\.0\.1:\([0-9]*\).*/\1/p' "$out")
    [ -n "$port" ] && { echo "$port"; return 0; }
    kill -0 "$pid" 2>/dev/null || return 1
    sleep 0.05
  done
  return 1
}
