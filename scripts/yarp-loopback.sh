#!/usr/bin/env bash
# Loopback check of record's YARP adapter without a robot (README "Recording on the robot"): a private
# yarpserver on 127.0.0.1, toolinc-yarp-fakes standing in for the camera, the stereo module and the blob
# detector (publishing view 0 of a session simulated here), then
#   1. record with the controllers: they are absent here (icub-main), which must be one clear error;
#   2. record --static-poses: one view captured through the ports, compared with what was published.
# It runs what a YARP-enabled build made; it builds nothing.
#
# usage: scripts/yarp-loopback.sh BUILD_DIR [WORK_DIR]
#   BUILD_DIR: configured with -DTOOLINC_WITH_YARP=ON and built (targets record, toolinc-yarp-fakes,
#   crop-cloud); yarpserver and yarp on PATH.
set -euo pipefail

BIN=$(cd "$1/bin" && pwd)
WORK=${2:-$(mktemp -d /tmp/toolinc-yarp-loopback.XXXXXX)}
mkdir -p "$WORK"
# A private YARP configuration, so the name server found is this one.
export YARP_CONFIG_HOME=$WORK/yarp-config
PORT=${YARP_LOOPBACK_PORT:-10111}
pids=()
cleanup() { for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done; wait 2>/dev/null || true; }
trap cleanup EXIT

yarpserver --ip 127.0.0.1 --socket "$PORT" --write --silent >"$WORK/yarpserver.log" 2>&1 &
pids+=($!)
for _ in $(seq 50); do yarp detect >/dev/null 2>&1 && break; sleep 0.2; done
yarp detect >/dev/null 2>&1 || { echo "yarpserver did not start (see $WORK/yarpserver.log)" >&2; exit 1; }

"$BIN/record" --backend sim --poses 0 0 -q -o "$WORK/published"
"$BIN/toolinc-yarp-fakes" "$WORK/published" 0 --static-poses "$WORK/poses.json" >"$WORK/fakes.log" 2>&1 &
pids+=($!)
for _ in $(seq 50); do yarp exists /SFM/rpc >/dev/null 2>&1 && break; sleep 0.2; done

echo "== 1. with the controllers (expected: a clear error, exit 2)"
set +e
"$BIN/record" --backend yarp --poses 0 0 --connect-timeout 2 -o "$WORK/with-controllers"
echo "exit code $?"
set -e

echo "== 2. one view through the ports, arm and gaze replaced by $WORK/poses.json"
"$BIN/record" --backend yarp --static-poses "$WORK/poses.json" --poses 0 0 --settle-time 0.3 -o "$WORK/recorded"
for file in left.png disparity.png blob.png; do
  cmp "$WORK/published/views/000/$file" "$WORK/recorded/views/000/$file" && echo "$file: identical"
done
"$BIN/crop-cloud" "$WORK/published" --view 0 --ascii -q -o "$WORK/published.ply"
"$BIN/crop-cloud" "$WORK/recorded" --view 0 --ascii -o "$WORK/recorded.ply"
# The same points (the headers name different sessions).
diff -q <(sed '1,/end_header/d' "$WORK/published.ply") <(sed '1,/end_header/d' "$WORK/recorded.ply") >/dev/null \
  && echo "crop-cloud: the same points from both sessions"
echo "loopback passed; everything is in $WORK"
