#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer (issue 8): the instrumented build of
# tools/ci/sanitized_build.sh (clang-14; any sanitizer report aborts the test, -fno-sanitize-recover), then ctest.
# RelWithDebInfo at -O2, not Debug: OctoMap's templates in Debug are ~10x slower and the suite would not fit in
# CI's time on 2 cores. Usage:
#   tools/ci/sanitize.sh [BUILD_DIR]          default /tmp/occsweep-sanitize (tools/ci/fuzz.sh can share it)
# Environment: OCCSWEEP_SANITIZE_EXCLUDE = ctest -E regex of tests to skip (default: none);
#              OCCSWEEP_SANITIZE_STEREO = ON|OFF, build the OpenCV stereo tools too (default ON).
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${1:-/tmp/occsweep-sanitize}
JOBS=$(nproc)
bash tools/ci/sanitized_build.sh "$BUILD"

# halt_on_error + abort: a report fails the test that caused it. detect_leaks: leaks are findings too.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
start=$(date +%s)
args=(--test-dir "$BUILD" --output-on-failure -j"$JOBS" --timeout 1200)
[ -n "${OCCSWEEP_SANITIZE_EXCLUDE:-}" ] && args+=(-E "$OCCSWEEP_SANITIZE_EXCLUDE")
ctest "${args[@]}"
echo "sanitize.sh: tests ran in $(( $(date +%s) - start )) s, no sanitizer report" >&2
