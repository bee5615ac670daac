#!/bin/sh
# One-node Slurm cluster for tests/campaign_slurm.rs, all state in DIR:
#   sh tests/slurm/cluster.sh start DIR     (prints SLURM_CONF=DIR/slurm.conf)
#   sh tests/slurm/cluster.sh stop DIR
# Needs root and Debian's slurm-wlm + munge (apt-get install -y slurm-wlm munge).
# Private munge socket and key, ports 16817/16818, the node named after this
# host with NodeAddr 127.0.0.1 (no DNS needed), proctrack/linuxproc and
# task/none (no cgroups), no accounting.
set -eu
cmd=$1
dir=$2
stop() {
  for p in slurmd slurmctld munged; do
    if [ -f "$dir/$p.pid" ]; then
      kill "$(cat "$dir/$p.pid")" 2>/dev/null || true
    fi
  done
  # give them a moment, then make sure
  sleep 1
  for p in slurmd slurmctld munged; do
    if [ -f "$dir/$p.pid" ]; then
      kill -9 "$(cat "$dir/$p.pid")" 2>/dev/null || true
      rm -f "$dir/$p.pid"
    fi
  done
}
if [ "$cmd" = stop ]; then stop; exit 0; fi

fail() { echo "slurm test cluster: $*" >&2; exit 1; }
[ "$(id -u)" = 0 ] || fail "needs root (slurmd runs jobs as their user)"
for b in munged slurmctld slurmd sbatch squeue sinfo scontrol; do
  command -v $b >/dev/null 2>&1 || [ -x /usr/sbin/$b ] || fail "$b not found: apt-get install -y slurm-wlm munge"
done
PATH=$PATH:/usr/sbin
mkdir -p "$dir/state" "$dir/spool" "$dir/munge"
chmod 700 "$dir/munge"
# munge: a fresh key and a private socket
dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 2>/dev/null
chmod 400 "$dir/munge/munge.key"
munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.sock" \
  --pid-file="$dir/munged.pid" --log-file="$dir/munge/munged.log" --seed-file="$dir/munge/seed" \
  || fail "munged did not start (see $dir/munge/munged.log)"
host=$(hostname -s 2>/dev/null || hostname)
cpus=$(nproc)
# RealMemory a little below the machine's, so slurmd does not drain the node
mem=$(awk '/MemTotal/ {printf "%d", $2/1024*0.9}' /proc/meminfo)
cat > "$dir/slurm.conf" <<CONF
ClusterName=flanktest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=16817
SlurmdPort=16818
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.sock
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
SchedulerType=sched/backfill
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
MailProg=/bin/true
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$dir/slurm.conf"
slurmctld -f "$SLURM_CONF" || fail "slurmctld did not start (see $dir/slurmctld.log)"
slurmd -f "$SLURM_CONF" -N "$host" || fail "slurmd did not start (see $dir/slurmd.log)"
# wait (at most 60 s) for the node to be idle
i=0
while [ $i -lt 120 ]; do
  state=$(sinfo -h -N -o %t 2>/dev/null | head -1 || true)
  case "$state" in
    idle*) echo "SLURM_CONF=$SLURM_CONF"; exit 0 ;;
    down*|drain*) scontrol update nodename="$host" state=resume 2>/dev/null || true ;;
  esac
  sleep 0.5
  i=$((i + 1))
done
fail "node $host not idle after 60 s (state '$state'; see $dir/slurmctld.log, $dir/slurmd.log)"
