#!/usr/bin/env bash
# ctest test_ros_rt_allocations_robot (run inside tests/ros/with_roscore.sh):
# stages deployments/ (absolute paths, the simulated WTS's PTY in
# wts_reader.cpf, as scripts/rt_common.sh does), starts wts_sim on the PTY and
# fri_sim_krc on fri.yaml's port, and runs the test binary's robot case in
# that folder (TACTILE_STAGED_DEPLOYMENTS).
#   run_robot_alloc_test.sh SOURCE_DIR BUILD_DIR TEST_BINARY
set -o pipefail
src="$1"; build="$2"; binary="$3"
out="${TACTILE_ROS_TMP:?run inside with_roscore.sh}/robot_alloc"
mkdir -p "$out/deployments"
cp "$src"/deployments/*.ops "$src"/deployments/*.cpf "$src"/deployments/*.osd "$out/deployments/"
sed -i "s#\.\./#$src/#g" "$out"/deployments/*.cpf
sed -i "s#<value>/dev/ttyACM0</value>#<value>$out/wts0</value>#" "$out/deployments/wts_reader.cpf"
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done; }
trap cleanup EXIT
"$build/bin/wts_sim" --link "$out/wts0" --pattern blob > "$out/wts_sim.log" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -e "$out/wts0" ] && break; sleep 0.1; done
[ -e "$out/wts0" ] || { echo "run_robot_alloc_test: wts_sim did not start"; cat "$out/wts_sim.log"; exit 1; }
# The KRC sends from now on (its first packets meet no bridge yet: lost, as at a real start-up);
# monitor mode for 1 s, then command mode; at most 180 s (killed when the test ends).
"$build/bin/fri_sim_krc" --port 49938 --cycles 180000 --period-ms 1 --schedule 0:MON:PERFECT,1000:CMD:PERFECT \
  > "$out/krc.log" 2>&1 &
pids+=($!)
TACTILE_STAGED_DEPLOYMENTS="$out/deployments" "$binary" --gtest_filter='*RobotLoop*'
