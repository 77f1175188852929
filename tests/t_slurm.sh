#!/bin/sh
# t_slurm.sh - the Slurm job-array recipe on a private one-node cluster started here: shards give one run's bytes; a shard cancelled mid-way and resubmitted with --resume completes the set.
#
# The cluster lives under $T (SLURM_CONF points at it): munged with its own
# key and socket, slurmctld and slurmd on loopback ports free at start, no
# cgroups, no accounting. Every daemon is started here, waited for and
# stopped by its PID on every exit path. Needs root (slurmd runs the jobs)
# and the Debian packages slurmctld slurmd slurm-client munge, which make
# check installs as root: without them the test fails, it never skips.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
for c in munged slurmctld slurmd sbatch squeue scancel scontrol sinfo; do
    command -v "$c" >/dev/null 2>&1 ||
        fail "$c is missing: this test cannot run (apt-get install -y slurmctld slurmd slurm-client munge, or run make check as root)"
done
[ "$(id -u)" = 0 ] || fail "the Slurm test must run as root (slurmd runs the jobs): run make check as root, as CI does"

scratch slurm
chmod 755 "$T"
MUNGED='' CTLD='' SLURMD=''
cleanup() {
    trap '' INT TERM
    # a shard blocked on the FIFO below gets its end of file (and fails)
    [ -p "$T/work/sim/jet_006.csv" ] && timeout 5 sh -c ': >"$1"' sh "$T/work/sim/jet_006.csv" 2>/dev/null
    if [ -n "$CTLD" ] && kill -0 "$CTLD" 2>/dev/null; then
        scancel --full --quiet --user=root 2>/dev/null # jobs first: their steps outlive slurmd
        i=0
        while [ -n "$(squeue -h -o %i 2>/dev/null)" ] && [ $i -lt 150 ]; do sleep 0.2; i=$((i + 1)); done
    fi
    for p in $SLURMD $CTLD $MUNGED; do kill "$p" 2>/dev/null; done
    for p in $SLURMD $CTLD $MUNGED; do wait "$p" 2>/dev/null; done
    rm -rf "$T"
}
trap cleanup EXIT
trap 'exit 1' INT TERM

