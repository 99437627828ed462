#!/usr/bin/env bash
# For the developers' own check (not part of the tests): frame and tooltip accuracy over a folder of
# canonical-pose CAD models (.pcd), 20 random grasps each, hand removed, sigma 1.5 mm noise.
# Usage: scripts/check-reference.sh MODELS_DIR
set -euo pipefail
[[ $# -eq 1 && -d $1 ]] || { echo "usage: scripts/check-reference.sh MODELS_DIR (a folder of canonical .pcd models)" >&2; exit 2; }
models=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
"${BUILD_DIR:-build}/bin/evaluate-models" -q --grasps 20 "$models"/*.pcd
