#!/usr/bin/env bash
# One instrumented build for both sanitizer checks of CI, so the project is compiled once for them:
# clang-14 with AddressSanitizer + UndefinedBehaviorSanitizer (-fno-sanitize-recover: any report aborts) and
# libFuzzer's coverage instrumentation (-fsanitize=fuzzer-no-link), RelWithDebInfo at -O2 -g1 (line tables are
# enough for the reports' stack traces; asserts stay on). tools/ci/sanitize.sh runs the test suite from it,
# tools/ci/fuzz.sh the libFuzzer targets. Installs clang-14 and libclang-rt-14-dev with apt-get when missing.
# Why clang for the test suite too: libFuzzer needs clang, and a second, g++ sanitizer build took 607 s against
# 305-370 s for this one, fuzz targets included, on 2 cores (g++ 12 at -O2 with both sanitizers is about twice as
# slow per file).
# One file at a time, through the compiler cache, so that a clone of the same sources reuses every object another
# clone compiled: CCACHE_BASEDIR makes the paths under the checkout relative, the build folder sits at the same place
# inside every clone (CI uses build-sanitize/), and CCACHE_NOHASHDIR leaves the build folder's absolute path out of
# the hash of objects with line tables (a reused object's line tables then name the folder of the clone that
# compiled it). A unity build is 20 % faster cold (1,340 s against 1,650 s on 2 vCPU) but its generated files
# include the sources by absolute path, so no object of it is ever reused by another clone (docs/robustness.md,
# "CI's time").
# It builds the command, every test program and every fuzz target (not the benchmarks); a second call on the same
# folder only checks that all is up to date. Usage: tools/ci/sanitized_build.sh BUILD_DIR
# Environment: OCCSWEEP_SANITIZE_STEREO = ON|OFF, build the OpenCV stereo tools too (default ON).
set -euo pipefail
SRC=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${1:?usage: sanitized_build.sh BUILD_DIR}

have_fuzzer_lib() { ls /usr/lib/llvm-14/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1; }
if ! command -v clang++-14 >/dev/null || ! have_fuzzer_lib; then
  echo "sanitized_build.sh: installing clang-14 and libclang-rt-14-dev" >&2
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  $SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq clang-14 libclang-rt-14-dev >/dev/null
fi

# The folder is started afresh when an earlier call built it from another checkout (its marker names the checkout's
# real path), so a clean clone gets a clean build, and only the compiler cache carries objects over. A non-empty folder
# without the marker is not this script's and stops it (made before the marker: its configure log beside a cache of
# OCCSWEEP_SANITIZE=ON counts as the marker).
marker="$BUILD/occsweep-sanitized-build.txt"
checkout=$(cd "$SRC" && pwd -P)
made_here() {
  [ -f "$marker" ] || { [ -f "$BUILD/ci-cmake.log" ] && grep -qx "OCCSWEEP_SANITIZE:BOOL=ON" "$BUILD/CMakeCache.txt" 2>/dev/null; }
}
if [ -e "$BUILD" ] && [ -n "$(ls -A "$BUILD")" ]; then
  made_here || { echo "sanitized_build.sh: $BUILD is not a folder this script made; choose another" >&2; exit 2; }
  [ -f "$marker" ] && [ "$(cat "$marker")" == "$checkout" ] || rm -rf "$BUILD"
fi
mkdir -p "$BUILD"
echo "$checkout" >"$marker"
# ccache when installed (docs/robustness.md, "CI's time"); an empty launcher otherwise, so that a folder configured
# while ccache was there still builds once it is gone.
launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=)
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$SRC} CCACHE_NOHASHDIR=1
fi
cmake -S "$SRC" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1" \
  -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link" "${launcher[@]}" \
  -DOCCSWEEP_SANITIZE=ON -DOCCSWEEP_FUZZ=ON -DOCCSWEEP_STEREO="${OCCSWEEP_SANITIZE_STEREO:-ON}" -DCMAKE_UNITY_BUILD=OFF \
  -DBUILD_TESTING=ON >"$BUILD/ci-cmake.log" 2>&1 || { cat "$BUILD/ci-cmake.log"; exit 1; }
targets=$(cmake --build "$BUILD" --target help | grep -Eo "^\.\.\. test_[A-Za-z0-9_]+" | cut -c5- | tr '\n' ' ')
start=$(date +%s)
# shellcheck disable=SC2086 # one word per target
cmake --build "$BUILD" -j"$(nproc)" --target occsweep $targets occsweep_fuzz_all >"$BUILD/ci-build.log" 2>&1 \
  || { grep -E "error|Error" -A3 "$BUILD/ci-build.log" | head -60; exit 1; }
echo "sanitized_build.sh: built in $(( $(date +%s) - start )) s" >&2
