#!/usr/bin/env bash
# The test command: installs what is missing (Debian packages, the Orocos
# toolchain 2.10 into $OROCOS_PREFIX), builds, runs every test, RTT layer
# included. TACTILE_WITH_RTT=OFF skips Orocos and the RTT tests (say so).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
t0=$SECONDS
bash "$root/scripts/setup/setup_deps.sh"
bash "$root/scripts/setup/realtime_host.sh"
bash "$root/scripts/setup/setup_orocos.sh"
echo "run_tests: set-up took $((SECONDS - t0)) s"
bash "$root/scripts/setup/build.sh"
echo "run_tests: set-up and build took $((SECONDS - t0)) s"
cd "$root/build"
if [ "${TACTILE_WITH_RTT:-ON}" != "OFF" ]; then
  n_rtt=$(ctest -N -L rtt | sed -n 's/^Total Tests: //p')
  if [ "${n_rtt:-0}" -eq 0 ]; then
    echo "run_tests: no RTT test was configured although TACTILE_WITH_RTT is not OFF" >&2
    exit 1
  fi
  echo "run_tests: $n_rtt RTT tests configured"
fi
n_ros=$(ctest -N -L ROS | sed -n 's/^Total Tests: //p')
if [ "${n_ros:-0}" -eq 0 ]; then
  echo "run_tests: ROS tests skipped: the ROS face is not built (TACTILE_WITH_ROS=${TACTILE_WITH_ROS:-AUTO}; scripts/setup/setup_rtt_ros.sh)"
else
  echo "run_tests: $n_ros ROS tests configured"
fi
ctest --output-on-failure -j"${TACTILE_JOBS:-$(nproc)}" --timeout 900
echo "run_tests: total $((SECONDS - t0)) s"
