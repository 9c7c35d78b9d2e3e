#!/usr/bin/env bash
# Installs the Debian 12 packages the project needs, only those missing
# (idempotent: nothing is downloaded when everything is present).
set -euo pipefail
PKGS=(
  build-essential cmake pkg-config clang-tidy  # clang-tidy: scripts/lint/function_size.sh
  libeigen3-dev liborocos-kdl-dev libopencv-dev libyaml-cpp-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-matplotlib python3-numpy python3-yaml
  stress-ng rt-tests  # scripts/realtime/rt_latency.sh: CPU/memory load, cyclictest
)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup_deps: all ${#PKGS[@]} packages present"
  exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "setup_deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
