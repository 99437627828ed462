#!/usr/bin/env bash
# For the developers' own check (not part of the tests): align-pose accuracy over folders of canonical-pose
# models (.pcd), 5 random grasps each (any turn about the handle), one rendered partial view per grasp.
# Usage: scripts/check-poses.sh MODELS_DIR... (extra evaluate-poses options in EVALUATE_POSES_OPTIONS)
set -euo pipefail
[[ $# -ge 1 ]] || { echo "usage: scripts/check-poses.sh MODELS_DIR... (folders of canonical .pcd models)" >&2; exit 2; }
models=()
for dir in "$@"; do
  [[ -d $dir ]] || { echo "scripts/check-poses.sh: $dir: not a folder" >&2; exit 2; }
  dir=$(cd "$dir" && pwd)
  models+=("$dir"/*.pcd)
done
cd "$(dirname "$0")/.."
# shellcheck disable=SC2086
"${BUILD_DIR:-build}/bin/evaluate-poses" -q --grasps 5 -j "${JOBS:-2}" ${EVALUATE_POSES_OPTIONS:-} "${models[@]}"
