#!/usr/bin/env bash
# Runs each GoogleTest runner of a build (tests/toolinc_<area>_tests) whole, with a gtest filter, one runner
# per core (RUNNER_JOBS), the longest first; prints each failing runner's log and fails when any did.
# Whole runners, not CTest's one process per test: a suite that sets up once for all its tests (a simulated
# session through the pipeline, a trained classifier) then does so once. Under the sanitizers that is 850
# CPU-seconds against CTest's 1290 for the same tests.
# Usage: scripts/runner-tests.sh BUILD_DIR GTEST_FILTER
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?usage: scripts/runner-tests.sh BUILD_DIR GTEST_FILTER}
filter=${2:?usage: scripts/runner-tests.sh BUILD_DIR GTEST_FILTER}
jobs=${RUNNER_JOBS:-$(nproc)}
logs=$build/runner-logs
mkdir -p "$logs"

# Longest first under the sanitizers (measured); a runner not listed goes last.
runners=()
for area in geometry io sim appearance session record report workflow; do
  [ -x "$build/tests/toolinc_${area}_tests" ] && runners+=("toolinc_${area}_tests")
done
for binary in "$build"/tests/toolinc_*_tests; do
  name=$(basename "$binary")
  [[ " ${runners[*]} " == *" $name "* ]] || runners+=("$name")
done

source scripts/run-each.sh

run_one() {
  local runner=$1 start
  start=$(date +%s)
  if timeout 1800 "$build/tests/$runner" --gtest_filter="$filter" >"$logs/$runner.log" 2>&1; then
    echo "tests: $runner ok, $(grep -oE '^\[  PASSED  \] [0-9]+' "$logs/$runner.log" | grep -oE '[0-9]+$') passed, $(( $(date +%s) - start )) s"
  else
    echo "tests: $runner FAILED after $(( $(date +%s) - start )) s, see $logs/$runner.log" >&2
    return 1
  fi
}

run_each "$jobs" "$logs" run_one "${runners[@]}"
for runner in "${failed[@]}"; do
  # Each failed test's output; a runner that crashed (a sanitizer's report) failed no test: its log's end.
  echo "tests: $runner's failures:" >&2
  awk '/^\[ RUN      \]/ {block = ""; open = 1} open {block = block $0 "\n"}
       /^\[       OK \]/ {open = 0} /^\[  FAILED  \].*ms\)$/ {printf "%s", block; open = 0; shown = 1}
       END {exit !shown}' "$logs/$runner.log" >&2 || tail -80 "$logs/$runner.log" >&2
done
[ ${#failed[@]} -eq 0 ]
