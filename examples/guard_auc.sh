#!/usr/bin/env bash
# A downstream CI step guarding its own AUC numbers with `occsweep results diff` (docs/install.md):
#   guard_auc.sh OCCSWEEP DATASET GOLDEN.json [GRID]
# sweeps DATASET with GRID (default octomap-opt) into a temporary file and compares it with GOLDEN.json: exit 0
# when every combination of the golden file is there with the same counts (and AUCs within --auc-tolerance),
# otherwise the table of what changed and exit 1. Make the golden file once with the same sweep, and commit it.
set -euo pipefail
[[ $# -ge 3 ]] || { echo "usage: $0 OCCSWEEP DATASET GOLDEN.json [GRID]" >&2; exit 2; }
occsweep=$1 dataset=$2 golden=$3 grid=${4:-octomap-opt}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$occsweep" sweep --quiet --dataset "$dataset" --grid "$grid" --out "$work/new.json"
"$occsweep" results diff "$golden" "$work/new.json" --auc-tolerance 1e-12
