#!/usr/bin/env bash
# Configures and builds the project into ./build (Release). Extra arguments go
# to CMake.
#
# The Orocos RTT layer (components, typekit, deployer tests) is part of the
# product: scripts/setup/setup_orocos.sh installs Orocos toolchain 2.10 into
# $OROCOS_PREFIX (default /opt/orocos), and this script then builds the RTT
# layer with TACTILE_WITH_RTT=ON (CMake fails if RTT cannot be found).
# Opt out with TACTILE_WITH_RTT=OFF (cores, simulator and tools only).
# TACTILE_BUILD_TARGETS="t1 t2" builds only those targets (the main job builds
# tactile_sim first, with TACTILE_WITH_RTT=OFF, to show a result before Orocos
# is set up; the later configuration with the RTT layer reuses its objects).
# The compiler's output goes to build.compile.log (a progress line from its
# [NN%] about every 45 s; on failure its first errors and last lines, and the
# build's exit status).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
# shellcheck source=progress.sh
source "$root/scripts/setup/progress.sh"
jobs="${TACTILE_JOBS:-$(nproc)}"
orocos="${OROCOS_PREFIX:-/opt/orocos}"
with_rtt="${TACTILE_WITH_RTT:-ON}"
args=(-DCMAKE_BUILD_TYPE=Release -DTACTILE_WITH_RTT="$with_rtt")
# The ROS 1 face (ros/): AUTO builds it where scripts/setup/setup_rtt_ros.sh installed rtt_ros_integration.
args+=(-DTACTILE_WITH_ROS="${TACTILE_WITH_ROS:-AUTO}")
if [ "$with_rtt" != "OFF" ]; then args+=(-DCMAKE_PREFIX_PATH="$orocos"); fi
# ccache wherever it is installed (its own cache, ~/.cache/ccache or $CCACHE_DIR);
# TACTILE_CCACHE=0 builds without it.
if [ "${TACTILE_CCACHE:-1}" != 0 ] && command -v ccache >/dev/null; then
  args+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
else
  args+=(-UCMAKE_CXX_COMPILER_LAUNCHER)
fi
echo "build: configuring (TACTILE_WITH_RTT=$with_rtt)"
cmake -S "$root" -B "$root/build" "${args[@]}" "$@" > "$root/build.configure.log" 2>&1 \
  || { echo "build: CMake configure failed. Log: $root/build.configure.log" >&2; tail -n 30 "$root/build.configure.log" >&2; exit 1; }
grep -E "tactile_servo:" "$root/build.configure.log" || true
log="$root/build.compile.log"
targets=()
key=build
if [ -n "${TACTILE_BUILD_TARGETS:-}" ]; then
  read -ra names <<< "$TACTILE_BUILD_TARGETS"
  targets=(--target "${names[@]}")
  key=build_cores
fi
echo "build: compiling ${TACTILE_BUILD_TARGETS:-everything} with -j$jobs ($(progress_about "$key") from scratch; log: $log)"
rc=0
progress_run "build:   compile" "$key" "$log" cmake --build "$root/build" -j"$jobs" "${targets[@]}" || rc=$?
if [ "$rc" -ne 0 ]; then
  echo "build: compile failed (exit $rc). Log: $log" >&2
  grep -a -m 10 -E ' error: |Error [0-9]+' "$log" >&2 || true
  tail -n 30 "$log" >&2
  exit "$rc"
fi
echo "build: compiled in $PROGRESS_WALL s (CPU user+sys $PROGRESS_CPU s)"
