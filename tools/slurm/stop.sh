#!/usr/bin/env bash
# Stops the one-node Slurm that tools/slurm/start.sh RUN_DIR started: cancels every job (stopping slurmd does not
# kill running jobs), waits for the queue to empty, then stops slurmd, slurmctld and munged by their saved pids.
# Never kills by name. Safe to run twice, or after a failed start.
# Usage: tools/slurm/stop.sh RUN_DIR
set -uo pipefail
[[ $# -eq 1 ]] || { echo "usage: $0 RUN_DIR" >&2; exit 2; }
[[ -d $1 ]] || { echo "stop.sh: no folder $1" >&2; exit 0; }
run=$(cd "$1" && pwd)
export SLURM_CONF=$run/slurm.conf

# The pid in FILE if that process is still the daemon NAME (a pid can be reused after the daemon died).
live_pid() {
  local file=$run/pids/$1.pid pid
  [[ -s $file ]] || return 1
  pid=$(cat "$file")
  [[ -r /proc/$pid/cmdline ]] || return 1
  tr '\0' ' ' <"/proc/$pid/cmdline" | grep -q -- "$1" || return 1
  echo "$pid"
}

if live_pid slurmctld >/dev/null; then
  scancel --full --quiet --user="$(id -un)" 2>/dev/null || true
  scancel --quiet $(squeue -h -o %A 2>/dev/null) 2>/dev/null || true
  for _ in $(seq 150); do
    [[ -z $(squeue -h 2>/dev/null) ]] && break
    sleep 0.2
  done
fi
for d in slurmd slurmctld munged; do
  pid=$(live_pid "$d") || { rm -f "$run/pids/$d.pid"; continue; }
  kill -TERM "$pid" 2>/dev/null
  for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
  if kill -0 "$pid" 2>/dev/null; then
    echo "stop.sh: $d (pid $pid) ignored TERM for 10 s: KILL" >&2
    kill -KILL "$pid" 2>/dev/null
  fi
  rm -f "$run/pids/$d.pid"
done
echo "slurm: stopped ($run)" >&2
exit 0
