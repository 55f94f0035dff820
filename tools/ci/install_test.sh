#!/usr/bin/env bash
# The install test of docs/install.md, run by CI after the README's test command:
#   install_test.sh BUILD_DIR
# installs into a temporary prefix, hides the source tree's grids, runs the installed command from another folder
# (grid count, the built-in scene, a sweep), then builds examples/ against the installed package and runs it and
# its AUC guard, and sweeps the example method (examples/occupancy_method) and compares it with OctoMap.
# Exit 0 only when every step does.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:?usage: install_test.sh BUILD_DIR}" && pwd)
work=$(mktemp -d)
prefix="$work/prefix"
hidden="$root/sweeps/.grids-hidden-by-install-test"
restore() { [[ -d "$hidden" ]] && mv "$hidden" "$root/sweeps/grids"; rm -rf "$work"; }
trap restore EXIT

cmake --install "$build" --prefix "$prefix" >/dev/null
mv "$root/sweeps/grids" "$hidden"  # the installed command must not need the source tree
unset OCCSWEEP_GRIDS
cd "$work"
occsweep="$prefix/bin/occsweep"
echo "== installed: $(find "$prefix" -type f | wc -l) files under $prefix"
"$occsweep" grid count knn-opt
"$occsweep" scene --out "$work/scene"
"$occsweep" sweep --quiet --dataset "$work/scene" --grid octomap-opt --out "$work/octomap-opt.json"
"$occsweep" results check "$work/octomap-opt.json"

echo "== examples/ against the installed package"
cmake -S "$root/examples" -B "$work/example-build" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/example-build" -j "$(nproc)" >/dev/null
"$work/example-build/knn_counts" "$work/scene"
"$root/examples/guard_auc.sh" "$occsweep" "$work/scene" "$work/octomap-opt.json"
echo "== a method of the example's own: registered, swept, compared by the installed command"
"$work/example-build/sweep_example_method" "$work/scene" "$root/examples/occupancy_method/density-octomap-opt.json" \
  "$work/density-octomap.json"
"$occsweep" compare "$work/octomap-opt.json" "$work/density-octomap.json" | tee "$work/compare.txt"
grep -qE "^  density-octomap +AUC [0-9]" "$work/compare.txt"
echo "== install test passed"
