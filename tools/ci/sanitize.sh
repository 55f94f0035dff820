#!/usr/bin/env bash
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer: the instrumented build of
# tools/ci/sanitized_build.sh (clang-14; any sanitizer report aborts the test, -fno-sanitize-recover), then ctest
# on every test but the long ones of tools/ci/sanitize_skip.txt.
# RelWithDebInfo at -O2, not Debug: OctoMap's templates in Debug are ~10x slower and the suite would not fit in
# CI's time on 2 cores. Usage:
#   tools/ci/sanitize.sh [BUILD_DIR]          default /tmp/occsweep-sanitize (tools/ci/fuzz.sh can share it)
# Environment: OCCSWEEP_SANITIZE_ALL = 1 runs every test (by hand); by default the tests named in
#              tools/ci/sanitize_skip.txt are left out (docs/robustness.md says why, and what covers their code);
#              OCCSWEEP_SANITIZE_EXCLUDE = ctest -E regex of further tests to skip (default: none);
#              OCCSWEEP_SANITIZE_STEREO = ON|OFF, build the OpenCV stereo tools too (default ON).
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${1:-/tmp/occsweep-sanitize}
JOBS=$(nproc)
bash tools/ci/sanitized_build.sh "$BUILD"

# The numbers of the tests to run: all but the skipped ones. A skipped name that ctest does not know is an error, so
# that a renamed test cannot leave a stale line behind.
skip_file=tools/ci/sanitize_skip.txt
declare -A skipped=()
if [[ "${OCCSWEEP_SANITIZE_ALL:-0}" != 1 ]]; then
  while IFS= read -r name; do
    [[ -z "$name" || "$name" == \#* ]] || skipped[$name]=0
  done <"$skip_file"
fi
numbers=()
while IFS= read -r line; do
  [[ "$line" =~ ^\ *Test\ +#([0-9]+):\ (.*)$ ]] || continue
  if [[ -n "${skipped[${BASH_REMATCH[2]}]+set}" ]]; then skipped[${BASH_REMATCH[2]}]=1; else numbers+=("${BASH_REMATCH[1]}"); fi
done < <(ctest --test-dir "$BUILD" -N)
for name in "${!skipped[@]}"; do
  # without the stereo tools (OCCSWEEP_SANITIZE_STEREO=OFF) their tests do not exist
  [[ "${OCCSWEEP_SANITIZE_STEREO:-ON}" == OFF && "$name" == test_stereo_* ]] && continue
  if [[ "${skipped[$name]}" == 0 ]]; then echo "sanitize.sh: $skip_file: no test is named '$name'" >&2; exit 2; fi
done
echo "sanitize.sh: ${#numbers[@]} tests under the sanitizers, ${#skipped[@]} left out ($skip_file)" >&2

# halt_on_error + abort: a report fails the test that caused it. detect_leaks: leaks are findings too.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
start=$(date +%s)
# -I 0,0,0,N,M,...: run exactly the tests numbered N, M, ... (ctest's test-number list)
args=(--test-dir "$BUILD" --output-on-failure -j"$JOBS" --timeout 1200 -I "0,0,0,$(IFS=,; echo "${numbers[*]}")")
[ -n "${OCCSWEEP_SANITIZE_EXCLUDE:-}" ] && args+=(-E "$OCCSWEEP_SANITIZE_EXCLUDE")
ctest "${args[@]}"
echo "sanitize.sh: tests ran in $(( $(date +%s) - start )) s, no sanitizer report" >&2
