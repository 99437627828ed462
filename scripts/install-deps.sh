#!/usr/bin/env bash
# Installs the Debian (bookworm) packages toolinc needs to build and test. Idempotent; works as root or
# through sudo. Skips apt entirely when everything is already installed.
set -euo pipefail

# scripts/install-deps.sh [PACKAGE...]: those packages instead (the Slurm check's, for one).
packages=(
  build-essential cmake pkg-config
  libeigen3-dev libpcl-dev libopencv-dev
  libcli11-dev nlohmann-json3-dev libspdlog-dev
  libgtest-dev libbenchmark-dev liblzf-dev ccache
  snakemake
  pybind11-dev python3-dev python3-numpy python3-pytest python3-jsonschema
  clang-14 libclang-rt-14-dev llvm-14 clang-format-14
)
[ $# -gt 0 ] && packages=("$@")

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then sudo=(); else sudo=(sudo); fi
echo "install-deps: installing ${missing[*]}"
"${sudo[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
