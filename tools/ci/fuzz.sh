#!/usr/bin/env bash
# Fuzzes every reader with libFuzzer: the fuzz targets of tools/ci/sanitized_build.sh (clang-14, ASan,
# UBSan; the same build folder as tools/ci/sanitize.sh by default, so CI compiles once for both), each run for a
# fixed time from its seed corpus (tests/fuzz/corpus/NAME, copied: the committed seeds stay as they
# are) plus the inputs of past findings (tests/fuzz/regressions/NAME). Exit 0 only when no target found anything. Usage:
#   tools/ci/fuzz.sh [BUILD_DIR] [SECONDS_PER_TARGET]      defaults: /tmp/occsweep-sanitize, 6 (12 targets, ~75 s)
# By hand, longer: tools/ci/fuzz.sh /tmp/occsweep-sanitize 600; the executions of each run are printed at the end.
set -euo pipefail
cd "$(dirname "$0")/../.."
SRC=$PWD
BUILD=${1:-/tmp/occsweep-sanitize}
SECONDS_EACH=${2:-6}
bash tools/ci/sanitized_build.sh "$BUILD"

status=0
summary=""
for corpus in "$SRC"/tests/fuzz/corpus/*/; do
  name=$(basename "$corpus")
  exe="$BUILD/tests/fuzz/fuzz_$name"
  [ -x "$exe" ] || { echo "fuzz.sh: no target for corpus $name" >&2; status=1; continue; }
  work="$BUILD/corpus-work/$name"; mkdir -p "$work" "$BUILD/findings/$name"
  cp -n "$corpus"/* "$work"/ 2>/dev/null || true
  # Inputs that once crashed a target (tests/fuzz/regressions/NAME) run first, every time.
  cp -n "$SRC/tests/fuzz/regressions/$name"/* "$work"/ 2>/dev/null || true
  log="$BUILD/fuzz_$name.log"
  # -rss_limit_mb / -malloc_limit_mb: a header that makes a reader allocate gigabytes is a finding, not an OOM kill.
  if ! "$exe" "$work" -max_total_time="$SECONDS_EACH" -rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=10 \
       -artifact_prefix="$BUILD/findings/$name/" -print_final_stats=1 >"$log" 2>&1; then
    echo "fuzz.sh: fuzz_$name FOUND A PROBLEM (log $log, input in $BUILD/findings/$name/):" >&2
    grep -E "ERROR|SUMMARY|runtime error|terminate|Test unit written" "$log" | head -20 >&2
    status=1
  fi
  runs=$(grep -Eo "stat::number_of_executed_units: *[0-9]+" "$log" | grep -Eo "[0-9]+$" || echo "?")
  summary+=$(printf "%-14s %10s executions in %ss\n" "$name" "$runs" "$SECONDS_EACH")$'\n'
done
echo "fuzz.sh: results (build $BUILD)"
printf "%s" "$summary"
exit $status
