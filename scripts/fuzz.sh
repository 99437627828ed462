#!/usr/bin/env bash
# Runs every libFuzzer target of a TOOLINC_BUILD_FUZZERS build for SECONDS each (default 60), FUZZ_JOBS
# targets at a time (default: one per core; each target is one process), on a copy of its seed corpus
# (tests/fuzz/corpus/<target>) with the keyword dictionary. A target stops at its first finding (crash,
# leak, timeout, sanitizer report), whose input libFuzzer saves in the work folder; the script fails when
# any target did, after printing each failing log's end.
# Usage: scripts/fuzz.sh BUILD_DIR [SECONDS] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?usage: scripts/fuzz.sh BUILD_DIR [SECONDS] [TARGET...]}
seconds=${2:-60}
shift $(( $# >= 2 ? 2 : 1 ))
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  for binary in "$build"/bin/fuzz/fuzz_*; do targets+=("$(basename "$binary")"); done
fi
jobs=${FUZZ_JOBS:-$(nproc)}
work=${FUZZ_WORK:-$build/fuzz-work}
mkdir -p "$work"

source scripts/run-each.sh

fuzz_one() {
  local target=$1 corpus="$work/corpus/$1" start
  mkdir -p "$corpus"
  if [ -d "tests/fuzz/corpus/$target" ]; then cp -n "tests/fuzz/corpus/$target"/* "$corpus"/ 2>/dev/null || true; fi
  start=$(date +%s)
  # -close_fd_mask=2: the tools' one-line errors would flood the log; libFuzzer's report still shows.
  if "$build/bin/fuzz/$target" "$corpus" -dict=tests/fuzz/toolinc.dict -max_total_time="$seconds" \
       -max_len=65536 -timeout=10 -rss_limit_mb=2048 -close_fd_mask=2 -artifact_prefix="$work/$target-" \
       -print_final_stats=1 >"$work/$target.log" 2>&1; then
    local stats
    stats=$(grep -E '^stat::number_of_executed_units|^#[0-9]+.*DONE' "$work/$target.log" | tr '\n' ' ')
    echo "fuzz: $target ok, $(( $(date +%s) - start )) s: $stats"
  else
    echo "fuzz: $target FAILED after $(( $(date +%s) - start )) s, see $work/$target.log" >&2
    return 1
  fi
}

run_each "$jobs" "$work" fuzz_one "${targets[@]}"
for target in "${failed[@]}"; do
  echo "fuzz: $target's finding:" >&2
  tail -40 "$work/$target.log" >&2
done
[ ${#failed[@]} -eq 0 ]
