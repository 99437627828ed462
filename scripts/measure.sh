#!/usr/bin/env bash
# Measures the frame and tooltip against ground truth and writes docs/accuracy.md: every figure in that
# document comes from this script's run, none is typed.
#
#   scripts/measure.sh [--models DIR] [--quick] [--output FILE] [--build DIR]
#
#   --models DIR  canonical models (PCD/PLY, handle from the origin along -Y, effector +X; kind from the
#                 file stem: hoe, hok, rak, sho, sti, ...), e.g. the original lab's 56 CAD models and its 5
#                 real tools. Without it the models are generated, one per family.
#   --models-name TEXT  what those models are, for the document (default: "the N models of MODELS")
#   --quick       a small setting (1 grasp per family, benchmarks briefly, scaling to 30k points) to check the script runs; its
#                 figures are too few to quote. CTest runs it (measure_script).
#   --output FILE default docs/accuracy.md
#   --build DIR   the build holding bin/ and bench/ (default build)
#
# Full setting: about 4 minutes on two cores with the 61 models.
set -euo pipefail
cd "$(dirname "$0")/.."
models="" models_name="" quick=0 output=docs/accuracy.md build=build
while [ $# -gt 0 ]; do
  case $1 in
    --models) models=$2; shift 2 ;;
    --models-name) models_name=$2; shift 2 ;;
    --quick) quick=1; shift ;;
    --output) output=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    *) echo "measure.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done
bin=$build/bin
for tool in evaluate-sessions evaluate-models evaluate-poses generate-tool; do
  [ -x "$bin/$tool" ] || { echo "measure.sh: $bin/$tool not found: build first (scripts/build.sh)" >&2; exit 2; }
done
if [ -n "$models" ] && [ ! -d "$models" ]; then
  echo "measure.sh: --models $models: not a folder" >&2
  exit 2
fi

if [ $quick = 1 ]; then
  grasps=1 any_grasps=1 model_grasps=2 model_sessions=1 bench_time=0.01 bench_cases=1 bench_largest=30000
else
  grasps=16 any_grasps=10 model_grasps=20 model_sessions=5 bench_time=0.5 bench_cases=10 bench_largest=1000000
fi
jobs=$(nproc)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

step() { echo "measure.sh: $*" >&2; }
sessions() {  # name, then evaluate-sessions arguments
  local name=$1
  shift
  step "evaluate-sessions $*"
  "$bin/evaluate-sessions" -q -j "$jobs" "$@" -o "$work/$name.json" >/dev/null
  printf '%s\n' "$*" >"$work/$name.command"
}

sessions elas --grasps $grasps
sessions original --reconstruction original --grasps $grasps
sessions ideal --stereo ideal --grasps $grasps
sessions ideal_any --stereo ideal --grasp any --first-seed 100 --grasps $any_grasps

if [ -z "$models" ]; then
  models=$work/generated
  mkdir -p "$models"
  kinds="{"
  for family in stick hoe hook rake shovel l-stick t-bar flat-top; do
    "$bin/generate-tool" -q --family $family --seed 1 -o "$models/$family.ply"
    kinds+="\"$family\": \"$family\","
  done
  kinds="${kinds%,}}"
  printf '%s' "$kinds" >"$work/kinds.json"
  kind_args=(--kinds "$work/kinds.json")
  models_named="the 8 generated families (generate-tool, seed 1)"
else
  kind_args=()
  models_named=${models_name:-"the $(find "$models" -maxdepth 1 \( -name '*.pcd' -o -name '*.ply' \) | wc -l) models of MODELS"}
fi
step "evaluate-models on $models_named"
"$bin/evaluate-models" -q "$models" "${kind_args[@]}" --grasps $model_grasps -o "$work/models.json" >/dev/null
printf '%s\n' "--grasps $model_grasps" >"$work/models.command"
sessions model_sessions --models "$models" "${kind_args[@]}" --grasps $model_sessions
step "evaluate-poses on $models_named"
"$bin/evaluate-poses" -q "$models" "${kind_args[@]}" --grasps $model_sessions -j "$jobs" -o "$work/poses.json" >/dev/null
printf '%s\n' "--grasps $model_sessions" >"$work/poses.command"

# One core, as the floors are stated; CPU time, which a loaded machine changes less than wall time.
bench() {  # name, filter
  if [ -x "$build/bench/$1" ]; then
    step "$1 $2"
    TOOLINC_BENCH_CASES_PER_FAMILY=$bench_cases taskset -c 0 "$build/bench/$1" --benchmark_filter="$2" --benchmark_min_time=$bench_time \
      --benchmark_out="$work/$1.json" --benchmark_out_format=json >/dev/null 2>&1
  fi
}
bench bench_tool_frame 'BM_FrameAndTooltip'
bench bench_session_pipeline 'BM_CropView|BM_MergeFiveViews|BM_WholePipeline'
bench bench_align_pose 'BM_AlignPose'
if [ -x "$build/bench/bench_peers" ]; then
  step "bench_peers"
  taskset -c 0 "$build/bench/bench_peers" "$bench_time" "$bench_largest" >"$work/bench_peers.txt"
fi

step "writing $output"
python3 scripts/accuracy_tables.py "$work" "$models" "$models_named" >"$work/accuracy.md"
mv "$work/accuracy.md" "$output"
