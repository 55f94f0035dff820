#!/usr/bin/env bash
# Regenerates the golden results in results/builtin/ from the code (the sweeps, and the LaTeX of their comparison). Run it only when a change to the numbers is
# intended, then commit the diff with the reason; tests/sweeps/test_golden.cpp checks them on every test run. They are
# made with the direct engine (liboctomap itself for OctoMap), the reference the default replay engine must match.
# Usage: tools/regenerate_golden.sh [BUILD_DIR]   (default: build)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$build/tools/occsweep" scene --out "$tmp/scene"  # the built-in scene with its default settings (seed 1)
for grid in octomap-opt knn-opt; do
  "$build/tools/occsweep" sweep --dataset "$tmp/scene" --grid "$grid" --engine direct --out "$tmp/$grid.json"
  cp "$tmp/$grid.json" "$root/results/builtin/$grid.json"
done
# The LaTeX tables of their comparison (test_compare_statistics compares compare --latex with it).
"$build/tools/occsweep" compare "$root/results/builtin/octomap-opt.json" "$root/results/builtin/knn-opt.json" \
  --latex "$tmp/compare.tex" >/dev/null
cp "$tmp/compare.tex" "$root/results/builtin/compare.tex"
echo "regenerated $root/results/builtin/: review with git diff, then commit"
