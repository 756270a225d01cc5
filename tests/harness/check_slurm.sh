#!/bin/sh
# SPDX-License-Identifier: MIT
# A sweep on a real Slurm scheduler through tools/slurm/sweep, as a user runs one past a single
# machine: munged, slurmctld and slurmd started for one local node from a configuration
# generated in a temporary folder; a small sweep (two models, two time steps, on the liver, a
# tenth of a second) submitted as a 2-task array behind the reference job, merged behind it; the
# merged table must equal the same sweep run unsharded here (same run ids, the same error values
# bit for bit; timings aside), and the reference must have been computed once, by the first job.
# Every daemon it started is stopped. Exits 77 (skipped) where Slurm or munge is not installed or
# cannot start; scripts/setup installs them.
# Usage: check_slurm.sh SOFTBENCH (from the repository root).
softbench="$(realpath "$1")"
for tool in munged slurmctld slurmd sbatch sinfo; do
  if ! command -v "$tool" > /dev/null 2>&1 && ! [ -x "/usr/sbin/$tool" ]; then
    echo "skipped: $tool is not installed (scripts/setup installs slurmctld, slurmd, slurm-client, munge)"
    exit 77
  fi
done
PATH="$PATH:/usr/sbin"
key=/etc/munge/munge.key
if ! [ -r "$key" ]; then
  echo "skipped: no readable munge key at $key"
  exit 77
fi
work=$(mktemp -d)
stop() {
  for daemon in slurmd slurmctld munged; do
    if [ -s "$work/$daemon.pid" ]; then
      kill "$(cat "$work/$daemon.pid")" 2> /dev/null
    fi
  done
  sleep 1
  rm -rf "$work"
}
trap stop EXIT
host=$(hostname)
port=$((20000 + $$ % 20000))
mkdir -p "$work/state" "$work/spool"
cat > "$work/slurm.conf" <<CONF
ClusterName=softbench-test
SlurmctldHost=$host
SlurmUser=$(id -un)
SlurmdUser=$(id -un)
AuthType=auth/munge
AuthInfo=socket=$work/munge.socket
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldPort=$port
SlurmdPort=$((port + 1))
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/builtin
SchedulerParameters=sched_interval=2
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
NodeName=$host CPUs=$(nproc) RealMemory=$(free -m | awk '/^Mem:/ {print $2}') State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$work/slurm.conf"
munged --force --socket="$work/munge.socket" --pid-file="$work/munged.pid" \
  --log-file="$work/munged.log" --seed-file="$work/munge.seed" --key-file="$key" \
  || { echo "skipped: munged cannot start"; exit 77; }
slurmctld -f "$SLURM_CONF" && slurmd -f "$SLURM_CONF" \
  || { echo "skipped: slurmctld or slurmd cannot start"; exit 77; }
tries=0
until sinfo -h -o %T 2> /dev/null | grep -q idle; do
  tries=$((tries + 1))
  if [ $tries -gt 30 ]; then
    echo "skipped: the node did not come up in 30 s"; tail -5 "$work/slurmctld.log" "$work/slurmd.log"
    exit 77
  fi
  sleep 1
done

sed -e 's/"duration": 3.5/"duration": 0.1/' -e 's/"name": "liver_gravity"/"name": "slurm_sweep"/' \
    -e 's|"mesh": "data/|"mesh": "'"$PWD"'/scenes/data/|' \
    scenes/liver_gravity.json > "$work/scene.json"
grep -q '"duration": 0.1' "$work/scene.json" || { echo "the scene edit did not take"; exit 1; }
set -- --model corotational_fem --model mass_spring --param model.dt=1/60,1/120 \
  --reference-model corotational_fem --reference-substeps 2 --no-plots

started=$(date +%s.%N)
tools/slurm/sweep --shards 2 --out "$work/cluster" --softbench "$softbench" --wait \
  "$work/scene.json" "$@" || { echo "the sharded sweep failed:"; cat "$work"/cluster/logs/*; exit 1; }
sharded=$(echo "$(date +%s.%N) - $started" | bc)
started=$(date +%s.%N)
OMP_NUM_THREADS=1 "$softbench" sweep "$work/scene.json" "$@" --out "$work/single" > /dev/null 2>&1 \
  || { echo "the unsharded sweep failed"; exit 1; }
unsharded=$(echo "$(date +%s.%N) - $started" | bc)
echo "sharded (2 tasks, through Slurm): ${sharded} s; unsharded: ${unsharded} s"

python3 - "$work/cluster/merged/sweep.csv" "$work/single/sweep.csv" <<'PY' || exit 1
import csv, sys
timing = {"steps_per_second", "realtime_factor"}
def table(path):
    with open(path, newline="") as f:
        return {row["id"]: {k: v for k, v in row.items() if k not in timing}
                for row in csv.DictReader(f)}
merged, single = table(sys.argv[1]), table(sys.argv[2])
if len(single) != 4:
    sys.exit("expected 4 runs unsharded, got %d" % len(single))
if merged != single:
    sys.exit("the merged table differs from the unsharded one:\n%s\n%s" % (merged, single))
PY
# Computed once: the reference and the finer run that checked it in the shared folder, written
# by the reference job; no shard computed its own.
count=$(find "$work/cluster/reference" -name '*.json' | wc -l)
[ "$count" -eq 2 ] || { echo "expected the reference and its check (2 files), found $count"; exit 1; }
grep -q "reference ready" "$work/cluster/logs/reference.log" || { echo "no reference job output"; exit 1; }
for shard in 0 1; do
  [ ! -e "$work/cluster/shard_$shard/reference" ] || { echo "shard $shard computed a reference"; exit 1; }
done
echo "merged table equals the unsharded one; the reference was computed once"
