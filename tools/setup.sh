#!/usr/bin/env bash
# Set-up for a fresh Debian 12 machine: installs what is missing (apt-get), builds (Release), then
#   run:  the main job on the built-in scene (out/demo/)
#   test: every test with ctest (installs the test-only packages too)
# Usage: tools/setup.sh run|test   (BUILD_DIR overrides the build folder, default build/)
set -euo pipefail
mode=${1:-}
[[ "$mode" == run || "$mode" == test ]] || { echo "usage: $0 run|test" >&2; exit 2; }
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}

# opencv-doc: the Middlebury Aloe stereo pair of `occsweep dataset middlebury` and its test (docs/datasets.md)
packages=(g++ cmake make git pkg-config liboctomap-dev libnanoflann-dev libeigen3-dev libtbb-dev nlohmann-json3-dev
          catch2 libcli11-dev libpng-dev libsqlite3-dev python3-matplotlib python3-numpy python3-scipy
          libopencv-calib3d-dev libopencv-imgproc-dev libjpeg-dev opencv-doc)
# The test command only: PCL 1.13, the oracle that test_point_filters_pcl checks methods/outlier_filters/.../point_filters.hpp against
# (docs/methods.md, outlier filters): about 280 packages, 140 MB to download, 870 MB installed, 30 s to install
# (download included) on this project's machine kind. `run` never needs it: the filters are header-only, on nanoflann.
# And pdflatex with booktabs, which test_compare_statistics compiles `compare --latex` with (docs/statistics.md): 17
# packages, 48 MB, 26 s. With them the oracles of the table-escaping test (test_robust_outputs): pdftotext reads the
# compiled names back, markdown-it-py is a CommonMark parser with GitHub's tables (docs/statistics.md, "In occsweep compare").
test_packages=(libpcl-dev texlive-latex-base texlive-latex-recommended poppler-utils python3-markdown-it)
if [[ "$mode" == test ]]; then packages+=("${test_packages[@]}"); fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  [[ $(id -u) -eq 0 ]] || sudo=sudo
  echo "installing: ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# A compiler cache when one is installed (CI installs ccache): paths under the checkout are hashed relative to it,
# so another clone of the same sources reuses the objects (docs/robustness.md, "CI's time").
launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=)  # empty: a build folder configured while ccache was there still builds
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$root}
fi
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" >/dev/null
if [[ "$mode" == test ]]; then
  cmake --build "$build" -j "$(nproc)"
  cd "$build" && ctest --output-on-failure -j "$(nproc)"
  exit
fi
cmake --build "$build" -j "$(nproc)" --target occsweep

# The main job: the built-in scene, both optimisation grids, the best AUC of each method; then every experiment of
# the paper's Section 4 at ci scale (report, JSON and five figures in out/repro/; about 3-6 minutes on 2 cores).
occsweep="$build/tools/occsweep"
out="$root/out/demo"
mkdir -p "$out"
# --force: a re-run replaces its own previous outputs (occsweep refuses to replace anything else, even then).
"$occsweep" scene --force --out "$out/scene"
"$occsweep" map --force --dataset "$out/scene" --method octomap --out "$out/octomap.ot"
"$occsweep" map --force --dataset "$out/scene" --method knn --out "$out/knn.ot"
"$occsweep" sweep --dataset "$out/scene" --grid octomap-opt --out "$out/octomap-opt.json"
"$occsweep" sweep --dataset "$out/scene" --grid knn-opt --out "$out/knn-opt.json"
"$occsweep" compare "$out/octomap-opt.json" "$out/knn-opt.json" --force --json "$out/comparison.json"
"$occsweep" reproduce --scale ci --out "$root/out/repro"
echo "results in $out and $root/out/repro (report.md, fig*.png)"
