#!/usr/bin/env bash
# The experiments of docs/fidelity.md: one per suspect of why our reproduction and the paper disagree.
# Each experiment is a line of tools/fidelity/experiments.txt: a name, the `dataset generate` options it changes,
# and the question it answers. For each, at ci scale on all 20 data sets:
#   occsweep dataset generate --all --scale ci --no-preview OPTIONS --out OUT/NAME/data
#   occsweep reproduce --scale ci --data-root OUT/NAME/data --out OUT/NAME/repro --steps comparison --no-figures
# (the comparison step: octomap-opt and knn-opt on the 1st, median and last set of every data set, under full and
# observable truth), then tools/fidelity/summarize.py writes OUT/summary.md (the tables of docs/fidelity.md),
# OUT/summary.json and OUT/fidelity_*.png. A finished experiment is not redone (delete its folder to redo it).
# Usage: tools/fidelity/experiments.sh OCCSWEEP_BINARY OUT [NAME...]     (default: every experiment)
# About 2-4 minutes an experiment on 2 cores, data generation included (docs/fidelity.md).
set -euo pipefail
[[ $# -ge 2 ]] || { echo "usage: $0 OCCSWEEP_BINARY OUT [NAME...]" >&2; exit 2; }
here=$(cd "$(dirname "$0")" && pwd)
bin=$1 out=$2
shift 2
mkdir -p "$out"
declare -A wanted=()
for n in "$@"; do wanted[$n]=1; done
while IFS=$'\t' read -r name options question; do
  [[ -z $name || $name == \#* ]] && continue
  [[ $options == - ]] && options=""  # a tab is whitespace to `read`: an empty field would vanish, so "-" is none
  ((${#wanted[@]} == 0)) || [[ -n ${wanted[$name]:-} ]] || continue
  dir="$out/$name"
  if [[ -f $dir/repro/comparison.json ]]; then
    echo "experiments: $name done before, kept"
    continue
  fi
  echo "experiments: $name ($question): dataset generate $options"
  t0=$SECONDS
  mkdir -p "$dir"
  if [[ ! -f $dir/data/summary.json ]]; then
    # dataset generate writes each data set whole or not at all, but refuses to add to a folder it did not finish.
    [[ ! -e $dir/data ]] || { echo "experiments: $dir/data is an unfinished generation: delete it to redo" >&2; exit 2; }
    # shellcheck disable=SC2086 # the options are words
    "$bin" dataset generate --all --scale ci --no-preview $options --out "$dir/data" 2>"$dir/generate.log"
  fi
  "$bin" reproduce --scale ci --data-root "$dir/data" --out "$dir/repro" --steps comparison --no-figures --quiet
  printf '%s\t%s\t%s\t%d\n' "$name" "$options" "$question" $((SECONDS - t0)) >"$dir/experiment.tsv"
  echo "experiments: $name done in $((SECONDS - t0)) s"
done <"$here/experiments.txt"
# The Python that has matplotlib, as `occsweep reproduce` looks for it: $OCCSWEEP_PYTHON, /usr/bin/python3, python3.
python=${OCCSWEEP_PYTHON:-/usr/bin/python3}
[[ -x $python ]] || python=python3
"$python" "$here/summarize.py" "$out"