# poll DESC SECONDS COMMAND...: runs COMMAND every 0.2 s until it succeeds
poll() {
    desc=$1 limit=$(( $2 * 5 )) i=0; shift 2
    until "$@"; do
        i=$((i + 1))
        [ $i -lt $limit ] || { tail -n 20 "$T"/log/*.log 2>/dev/null; fail "timed out waiting for $desc"; }
        sleep 0.2
    done
}

# a TCP port no socket on this machine uses now (loopback only is used)
free_port() {
    while :; do
        n=$(od -An -N2 -tu2 /dev/urandom | tr -d ' ')
        p=$((20000 + n % 30000))
        h=$(printf '%04X' "$p")
        [ "$p" != "${1:-}" ] || continue
        cat /proc/net/tcp /proc/net/tcp6 2>/dev/null | grep -q ":$h " || { echo "$p"; return; }
    done
}

# ---- the cluster --------------------------------------------------------
mkdir -p "$T/munge" "$T/state" "$T/spool" "$T/log" "$T/work"
chmod 755 "$T/munge"
dd if=/dev/urandom of="$T/munge/key" bs=1024 count=1 2>/dev/null
chmod 600 "$T/munge/key"
munged -F --force --key-file="$T/munge/key" --socket="$T/munge/sock" --pid-file="$T/munge/pid" \
    --seed-file="$T/munge/seed" --log-file="$T/log/munged.log" </dev/null >/dev/null 2>&1 &
MUNGED=$!
poll "munged's socket" 30 test -S "$T/munge/sock"

HOST=$(hostname -s)
CPUS=$(nproc 2>/dev/null || echo 1) # never more than the machine has: slurmd would drain the node
[ "$CPUS" -gt 2 ] && CPUS=2
export SLURM_CONF="$T/slurm.conf"
start_slurm() { # writes the configuration with fresh ports, starts both daemons
    P1=$(free_port) && P2=$(free_port "$P1")
    cat >"$SLURM_CONF" <<EOC
ClusterName=jetmeshtest
SlurmctldHost=$HOST(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$T/munge/sock
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerParameters=batch_sched_delay=0
SlurmctldPort=$P1
SlurmdPort=$P2
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/log/slurmctld.log
SlurmdLogFile=$T/log/slurmd.log
ReturnToService=2
KillWait=5
MinJobAge=600
NodeName=$HOST NodeAddr=127.0.0.1 CPUs=$CPUS RealMemory=100 State=UNKNOWN
PartitionName=jetmesh Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOC
    slurmctld -D -i </dev/null >"$T/log/slurmctld.out" 2>&1 &
    CTLD=$!
    slurmd -D </dev/null >"$T/log/slurmd.out" 2>&1 &
    SLURMD=$!
}
node_idle() {
    kill -0 "$CTLD" 2>/dev/null && kill -0 "$SLURMD" 2>/dev/null || return 2
    [ "$(sinfo -h -o %T 2>/dev/null)" = idle ]
}
tries=0
while :; do
    start_slurm
    i=0 up=0
    while [ $i -lt 300 ]; do # 60 s
        node_idle && { up=1; break; }
        [ $? = 2 ] && break # a daemon died (a port taken meanwhile?): try new ports
        sleep 0.2; i=$((i + 1))
    done
    [ $up = 1 ] && break
    for p in $SLURMD $CTLD; do kill "$p" 2>/dev/null; wait "$p" 2>/dev/null; done
    SLURMD='' CTLD=''
    tries=$((tries + 1))
    [ $tries -lt 3 ] || { cat "$T"/log/*.out; tail -n 30 "$T"/log/*.log; fail "the Slurm cluster did not start"; }
done

# no job of ours pending or running (squeue failing is an error, not "none")
queue_empty() {
    q=$(squeue -h -o %i) || fail "squeue failed: the controller is gone"
    [ -z "$q" ]
}
# every task of job $1 in state $2
job_state_is() {
    scontrol -o show job "$1" >"$T/job" 2>&1 || fail "scontrol show job $1"
    ! grep -v "JobState=$2 " "$T/job" | grep -q .
}

# ---- the recipe (README "On a cluster", jetmesh(1) EXAMPLES) --------------
cd "$T/work" || exit 1
mkdir sim
cp "$S"/jet_*.csv sim/
cat >convert.sbatch <<EOJ
#!/bin/sh
#SBATCH --job-name=jetmesh
#SBATCH --cpus-per-task=1
#SBATCH --output=logs/jetmesh_%A_%a.out
$J convert 'sim/jet_%03d.csv' --frames 0:99 -r 0.025 -q --threads "\$SLURM_CPUS_PER_TASK" \\
    -o 'meshes/jet_%03d.glb' --resume \\
    --shard "\$SLURM_ARRAY_TASK_ID/4" --stats "stats/shard_\$SLURM_ARRAY_TASK_ID.csv"
EOJ
mkdir logs
"$J" convert 'sim/jet_%03d.csv' --frames 0:99 -r 0.025 -q -o 'ref/jet_%03d.glb' || fail "single run"
seq 0 99 >"$T/seq"
check() { # the outputs are one run's; the merged stats hold every frame once
    diff -r ref meshes >/dev/null || fail "the shards' outputs differ from a single run's"
    "$J" stats merge stats/shard_*.csv -o stats/all.csv --svg stats/all.svg >"$T/merge.out" 2>&1 ||
        { cat "$T/merge.out"; fail "stats merge"; }
    grep -v '^#' stats/all.csv | tail -n +2 | cut -d, -f1 | cmp -s - "$T/seq" ||
        fail "merged rows are not frames 0..99 once each, in order"
    grep -q '^# summary frames=100$' stats/all.csv || fail "merged summary is not 100 frames"
}

id=$(sbatch --parsable --array=0-3 convert.sbatch) || fail "sbatch"
poll "the array to finish" 180 queue_empty
job_state_is "$id" COMPLETED || { cat "$T/job" logs/*; fail "not every task completed"; }
check
grep -q '^# summary ok=100$' stats/all.csv || fail "merged summary is not 100 ok"

# ---- a shard cancelled mid-way, then resubmitted with --resume -----------
# Shard 2 converts positions 2, 6, 10...; frame 6's input becomes a FIFO
# that nobody writes, so the shard stops there, deterministically, after
# publishing frame 2: then scancel.
for k in $(seq 2 4 98); do rm -f "meshes/jet_$(printf %03d "$k").glb"; done
rm -f stats/shard_2.csv
rm sim/jet_006.csv && mkfifo sim/jet_006.csv
id=$(sbatch --parsable --array=2 convert.sbatch) || fail "sbatch (shard 2)"
poll "shard 2 to publish frame 2" 120 test -f meshes/jet_002.glb
job_state_is "$id" RUNNING || { cat "$T/job"; fail "shard 2 is not running, blocked on the FIFO"; }
scancel "$id" || fail "scancel"
poll "the cancelled shard to end" 120 queue_empty
job_state_is "$id" CANCELLED || { cat "$T/job"; fail "shard 2 was not cancelled"; }
[ ! -e meshes/jet_006.glb ] && [ ! -e meshes/jet_010.glb ] || fail "frames after the stop were published"
[ ! -e stats/shard_2.csv ] || fail "the cancelled shard wrote statistics"
rm sim/jet_006.csv && cp "$S/jet_006.csv" sim/
id=$(sbatch --parsable --array=2 convert.sbatch) || fail "sbatch (shard 2 again)"
poll "the resubmitted shard to finish" 120 queue_empty
job_state_is "$id" COMPLETED || { cat "$T/job" logs/*; fail "the resubmitted shard did not complete"; }
check
grep -q '^# summary ok=99$' stats/all.csv && grep -q '^# summary skipped=1$' stats/all.csv ||
    fail "merged summary is not 99 ok + frame 2 skipped by --resume"
echo "ok"
