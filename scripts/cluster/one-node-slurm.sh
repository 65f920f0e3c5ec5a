#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, everything in one folder (docs/regression.md "On a
# cluster"): munge with a fresh key, slurmctld and slurmd from a generated slurm.conf on
# 127.0.0.1 and two free ports, their spool, state, pid and log files in DIR. To try the job array
# recipe before a real cluster, and for the test that runs it (CTest cluster.slurm).
#
#   scripts/cluster/one-node-slurm.sh start DIR   # then: export SLURM_CONF=DIR/slurm.conf
#   scripts/cluster/one-node-slurm.sh stop DIR    # stops what start started, by the pids in DIR
#
# Needs root (munged and slurmd run as root here) and Debian's slurmctld, slurmd, slurm-client and
# munge (scripts/install-deps.sh). start exits 0 once the node is idle, 2 when it cannot start
# (the reason on stderr, the daemons' logs in DIR). No accounting (sacct needs slurmdbd), no
# cgroups: proctrack/linuxproc and task/none run where the freezer cgroup is not available.
set -u
usage() { echo "usage: one-node-slurm.sh start|stop DIR" >&2; exit 2; }
[ $# -eq 2 ] || usage
action=$1
DIR=$2

# The daemons in the order stop ends them: slurmd first, munge last (the others authenticate with it).
daemons="slurmd slurmctld munged"

stop() {
    for d in $daemons; do
        pidfile=$DIR/$d.pid
        [ -s "$pidfile" ] || continue
        pid=$(cat "$pidfile")
        kill "$pid" 2>/dev/null
        # A daemon that does not end within 10 s is killed: a test must never leave one behind.
        for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
        kill -KILL "$pid" 2>/dev/null
        rm -f "$pidfile"
    done
    return 0
}

die() { echo "one-node-slurm: $*" >&2; stop; exit 2; }

# A TCP port nobody listens on now, on 127.0.0.1.
free_port() {
    /usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

write_conf() {
    # CPUs and memory as slurmd itself sees them: more memory than `slurmd -C` reports drains the node.
    local node cpus mem
    node=$(slurmd -C | head -1) || die "slurmd -C failed"
    cpus=$(sed -n 's/.* CPUs=\([0-9]*\).*/\1/p' <<<"$node")
    mem=$(sed -n 's/.* RealMemory=\([0-9]*\).*/\1/p' <<<"$node")
    [ -n "$cpus" ] && [ -n "$mem" ] || die "slurmd -C: no CPUs= or RealMemory= in '$node'"
    cat >"$DIR/slurm.conf" <<EOF
ClusterName=rcsim
SlurmctldHost=localhost(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
CommunicationParameters=NoInAddrAny,NoCtldInAddrAny
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$DIR/munge.socket
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MpiDefault=none
StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool
SlurmctldPidFile=$DIR/slurmctld.pid
SlurmdPidFile=$DIR/slurmd.pid
SlurmctldLogFile=$DIR/slurmctld.log
SlurmdLogFile=$DIR/slurmd.log
ReturnToService=2
KillWait=5
MinJobAge=600
NodeName=localhost NodeHostname=$(hostname) NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=rcsim Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
}

start() {
    [ "$(id -u)" -eq 0 ] || die "needs root (munged and slurmd run as root)"
    for t in munged slurmctld slurmd sinfo sbatch; do
        command -v "$t" >/dev/null 2>&1 || die "$t is not installed (scripts/install-deps.sh installs it)"
    done
    mkdir -p "$DIR/state" "$DIR/spool" || die "cannot create $DIR"
    DIR=$(cd "$DIR" && pwd)
    chmod 0700 "$DIR"
    # A fresh key each time: nothing outside DIR can talk to this cluster.
    head -c 1024 /dev/urandom >"$DIR/munge.key" && chmod 0400 "$DIR/munge.key" || die "cannot write the munge key"
    munged --force --socket="$DIR/munge.socket" --key-file="$DIR/munge.key" --pid-file="$DIR/munged.pid" \
        --log-file="$DIR/munged.log" --seed-file="$DIR/munged.seed" || die "munged did not start ($DIR/munged.log)"
    write_conf
    export SLURM_CONF=$DIR/slurm.conf
    slurmctld -f "$SLURM_CONF" || die "slurmctld did not start ($DIR/slurmctld.log)"
    slurmd -f "$SLURM_CONF" -N localhost || die "slurmd did not start ($DIR/slurmd.log)"
    # The node registers within a few seconds; 60 s on a loaded machine.
    for _ in $(seq 120); do
        state=$(sinfo -h -n localhost -o %t 2>/dev/null)
        [ "$state" = idle ] && { echo "one-node-slurm: node idle; export SLURM_CONF=$SLURM_CONF"; return 0; }
        sleep 0.5
    done
    die "the node is not idle after 60 s (state '${state:-}'; $DIR/slurmctld.log, $DIR/slurmd.log)"
}

case $action in
    start) start ;;
    stop) stop ;;
    *) usage ;;
esac
