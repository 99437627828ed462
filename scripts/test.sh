#!/usr/bin/env bash
# The README's test command (CI runs it through .ci/run). Installs the dependencies, checks the
# formatting (scripts/format.sh --check), then, each part timed:
#   1. the Release build, warnings as errors, and every test (CTest: unit, integration, accuracy);
#   2. scripts/slurm-check.sh: the Snakemake workflow through a real one-node Slurm;
#   3. a second build with AddressSanitizer + UndefinedBehaviorSanitizer (Clang 14, no recovery, the
#      library instrumented for libFuzzer too) and the `unit` tests there, each test runner whole
#      (scripts/runner-tests.sh: a suite sets up once, not once per test): the readers, writers, every
#      executable on good and bad input, and every fuzz target's seeds. The accuracy loops run in 1 only:
#      they exercise no code the unit tests do not, and their bounds are about the method, not memory;
#   4. every fuzz target of that build for FUZZ_SECONDS each (default 20) on its seed corpus.
# Both builds compile through ccache (installed by scripts/install-deps.sh), so a fresh clone rebuilds
# only what differs from the last build on this machine.
#
#   scripts/test.sh           everything (CI)
#   scripts/test.sh --quick   the check for a working session: formatting, the Release build, `ctest -L unit`
# SANITIZE=0 leaves out 3 and 4, SLURM_CHECK=0 leaves out 2.
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
case "${1:-}" in
  --quick) quick=1 ;;
  "") ;;
  *) echo "usage: scripts/test.sh [--quick]" >&2; exit 2 ;;
esac
scripts/install-deps.sh

parts=()
timed() {
  local name=$1 start
  shift
  start=$(date +%s)
  "$@"
  parts+=("$name $(( $(date +%s) - start )) s")
  echo "test.sh: $name took $(( $(date +%s) - start )) s"
}
summary() { printf 'test.sh: %s\n' "${parts[@]}"; }
trap summary EXIT

timed "format" scripts/format.sh --check

build=${BUILD_DIR:-build}
timed "release build" env CMAKE_ARGS="-DTOOLINC_WARNINGS_AS_ERRORS=ON" scripts/build.sh
if [ "$quick" = 1 ]; then
  timed "unit tests" ctest --test-dir "$build" --output-on-failure -j "$(nproc)" -L unit
  exit 0
fi
timed "release tests" ctest --test-dir "$build" --output-on-failure -j "$(nproc)"
# Installs and starts daemons of its own (root, or sudo), stops them at the end.
if [ "${SLURM_CHECK:-1}" != 0 ]; then timed "slurm check" scripts/slurm-check.sh "$build/bin"; fi

if [ "${SANITIZE:-1}" != 0 ]; then
  sanitize=${SANITIZE_BUILD_DIR:-build-sanitize}
  configure_sanitized() {
    cmake -S . -B "$sanitize" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++-14 \
      -DTOOLINC_SANITIZE=ON -DTOOLINC_BUILD_FUZZERS=ON -DTOOLINC_WARNINGS_AS_ERRORS=ON -DTOOLINC_BUILD_BENCHMARKS=OFF -DTOOLINC_BUILD_PYTHON=OFF >/dev/null
    cmake --build "$sanitize" -j "$(nproc)" --target toolinc_tests fuzzers
  }
  timed "sanitizer build" configure_sanitized
  # The unit tests that push whole batches of sessions or models through the executables (evaluate-sessions,
  # evaluate-poses, the workflow managers, every output against its schema, the shipped configs) run in the
  # Release pass only: under the sanitizers they took 16 of the pass's 33 CPU-minutes, on code the other unit
  # tests run under the sanitizers too. The GoogleTest runners run whole (scripts/runner-tests.sh), the other
  # unit tests (each fuzz target on its seeds) through CTest.
  batches='*EvaluateSessions*:Snakemake.ThreeSessions*:Snakemake.FailedSessions*:AppearanceCli.FeatureDatabaseRoundTrip*'
  batches+=':AppearanceCli.TrainThenClassify*:Realism.ExecutableTables*:EvaluatePoses.TableAndJson*:ConfigDefaults.RecordShippedConfig*'
  sanitized_tests() (
    export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1
    scripts/runner-tests.sh "$sanitize" "-*Accuracy.*:$batches"
    ctest --test-dir "$sanitize" --output-on-failure -j "$(nproc)" -L unit -R '^fuzz_'
  )
  timed "sanitizer tests" sanitized_tests
  timed "fuzzing" scripts/fuzz.sh "$sanitize" "${FUZZ_SECONDS:-20}"
fi
