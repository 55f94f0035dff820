#!/usr/bin/env bash
# End-to-end test of `occsweep cluster` on a real one-node Slurm (run by tests/sweeps/test_cluster_slurm.cpp, or by hand as
# root):
#  1. installs Slurm when missing, starts it on loopback; stops it on exit, also on failure (trap);
#  2. plans a small reproduction (2 small data sets of the built-in scene, 2 + 3 + 2 sweep shards each) twice: runs one
#     with `run-local --threads 2`, submits the other, waits, checks status;
#  3. removes one sweep shard and blocks its path, so its task fails: status must show it failed, resubmit must
#     submit only it (and the merge and report after it);
#  4. unblocks it, resubmits only it again, waits: everything done.
# The Slurm plan runs as a cluster's plan would, unchanged: a set-up line in every task, an array throttle, the sweep
# stage's own --mem, and a cluster MaxArraySize of 4, which submit reads from `scontrol show config` and splits the
# 14 sweep tasks into arrays of indices below 4 (Slurm refuses any other).
# The caller compares WORK/local/merged, WORK/first-merged and WORK/slurm/merged (identical results expected).
# Usage: slurm_e2e.sh OCCSWEEP_BINARY WORK_DIR
set -euo pipefail
[[ $# -eq 2 ]] || { echo "usage: $0 OCCSWEEP_BINARY WORK_DIR" >&2; exit 2; }
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=$1
work=$2
rm -rf "$work"
mkdir -p "$work"
run=$(mktemp -d /tmp/occsweep-slurm.XXXXXX)
finish() {
  local rc=$?
  if ((rc != 0)); then
    echo "slurm_e2e: FAILED (exit $rc); last lines of the Slurm logs:" >&2
    tail -n 15 "$run"/log/slurmctld.log "$run"/log/slurmd.log >&2 2>/dev/null || true
  fi
  bash "$root/tools/slurm/stop.sh" "$run" || true
  rm -rf "$run"
  exit "$rc"
}
trap finish EXIT
trap 'exit 130' INT TERM HUP  # so that the EXIT trap stops Slurm on these too
fail() { echo "slurm_e2e: $*" >&2; exit 1; }
t0=$SECONDS

bash "$root/tools/slurm/install.sh"
eval "$(SLURM_MAX_ARRAY_SIZE=4 bash "$root/tools/slurm/start.sh" "$run")"
echo "slurm_e2e: Slurm up after $((SECONDS - t0)) s (SLURM_CONF=$SLURM_CONF)"

# Small data sets and grids: what this test shows is Slurm's orchestration, which does not depend on their size, and
# CI's sanitizer build runs it too (with the default scene and the full reduction grid it took 1,003 s there, a
# quarter of the sanitized suite; now about 30 s in Release, mostly Slurm's scheduling). The data sets: the built-in
# scene at 8 scans of 32 x 24 rays, an eighth of the default's points.
plan_args=(--experiment reproduce --name ds0 --name ds1 --unranked
           --generate "scene --out {out} --seed {seed} --scans 8 --width 32 --height 24"
           --generate-out "data/{dataset}" --generate-kind dataset
           --grid "octomap-opt:2" --grid "knn-opt:3" --grid "$work/reduction-small.json:2:grouped" --cpus-per-task 1 --mem 400M
           --time 00:10:00)
# The grouped grid: the reduction grid's parameters at coarser steps (600 combinations, not 112,500, whose results
# are 37 MB of JSON that a sanitizer build reads and writes slowly); grouping works the same on any grid.
cat >"$work/reduction-small.json" <<'GRID'
{
  "name": "reduction-small",
  "method": "knn",
  "description": "slurm_e2e.sh: the reduction grid at coarser steps",
  "parameters": {
    "p_max":   {"min": 0.50, "max": 0.98, "step": 0.48},
    "p_min":   {"min": 0.02, "max": 0.38, "step": 0.36},
    "p_m":     {"min": 0.02, "max": 0.38, "step": 0.36},
    "p_m_out": {"min": 0.02, "max": 0.38, "step": 0.36},
    "p_u":     {"min": 0.02, "max": 0.98, "step": 0.48},
    "p_l":     {"min": 0.02, "max": 0.98, "step": 0.48},
    "p_t":     {"step": 0.12},
    "k":       [1, 3]
  }
}
GRID
"$bin" cluster plan --out "$work/local" "${plan_args[@]}"
"$bin" cluster plan --out "$work/slurm" "${plan_args[@]}" --setup 'echo "set-up line ran on $(hostname)" >&2' \
  --setup 'export OCCSWEEP_E2E=1' --array-throttle 2 --mem sweep=300M
grep -qx "#SBATCH --mem=300M" "$work/slurm/slurm/sweep.sbatch" || fail "the sweep stage has not its own --mem"
grep -qx "#SBATCH --mem=400M" "$work/slurm/slurm/merge.sbatch" || fail "the merge stage has not every stage's --mem"
# Task t of a stage runs at array index t % 4 of the array of offset t - t % 4 (MaxArraySize 4).
array_of() { local t=$1 offset=$(( $1 - $1 % 4 )); if ((offset)); then echo "(--array=$((t % 4))%2, tasks from $offset)"; else echo "(--array=$t%2)"; fi; }

"$bin" cluster run-local "$work/local" --threads 2
"$bin" cluster status "$work/local" || fail "run-local left tasks not done"
echo "slurm_e2e: run-local done after $((SECONDS - t0)) s"

"$bin" cluster submit "$work/slurm" | tee "$work/submit.txt"
for part in "4 of 14 tasks (--array=0-3%2)" "4 of 14 tasks (--array=0-3%2, tasks from 4)" \
            "4 of 14 tasks (--array=0-3%2, tasks from 8)" "2 of 14 tasks (--array=0-1%2, tasks from 12)"; do
  grep -qF "stage sweep: job" "$work/submit.txt" && grep -F "stage sweep: job" "$work/submit.txt" | grep -qF "$part" \
    || fail "submit did not split the sweep stage into arrays within MaxArraySize 4: no '$part'"
done
# The --timeout bounds only end a wait that hangs: a run that finishes returns at once. They are wide because a
# loaded CI machine, or a sanitizer build of occsweep, is several times slower than a quiet Release run, and they
# add up (600 + 240 + 240 s) to less than ctest's 1200 s for the test, so that a hang ends here, where the EXIT trap
# stops Slurm, rather than by ctest killing the test program.
"$bin" cluster status "$work/slurm" --wait --poll 1 --timeout 600 || fail "Slurm run not done"
cp -r "$work/slurm/merged" "$work/first-merged"
ran=$(grep -l "^set-up line ran on " "$work/slurm/logs/"*.out | wc -l)
[[ $ran -ge 1 && $ran -eq $(ls "$work/slurm/logs/"*.out | wc -l) ]] || fail "the set-up line ran in $ran task logs"
echo "slurm_e2e: Slurm run done after $((SECONDS - t0)) s"

# One task fails on purpose: its output path is a folder, so the sweep cannot read or replace it.
victim=sweeps/ds1/knn-opt/shard-1-of-3.json
index=$("$bin" cluster status "$work/slurm" --list-done | sed -n "s|^  done sweep\[\([0-9]*\)\] .* -> $victim\$|\1|p")
[[ -n $index ]] || fail "no sweep task writes $victim"
rm "$work/slurm/$victim"
mkdir "$work/slurm/$victim"
"$bin" cluster resubmit "$work/slurm" | tee "$work/resubmit-1.txt"
grep -q "^stage sweep: job [0-9]*, 1 of 14 tasks " "$work/resubmit-1.txt" && grep -qF "1 of 14 tasks $(array_of "$index")" "$work/resubmit-1.txt" || fail "resubmit did not submit sweep task $index alone"
grep -q "^stage generate" "$work/resubmit-1.txt" && fail "resubmit submitted generation again"
"$bin" cluster status "$work/slurm" --wait --poll 1 --timeout 240 | tee "$work/status-failed.txt" && fail "status says done after a failed task"
grep -q "^stage sweep: 14 tasks: 13 done, 0 running, 0 pending, 1 failed," "$work/status-failed.txt" || fail "status does not count one failed sweep task"
grep -q "^  failed sweep\[$index\] .* -> $victim: slurm FAILED" "$work/status-failed.txt" || fail "status does not show task $index failed"
echo "slurm_e2e: failed task shown after $((SECONDS - t0)) s"

rmdir "$work/slurm/$victim"
"$bin" cluster resubmit "$work/slurm" | tee "$work/resubmit-2.txt"
grep -qF "1 of 14 tasks $(array_of "$index")" "$work/resubmit-2.txt" || fail "second resubmit did not submit task $index alone"
"$bin" cluster status "$work/slurm" --wait --poll 1 --timeout 240 || fail "not done after resubmitting the failed task"
"$bin" cluster resubmit "$work/slurm" | grep -q "nothing to submit" || fail "resubmit of a finished plan submitted work"
echo "slurm_e2e: passed in $((SECONDS - t0)) s"
