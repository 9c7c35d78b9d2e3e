#!/usr/bin/env bash
# Installs the Debian 12 packages the project needs, only those missing
# (idempotent: nothing is downloaded when everything is present). apt's
# output goes to /tmp/tactile-deps-apt.log (its last lines printed on failure,
# with apt's exit status); a progress line about every 45 s meanwhile.
set -euo pipefail
# shellcheck source=progress.sh
source "$(dirname "${BASH_SOURCE[0]}")/progress.sh"
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
log=/tmp/tactile-deps-apt.log
echo "setup_deps: installing ${missing[*]} ($(progress_about deps_apt); log: $log)"
rc=0
progress_run "setup_deps:   apt" deps_apt "$log" apt_install "${missing[@]}" || rc=$?
if [ "$rc" -ne 0 ]; then
  echo "setup_deps: FAILED at step 'apt-get install' (exit $rc). Log: $log" >&2
  tail -n 30 "$log" >&2
  exit "$rc"
fi
echo "setup_deps:   apt done in $PROGRESS_WALL s"
