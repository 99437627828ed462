#!/usr/bin/env bash
# The README's main command: installs the dependencies, builds, and runs the tool-frame pipeline
# (estimate-frame -> find-tooltip -> evaluate against the ground truth) on the embedded sample clouds
# in data/held/. Results go to ${OUT_DIR:-out/demo}.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh >/dev/null
bin=${BUILD_DIR:-build}/bin
out=${OUT_DIR:-out/demo}
mkdir -p "$out"
printf '%-9s %-32s %s\n' tool "tooltip (hand frame, m)" "error vs ground truth"
for cloud in data/held/*.ply; do
  tool=$(basename "$cloud" .ply)
  "$bin/estimate-frame" -q "$cloud" -o "$out/$tool.frame.json"
  "$bin/find-tooltip" -q "$cloud" --frame "$out/$tool.frame.json" -o "$out/$tool.tooltip.json"
  "$bin/evaluate" -q --truth "data/held/$tool.truth.json" --frame "$out/$tool.frame.json" \
    --tooltip "$out/$tool.tooltip.json" -o "$out/$tool.evaluation.json"
  position=$(tr -d ' \n' <"$out/$tool.tooltip.json" | sed -E 's/.*"position":\[([^]]*)\].*"position_in_tool_frame".*/\1/' |
    awk -F, '{printf "(%.4f, %.4f, %.4f)", $1, $2, $3}')
  error=$(tr -d ' \n' <"$out/$tool.evaluation.json" | sed -E 's/.*"tooltip":\{[^}]*"error_m":([-0-9.e]+).*/\1/')
  printf '%-9s %-32s %.1f mm\n' "$tool" "$position" "$(awk -v e="$error" 'BEGIN{print e*1000}')"
done
echo "Results (tool_frame, tooltip and evaluation JSON per tool) are in $out/"
