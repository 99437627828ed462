#!/usr/bin/env bash
# Loopback check of record's YARP adapter without a robot (README "Recording on the robot"): a private
# yarpserver on 127.0.0.1, toolinc-yarp-fakes standing in for the camera, the stereo module and the blob
# detector (publishing view 0 of a session simulated here), then
#   1. record with the controllers: they are absent here (icub-main), which must be one clear error;
#   2. record --static-poses: one view captured through the ports, compared with what was published.
# It runs what a YARP-enabled build made; it builds nothing. Everything it starts stays on 127.0.0.1: the
# name server, every port (YARP_IP), and the YARP configuration is a private one in WORK_DIR (the user's own
# is neither read nor written); at the end it checks the name server's registrations and, where `ss` is
# installed, the TCP sockets its processes listen on, and fails if any is on another address.
#
# usage: scripts/yarp-loopback.sh BUILD_DIR [WORK_DIR]
#   BUILD_DIR: configured with -DTOOLINC_WITH_YARP=ON and built (targets record, toolinc-yarp-fakes,
#   crop-cloud); yarpserver and yarp on PATH.
set -euo pipefail

BIN=$(cd "$1/bin" && pwd)
WORK=${2:-$(mktemp -d /tmp/toolinc-yarp-loopback.XXXXXX)}
mkdir -p "$WORK"
PORT=${YARP_LOOPBACK_PORT:-10111}
# A private YARP configuration, so the name server found is this one and the user's files stay untouched
# (YARP_CONF for YARP before 3.0; XDG_* where the YARP_* ones are not set).
export YARP_CONFIG_HOME=$WORK/yarp-config YARP_DATA_HOME=$WORK/yarp-data
export YARP_CONF=$YARP_CONFIG_HOME XDG_CONFIG_HOME=$WORK/xdg-config XDG_DATA_HOME=$WORK/xdg-data
export XDG_CACHE_HOME=$WORK/xdg-cache
unset YARP_NAMESPACE YARP_PORT_PREFIX YARP_RENAME
mkdir -p "$YARP_CONFIG_HOME" "$YARP_DATA_HOME"
echo "127.0.0.1 $PORT yarp" >"$YARP_CONFIG_HOME/yarp.conf"
# Every port registers and listens on 127.0.0.1: without YARP_IP a port takes the address YARP prefers,
# the machine's external one.
export YARP_IP=127.0.0.1
echo "== YARP on 127.0.0.1 only: name server 127.0.0.1:$PORT, YARP_IP=127.0.0.1, configuration in $YARP_CONFIG_HOME"
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

echo "== 3. everything on 127.0.0.1"
# The name server's registrations (YARP's multicast fallback entry for finding the name server excepted:
# a group address, not a port of ours), then the TCP sockets the processes started here listen on.
registrations=$(yarp name list 2>/dev/null | grep '^registration name' | grep -v ' type mcast')
[ -n "$registrations" ] || { echo "no registration listed by the name server" >&2; exit 1; }
elsewhere=$(grep -v ' ip 127\.0\.0\.1 ' <<<"$registrations" || true)
[ -z "$elsewhere" ] || { echo "registered on another address than 127.0.0.1:" >&2; echo "$elsewhere" >&2; exit 1; }
echo "$(wc -l <<<"$registrations") registrations, all on 127.0.0.1"
if command -v ss >/dev/null 2>&1; then
  listening=$(ss -ltnpH | grep -E "pid=($(IFS='|'; echo "${pids[*]}")),")
  [ -n "$listening" ] || { echo "ss lists no socket of yarpserver or the fakes" >&2; exit 1; }
  elsewhere=$(awk '$4 !~ /^127\.0\.0\.1:/' <<<"$listening")
  [ -z "$elsewhere" ] || { echo "listening on another address than 127.0.0.1:" >&2; echo "$elsewhere" >&2; exit 1; }
  echo "$(wc -l <<<"$listening") listening TCP sockets (yarpserver, fakes), all on 127.0.0.1"
else
  echo "ss is not installed: listening sockets not checked"
fi
echo "loopback passed; everything is in $WORK"
