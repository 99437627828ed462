#!/usr/bin/env bash
# Runs every libFuzzer target of a TOOLINC_BUILD_FUZZERS build for SECONDS each (default 60), one at a
# time, on a copy of its seed corpus (tests/fuzz/corpus/<target>) with the keyword dictionary; stops at
# the first finding (crash, leak, timeout, sanitizer report), whose input libFuzzer saves in the
# work folder. Usage: scripts/fuzz.sh BUILD_DIR [SECONDS] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?usage: scripts/fuzz.sh BUILD_DIR [SECONDS] [TARGET...]}
seconds=${2:-60}
shift $(( $# >= 2 ? 2 : 1 ))
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  for binary in "$build"/bin/fuzz/fuzz_*; do targets+=("$(basename "$binary")"); done
fi
work=${FUZZ_WORK:-$build/fuzz-work}
mkdir -p "$work"
for target in "${targets[@]}"; do
  corpus="$work/corpus/$target"
  mkdir -p "$corpus"
  if [ -d "tests/fuzz/corpus/$target" ]; then cp -n "tests/fuzz/corpus/$target"/* "$corpus"/ 2>/dev/null || true; fi
  start=$(date +%s)
  # -close_fd_mask=2: the tools' one-line errors would flood the log; libFuzzer's report still shows.
  if ! "$build/bin/fuzz/$target" "$corpus" -dict=tests/fuzz/toolinc.dict -max_total_time="$seconds" \
       -max_len=65536 -timeout=10 -rss_limit_mb=2048 -close_fd_mask=2 -artifact_prefix="$work/$target-" \
       -print_final_stats=1 >"$work/$target.log" 2>&1; then
    echo "fuzz: $target FAILED after $(( $(date +%s) - start )) s, see $work/$target.log" >&2
    tail -40 "$work/$target.log" >&2
    exit 1
  fi
  stats=$(grep -E '^stat::number_of_executed_units|^#[0-9]+.*DONE' "$work/$target.log" | tr '\n' ' ')
  echo "fuzz: $target ok, $(( $(date +%s) - start )) s: $stats"
done
