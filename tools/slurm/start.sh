#!/usr/bin/env bash
# Starts a one-node Slurm on loopback (munged, slurmctld, slurmd) with everything under RUN_DIR, and waits until
# the node is idle. The daemons run in the foreground of background jobs, so each saved pid is the daemon's own:
# RUN_DIR/pids/{munged,slurmctld,slurmd}.pid. tools/slurm/stop.sh RUN_DIR stops them by those pids.
# Settings measured to work on a 2-core machine without systemd: docs/cluster.md.
# Usage: tools/slurm/start.sh RUN_DIR     then: export SLURM_CONF=RUN_DIR/slurm.conf (or source RUN_DIR/env)
# Ports: SLURM_CTLD_PORT / SLURMD_PORT, default the first free ones from 6817 / 6818 (several clusters can run).
# SLURM_MAX_ARRAY_SIZE: the cluster's MaxArraySize, default 10001 (tests set a small one to make plans split arrays).
set -euo pipefail
[[ $# -eq 1 ]] || { echo "usage: $0 RUN_DIR" >&2; exit 2; }
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$1"
run=$(cd "$1" && pwd)
for tool in munged mungekey slurmctld slurmd sinfo; do
  command -v "$tool" >/dev/null || { echo "start.sh: $tool not found: run tools/slurm/install.sh" >&2; exit 1; }
done
if [[ -s $run/pids/slurmctld.pid ]] && kill -0 "$(cat "$run/pids/slurmctld.pid")" 2>/dev/null; then
  echo "start.sh: $run already has a running slurmctld (pid $(cat "$run/pids/slurmctld.pid")): stop it first" >&2
  exit 1
fi
rm -rf "$run/state" "$run/spool" "$run/log" "$run/munge" "$run/pids"
mkdir -p "$run/state" "$run/spool" "$run/log" "$run/munge" "$run/pids"
chmod 755 "$run" "$run/munge"  # munged refuses a socket folder others can write to

port_free() { ! ss -Htln "sport = :$1" 2>/dev/null | grep -q .; }
free_port() {
  local p=$1
  while ! port_free "$p" || [[ $p == "${2:-}" ]]; do p=$((p + 2)); done
  echo "$p"
}
ctld_port=${SLURM_CTLD_PORT:-$(free_port 6817)}
slurmd_port=${SLURMD_PORT:-$(free_port 6818 "$ctld_port")}

host=$(hostname -s)
# The node line as slurmd measures it, with RealMemory lowered to 90% so the OS keeps some.
node=$(slurmd -C | head -n 1 | sed -E 's/^NodeName=[^ ]+ //')
mem=$(sed -nE 's/.*RealMemory=([0-9]+).*/\1/p' <<<"$node")
node=$(sed -E "s/RealMemory=[0-9]+/RealMemory=$((mem * 9 / 10))/" <<<"$node")

cat >"$run/slurm.conf" <<CONF
# One-node Slurm on loopback, written by tools/slurm/start.sh
ClusterName=occsweep
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$run/munge/munge.socket.2
StateSaveLocation=$run/state
SlurmdSpoolDir=$run/spool
SlurmctldPidFile=$run/slurmctld.pid
SlurmdPidFile=$run/slurmd.pid
SlurmctldLogFile=$run/log/slurmctld.log
SlurmdLogFile=$run/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$run/log/jobcomp.txt
MpiDefault=none
MailProg=/bin/true
SchedulerType=sched/backfill
# Without batch_sched_delay=0 an array waits about 3 s per scheduling round.
SchedulerParameters=batch_sched_delay=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
# Without a default, CR_Core_Memory gives each job the whole node's memory and jobs run one at a time.
DefMemPerCPU=256
# Without it an impossible request stays pending forever.
EnforcePartLimits=ALL
ReturnToService=2
MinJobAge=600
MaxArraySize=${SLURM_MAX_ARRAY_SIZE:-10001}
NodeName=$host $node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
echo "export SLURM_CONF=$run/slurm.conf" >"$run/env"
export SLURM_CONF=$run/slurm.conf

started=0
fail() {
  echo "start.sh: $*" >&2
  for f in "$run"/log/*.log; do [[ -f $f ]] && { echo "--- $f" >&2; tail -n 20 "$f" >&2; }; done
  ((started)) && bash "$here/stop.sh" "$run" >&2 || true
  exit 1
}

mungekey -c -k "$run/munge/munge.key" >/dev/null 2>&1 || mungekey -c -f -k "$run/munge/munge.key"
chmod 600 "$run/munge/munge.key"
started=1
munged -F --socket="$run/munge/munge.socket.2" --key-file="$run/munge/munge.key" \
  --pid-file="$run/munge/munged.pid" --seed-file="$run/munge/munged.seed" --log-file="$run/log/munged.log" \
  </dev/null >>"$run/log/munged.out" 2>&1 &
echo $! >"$run/pids/munged.pid"
for _ in $(seq 100); do [[ -S $run/munge/munge.socket.2 ]] && break; sleep 0.05; done
[[ -S $run/munge/munge.socket.2 ]] || fail "munged did not create its socket"

slurmctld -D -i </dev/null >>"$run/log/slurmctld.out" 2>&1 &
echo $! >"$run/pids/slurmctld.pid"
slurmd -D </dev/null >>"$run/log/slurmd.out" 2>&1 &
echo $! >"$run/pids/slurmd.pid"

state=""
for _ in $(seq 300); do
  for d in munged slurmctld slurmd; do
    kill -0 "$(cat "$run/pids/$d.pid")" 2>/dev/null || fail "$d exited (see $run/log)"
  done
  state=$(sinfo -h -o %T 2>/dev/null || true)
  [[ $state == idle ]] && break
  sleep 0.1
done
[[ $state == idle ]] || fail "node not idle after 30 s (state '$state')"
echo "slurm: one node ($host, $node) idle; ports $ctld_port/$slurmd_port; pids munged $(cat "$run/pids/munged.pid")" \
  "slurmctld $(cat "$run/pids/slurmctld.pid") slurmd $(cat "$run/pids/slurmd.pid")" >&2
echo "export SLURM_CONF=$run/slurm.conf"
