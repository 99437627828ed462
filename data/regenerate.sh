#!/usr/bin/env bash
# Regenerates the sample held-tool clouds in data/held/ (hand frame, hand removed, sigma 1.5 mm noise)
# and their ground truth, with the project's own generator. Usage: data/regenerate.sh [BIN_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=$(cd "${1:-$here/../build/bin}" && pwd)
cd "$here"  # relative paths, so the files' provenance comments do not depend on the checkout's location
mkdir -p held
grasp=1
for family in hoe hook rake shovel stick l-stick t-bar flat-top; do
  "$bin/generate-tool" -q --family "$family" --seed 1 --spacing 0.0025 --grasp-seed "$grasp" \
    --truth "held/$family.truth.json" -o "held/$family.ply"
  grasp=$((grasp + 1))
done
