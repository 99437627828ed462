#!/usr/bin/env bash
# The README's main command: installs the dependencies, builds, and runs the pipeline on the embedded
# sample data:
#  1. the sample held-tool clouds in data/held/: estimate-frame -> find-tooltip -> evaluate;
#  2. sample recorded sessions, simulated with known ground truth: simulate-session, then
#     scripts/pipeline.mk: crop-cloud --all -> merge-views -> estimate-frame -> find-tooltip -> evaluate,
#     render (the model, and a contact sheet of the session's views) and report (one HTML page per session).
# Results go to ${OUT_DIR:-out/demo}.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh >/dev/null
bin=${BUILD_DIR:-build}/bin
out=${OUT_DIR:-out/demo}
rm -rf "$out"
mkdir -p "$out/held" "$out/sessions"

json_vector() {  # json_vector FILE KEY: the first "KEY": [x, y, z] of FILE as (x, y, z) in metres
  tr -d ' \n' <"$1" | sed -E "s/^.*\"$2\":\[([-0-9.e]+),([-0-9.e]+),([-0-9.e]+)\].*$/\1 \2 \3/" |
    awk '{printf "(%.4f, %.4f, %.4f)", $1, $2, $3}'
}
json_error_mm() {  # json_error_mm EVALUATION.json: the tooltip error in mm
  tr -d ' \n' <"$1" | sed -E 's/^.*"tooltip":\{[^}]*"error_m":([-0-9.e]+).*$/\1/' | awk '{printf "%.1f mm", $1 * 1000}'
}

echo "== 1. Sample held-tool clouds (data/held/): tool frame and tooltip"
printf '%-9s %-28s %s\n' tool "tooltip (hand frame, m)" "error vs ground truth"
for cloud in data/held/*.ply; do
  tool=$(basename "$cloud" .ply)
  "$bin/estimate-frame" -q "$cloud" -o "$out/held/$tool.frame.json"
  "$bin/find-tooltip" -q "$cloud" --frame "$out/held/$tool.frame.json" -o "$out/held/$tool.tooltip.json"
  "$bin/evaluate" -q --truth "data/held/$tool.truth.json" --frame "$out/held/$tool.frame.json" \
    --tooltip "$out/held/$tool.tooltip.json" -o "$out/held/$tool.evaluation.json"
  printf '%-9s %-28s %s\n' "$tool" "$(json_vector "$out/held/$tool.tooltip.json" position)" \
    "$(json_error_mm "$out/held/$tool.evaluation.json")"
done

echo
echo "== 2. Recorded sessions (simulated): crop, merge, frame, tooltip"
seed=1
for family in hoe hook rake; do
  "$bin/simulate-session" -q --family "$family" --seed "$seed" --label "$family" -o "$out/sessions/$family"
  seed=$((seed + 1))
done
make -s -f scripts/pipeline.mk SESSIONS="$out/sessions" OUT="$out/pipeline" BIN="$bin" -j "$(nproc)"
printf '%-9s %-16s %-28s %s\n' session "views merged" "tooltip (hand frame, m)" "error vs ground truth"
for family in hoe hook rake; do
  result=$out/pipeline/$family
  merged=$(grep -c '"accepted": true' "$result/merge_report.json")
  printf '%-9s %-16s %-28s %s\n' "$family" "$merged of $(grep -c '"file"' "$result/merge_report.json")" \
    "$(json_vector "$result/tooltip.json" position)" "$(json_error_mm "$result/evaluation.json")"
done
echo
echo "Outputs: $out/held/ (frame, tooltip, evaluation per sample cloud); $out/sessions/ (the simulated"
echo "sessions); $out/pipeline/<session>/ (views/, model.ply, merge_report.json, frame.json, tooltip.json,"
echo "evaluation.json, model.png: the model with its frame and tooltip in four views, sheet.png: the"
echo "session's views, and report.html: all of it on one page)."
echo "Look at the results in a browser: $out/pipeline/{hoe,hook,rake}/report.html"
