#!/bin/bash
# The farm bake on a real Slurm: starts munged, slurmctld and slurmd on this machine (one node, private
# ports, sockets and state under a temporary folder), generates a 1 km x 1 km field, bakes it in 8 shards
# through tools/slurm/submit-bake.sh and checks that the merged file is byte for byte the file of one bake.
#
#   tests/slurm/LocalSlurmBake.sh STRATA_EXECUTABLE [SIZE_M] [SHARDS]
#
# Exit 77 (ctest: skipped) only when Slurm or MUNGE is not installed; tools/scripts/install-deps.sh
# installs both, so CI runs it.
set -euo pipefail

strata=$(realpath -- "$1")
size=${2:-1000}
shards=${3:-8}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)

for program in munged slurmctld slurmd sbatch sinfo; do
  if ! command -v "$program" > /dev/null && ! [ -x "/usr/sbin/$program" ]; then
    echo "skipped: $program is not installed (tools/scripts/install-deps.sh installs Slurm and MUNGE)"
    exit 77
  fi
done
export PATH=$PATH:/usr/sbin

work=$(mktemp -d "${TMPDIR:-/tmp}/strata-slurm.XXXXXX")
pids=()
stop() {
  local status=$?
  for pid in "${pids[@]}"; do kill "$pid" 2> /dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2> /dev/null || true; done
  # munged puts itself in the background: stop it through its pid file, and wait until it is gone.
  if [ -f "$work/munged.pid" ]; then
    local munged_pid
    munged_pid=$(cat "$work/munged.pid")
    kill "$munged_pid" 2> /dev/null || true
    for ((try = 0; try < 100; ++try)); do kill -0 "$munged_pid" 2> /dev/null || break; sleep 0.1; done
  fi
  if [ $status -ne 0 ]; then
    echo "--- logs in $work:"
    for log in "$work"/*.log "$work"/shards/*.log; do [ -f "$log" ] && { echo "== $log"; tail -n 20 "$log"; }; done
  else
    # A daemon's last log line can land while the folder is removed: try again briefly.
    for ((try = 0; try < 20; ++try)); do rm -rf "$work" 2> /dev/null && break; sleep 0.2; done
  fi
  exit $status
}
trap stop EXIT

# Two free ports for the controller and the node daemon: random ones nothing answers on.
free_port() {
  local port
  while true; do
    port=$((20000 + RANDOM % 40000))
    if ! (exec 3<> "/dev/tcp/127.0.0.1/$port") 2> /dev/null; then
      echo "$port"
      return
    fi
  done
}
controller_port=$(free_port)
node_port=$(free_port)
while [ "$node_port" = "$controller_port" ]; do node_port=$(free_port); done
user=$(id -un)
cpus=$(nproc)
mkdir -p "$work/state" "$work/spool" "$work/shards"

# MUNGE authenticates Slurm's messages: a private key and socket, so the machine's own munged (if any) and
# its key are left alone.
head -c 1024 /dev/urandom > "$work/munge.key"
chmod 400 "$work/munge.key"
munged --force --key-file="$work/munge.key" --socket="$work/munge.socket" --pid-file="$work/munged.pid" \
  --log-file="$work/munged.log" --seed-file="$work/munged.seed"

cat > "$work/slurm.conf" << CONF
ClusterName=strata-test
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$controller_port
SlurmdPort=$node_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
AuthInfo=socket=$work/munge.socket
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
SlurmdTimeout=30
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=bake Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$work/slurm.conf

slurmctld -D -c -f "$SLURM_CONF" > "$work/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -N localhost -f "$SLURM_CONF" > "$work/slurmd.out" 2>&1 &
pids+=($!)
for ((try = 0; ; ++try)); do
  state=$(sinfo -h -n localhost -o %T 2> /dev/null || true)
  [ "$state" = "idle" ] && break
  if [ $try -ge 120 ]; then
    echo "the node did not come up (state '$state')"
    exit 1
  fi
  sleep 0.5
done
echo "single-node Slurm up: $(sinfo -h -o '%P %D %c %T')"

level="$work/field.obj"
"$strata" level field --size "$size" --seed 11 --out "$level"
"$strata" navmesh bake "$level" --threads "$cpus" --out "$work/single.bin"
STRATA=$strata "$repo/tools/slurm/submit-bake.sh" --wait "$level" "$work/shards" "$shards" "$work/merged.bin"
ls "$work/shards"
if ! cmp "$work/single.bin" "$work/merged.bin"; then
  echo "the merged navmesh differs from the single bake"
  exit 1
fi
echo "merged $shards shards: $(stat -c %s "$work/merged.bin") bytes, identical to the single bake"
