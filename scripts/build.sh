#!/usr/bin/env bash
# Configures and builds the project into ./build (Release). Extra arguments go
# to CMake, e.g. scripts/build.sh -DTACTILE_WITH_RTT=OFF.
# The Orocos RTT layer builds when find_package(OROCOS-RTT) succeeds: an
# installed Orocos toolchain 2.10 under $OROCOS_PREFIX (default /opt/orocos) is
# added to CMAKE_PREFIX_PATH when it exists; without it the RTT layer is skipped.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
jobs="${TACTILE_JOBS:-$(nproc)}"
prefix_args=()
orocos="${OROCOS_PREFIX:-/opt/orocos}"
if [ -d "$orocos" ]; then prefix_args=(-DCMAKE_PREFIX_PATH="$orocos"); fi
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release "${prefix_args[@]}" "$@" | grep -E "tactile_servo:" || true
cmake --build "$root/build" -j"$jobs"
