#!/usr/bin/env bash
# One step of scripts/pipeline.mk: runs COMMAND with its stderr in LOG, where scripts/session_summary.py
# finds a failed session's error, and shown on stderr too when the step fails (an error with no message
# gets one, so that no failure goes unlisted). Exits with COMMAND's status.
#
# usage: scripts/run-step.sh LOG COMMAND [ARGUMENT...]
set -uo pipefail
log=$1
shift
mkdir -p "$(dirname "$log")" || exit 1
"$@" 2>"$log"
status=$?
if [ "$status" -ne 0 ]; then
  [ -s "$log" ] || echo "$(basename "$1"): exit status $status, no message" >"$log"
  cat "$log" >&2
fi
exit "$status"
