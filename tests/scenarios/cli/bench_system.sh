#!/bin/bash
# `rcsim bench system` prints, beside its RTF figures, what bounds them: for each run the comm
# CPU's kernel waits and the instructions it executed one by one. Checked against what the
# switches mean: with fast_sync off every TLM access ends a slice, so the CPU waits for the
# kernel more often, but before as many accesses; with the fast-forward on, the idle loop of
# the run without traffic is mostly forwarded, so far fewer instructions are executed than
# with it off, and its accesses are still made, each after a wait unless its target declared
# it stable: with stable reads off, every access waits (the idle loop's DP-RAM polls too). With
# the slice chain off, every slice that ends before the next event waits for the kernel too.
set -euo pipefail
rcsim=$1
scenario=$2
out=$("$rcsim" bench system "$scenario" --rounds 1)
echo "$out"
field() { # field VARIANT N: the N-th number of the variant's bound line
    echo "$out" | grep -E "^    $1: [0-9]+ kernel waits" | grep -oE '[0-9]+(\.[0-9]+)?' | sed -n "$2p"
}
for v in "all speed-ups on" "fast_sync off" "fast_forward off" "no traffic, all on" "no traffic, fast_forward off" \
    "no traffic, stable_reads off" "no traffic, slice_chain off"; do
    echo "$out" | grep -qE "^    $v: [0-9]+ kernel waits \([0-9]+ before accesses\) [0-9.]+ ms \+ [0-9.]+ M instructions [0-9.]+ ms -> at most [0-9.]+x$" ||
        { echo "FAIL: no bound line for '$v'"; exit 1; }
done
echo "$out" | grep -qE "one SystemC wait\(\) of a thread alone [0-9.]+ ns" || { echo "FAIL: no wait() figure"; exit 1; }
echo "$out" | grep -qE "libx86emu on the anchor image [0-9.]+ M instructions/s" || { echo "FAIL: no libx86emu figure"; exit 1; }
on=$(field "all speed-ups on" 1)
off=$(field "fast_sync off" 1)
[ "$off" -gt "$on" ] || { echo "FAIL: fast_sync off waits $off times, not more than all on ($on)"; exit 1; }
# Every bus access waits for its T1 whatever the switches (the sync rule): the same count with
# fast_sync off and with the fast-forward off (its replay makes each access again, synced).
for v in "fast_sync off" "fast_forward off"; do
    [ "$(field "$v" 2)" = "$(field "all speed-ups on" 2)" ] ||
        { echo "FAIL: '$v' waits before $(field "$v" 2) accesses, all on before $(field "all speed-ups on" 2)"; exit 1; }
done
[ "$(field "no traffic, all on" 2)" = "$(field "no traffic, fast_forward off" 2)" ] ||
    { echo "FAIL: without traffic the fast-forward changes the waits before accesses"; exit 1; }
stable_on=$(field "no traffic, all on" 2)
stable_off=$(field "no traffic, stable_reads off" 2)
[ "$stable_off" -gt "$stable_on" ] ||
    { echo "FAIL: without traffic and stable reads off $stable_off waits before accesses, all on $stable_on"; exit 1; }
chain_off=$(field "no traffic, slice_chain off" 1)
[ "$chain_off" -gt "$(field "no traffic, all on" 1)" ] ||
    { echo "FAIL: without traffic and the slice chain off $chain_off kernel waits, all on $(field "no traffic, all on" 1)"; exit 1; }
idle_on=$(field "no traffic, all on" 4)
idle_off=$(field "no traffic, fast_forward off" 4)
awk -v a="$idle_on" -v b="$idle_off" 'BEGIN { exit !(a * 4 < b) }' ||
    { echo "FAIL: without traffic $idle_on M instructions executed with the fast-forward, $idle_off M without: not under a quarter"; exit 1; }
echo "PASS"
