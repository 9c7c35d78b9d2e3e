#!/usr/bin/env bash
# ctest test_ros_rt_allocations_robot (run inside tests/ros/with_roscore.sh):
# stages deployments/ (absolute paths, the simulated WTS's PTY in
# wts_reader.cpf: scripts/realtime/rt_common.sh), starts wts_sim on the PTY and
# fri_sim_krc on fri.yaml's port, and runs the test binary's robot case in
# that folder (TACTILE_STAGED_DEPLOYMENTS).
#   run_robot_alloc_test.sh SOURCE_DIR BUILD_DIR TEST_BINARY
set -o pipefail
src="$1"; build="$2"; binary="$3"
out="${TACTILE_ROS_TMP:?run inside with_roscore.sh}/robot_alloc"
name=run_robot_alloc_test
# shellcheck source=../../scripts/realtime/rt_common.sh
BUILD="$build" source "$src/scripts/realtime/rt_common.sh"   # staging, wts_sim, the cleanup of pids
rt_stage_deployments "$out"
rt_start_wts_sim "$out"
# The KRC sends from now on (its first packets meet no bridge yet: lost, as at a real start-up);
# monitor mode for 1 s, then command mode; at most 180 s (killed when the test ends).
"$build/bin/fri_sim_krc" --port 49938 --cycles 180000 --period-ms 1 --schedule 0:MON:PERFECT,1000:CMD:PERFECT --wrench "$rt_press_wrench" \
  > "$out/krc.log" 2>&1 &
pids+=($!)
TACTILE_STAGED_DEPLOYMENTS="$out/deployments" "$binary" --gtest_filter='*RobotLoop*'
