#!/usr/bin/env bash
# Configures and builds toolinc (Release) into ${BUILD_DIR:-build}; CMAKE_ARGS adds cache entries.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
# shellcheck disable=SC2086  # CMAKE_ARGS: extra cache entries, split on spaces
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release ${CMAKE_ARGS:-} >/dev/null
cmake --build "$build" -j "$(nproc)"
