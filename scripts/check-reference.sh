#!/usr/bin/env bash
# For the developers' own check (not part of the tests): frame and tooltip accuracy over the reference
# CAD models in ../shared/reference-models, 20 random grasps each, hand removed, sigma 1.5 mm noise.
# Usage: scripts/check-reference.sh [MODELS_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
models=${1:-../shared/reference-models}
"${BUILD_DIR:-build}/bin/evaluate-models" -q --grasps 20 "$models"/*.pcd
