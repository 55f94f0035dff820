#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer (issue 8): configures a separate build
# with -DOCCSWEEP_SANITIZE=ON (any sanitizer report aborts the test, -fno-sanitize-recover), builds every test
# program and runs ctest. RelWithDebInfo, not Debug: OctoMap's templates in Debug are ~10x slower and the suite
# would not fit in CI's 10 minutes on 2 cores. Usage:
#   tools/ci/sanitize.sh [BUILD_DIR]          default /tmp/occsweep-sanitize
# Environment: OCCSWEEP_SANITIZE_EXCLUDE = ctest -E regex of tests to skip (default: none);
#              OCCSWEEP_SANITIZE_STEREO = ON|OFF, build the OpenCV stereo tools too (default ON).
set -euo pipefail
cd "$(dirname "$0")/../.."
SRC=$PWD
BUILD=${1:-/tmp/occsweep-sanitize}
JOBS=$(nproc)

# A build folder configured from another checkout (CMake refuses it) is started afresh.
if [ -f "$BUILD/CMakeCache.txt" ] && ! grep -qx "CMAKE_HOME_DIRECTORY:INTERNAL=$SRC" "$BUILD/CMakeCache.txt"; then
  rm -rf "$BUILD"
fi
# -g1 (line tables, enough for the sanitizers' stack traces) instead of -g: a much cheaper build. Asserts stay on.
cmake -S "$SRC" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1" \
  -DOCCSWEEP_SANITIZE=ON \
  -DOCCSWEEP_STEREO="${OCCSWEEP_SANITIZE_STEREO:-ON}" -DBUILD_TESTING=ON >"$BUILD.cmake.log" 2>&1 \
  || { cat "$BUILD.cmake.log"; exit 1; }
start=$(date +%s)
# Only what ctest runs (the command and the test programs), not benchmarks.
targets=$(cmake --build "$BUILD" --target help | grep -Eo "^\.\.\. test_[A-Za-z0-9_]+" | cut -c5- | tr '\n' ' ')
cmake --build "$BUILD" -j"$JOBS" --target occsweep $targets >"$BUILD.build.log" 2>&1 \
  || { grep -E "error|Error" -A3 "$BUILD.build.log" | head -60; exit 1; }
echo "sanitize.sh: built in $(( $(date +%s) - start )) s" >&2

# halt_on_error + abort: a report fails the test that caused it. detect_leaks: leaks are findings too.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
start=$(date +%s)
args=(--test-dir "$BUILD" --output-on-failure -j"$JOBS" --timeout 900)
[ -n "${OCCSWEEP_SANITIZE_EXCLUDE:-}" ] && args+=(-E "$OCCSWEEP_SANITIZE_EXCLUDE")
ctest "${args[@]}"
echo "sanitize.sh: tests ran in $(( $(date +%s) - start )) s, no sanitizer report" >&2
