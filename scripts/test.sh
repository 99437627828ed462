#!/usr/bin/env bash
# The README's test command (CI runs it through .ci/run). Installs the dependencies, checks the
# formatting (scripts/format.sh --check), then, each part timed:
#   1. the Release build, warnings as errors, and every test (CTest);
#   2. a second build with AddressSanitizer + UndefinedBehaviorSanitizer (Clang 14, no recovery, the
#      library instrumented for libFuzzer too) and the whole suite again there, but for the slowest
#      accuracy loops, which exercise no code the rest of the suite does not and already ran in 1
#      (SLOW_ACCURACY below);
#   3. every fuzz target of that build for FUZZ_SECONDS each (default 30) on its seed corpus.
# Between 1 and 2, scripts/slurm-check.sh: the Snakemake workflow through a real one-node Slurm.
# SANITIZE=0 runs 1 (and the Slurm check) only.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh

timed() {
  local name=$1 start
  shift
  start=$(date +%s)
  "$@"
  echo "test.sh: $name took $(( $(date +%s) - start )) s"
}

scripts/format.sh --check

build=${BUILD_DIR:-build}
timed "release build" env CMAKE_ARGS="-DTOOLINC_WARNINGS_AS_ERRORS=ON" scripts/build.sh
timed "release tests" ctest --test-dir "$build" --output-on-failure -j "$(nproc)"
# The workflow through a real one-node Slurm with accounting (root, or sudo; installs and starts daemons
# of its own, stops them at the end). SLURM_CHECK=0 leaves it out.
if [ "${SLURM_CHECK:-1}" != 0 ]; then timed "slurm check" scripts/slurm-check.sh "$build/bin"; fi

if [ "${SANITIZE:-1}" != 0 ]; then
  sanitize=${SANITIZE_BUILD_DIR:-build-sanitize}
  SLOW_ACCURACY='^(ToolFrameAccuracy\.EveryFamilyManyGrasps|AlignPose\.AccuracyOverRandomGraspsOfEveryFamily|SessionPipeline\.EveryFamilyManySessions|MergeViews\.EveryFamilyWithKinematicError|AppearanceAccuracy\.OtherGraspsRecognisedWithBuiltinFeatures|AppearanceAccuracy\.FamilyLeftOutAnsweredUnknown|ToolFrameAccuracy\.RealShapesManyGrasps|ToolMaskAccuracy\.CloserToTheTruthThanTheBlobOnMatchedStereo)$'
  # The install-and-examples test builds a second project against an install, and measure_script runs
  # the evaluate-* executables the accuracy loops already ran: the Release run covers both.
  SLOW_ACCURACY="$SLOW_ACCURACY|^package_install_and_examples$|^measure_script$"
  configure_sanitized() {
    cmake -S . -B "$sanitize" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++-14 \
      -DTOOLINC_SANITIZE=ON -DTOOLINC_BUILD_FUZZERS=ON -DTOOLINC_WARNINGS_AS_ERRORS=ON -DTOOLINC_BUILD_BENCHMARKS=OFF -DTOOLINC_BUILD_PYTHON=OFF >/dev/null
    cmake --build "$sanitize" -j "$(nproc)" --target toolinc_tests fuzzers
  }
  timed "sanitizer build" configure_sanitized
  timed "sanitizer tests" env ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir "$sanitize" --output-on-failure -j "$(nproc)" -E "$SLOW_ACCURACY"
  timed "fuzzing" scripts/fuzz.sh "$sanitize" "${FUZZ_SECONDS:-30}"
fi
