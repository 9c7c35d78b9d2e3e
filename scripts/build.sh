#!/usr/bin/env bash
# Configures and builds the project into ./build (Release). Extra arguments go
# to CMake, e.g. scripts/build.sh -DTACTILE_WITH_RTT=OFF.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
jobs="${TACTILE_JOBS:-$(nproc)}"
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$root/build" -j"$jobs"
