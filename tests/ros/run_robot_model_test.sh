#!/usr/bin/env bash
# ctest ros_robot_model (run inside tests/ros/with_roscore.sh): the arm as the
# launch file draws it -- the URDF as /robot_description, robot_state_publisher
# on /tactile/joint_states, /RosAdapter/publish_flange_tf false -- during the
# simulated edge exploration (tests/ros/ops/edge_exploration_ros.ops, its
# report into this test's folder), tests/ros/check_robot_model.py subscribing.
#   run_robot_model_test.sh SOURCE_DIR BUILD_DIR OROCOS_PREFIX
set -o pipefail
src="$1"; build="$2"; orocos="$3"
tmp="${TACTILE_ROS_TMP:?run inside with_roscore.sh}"
urdf="$src/ros/tactile_ros/urdf/lwr4plus_wts.urdf"
rsp_node=tactile_robot_state_publisher
checker=""; rsp=""
cleanup() {
  [ -n "$checker" ] && kill "$checker" 2>/dev/null
  [ -n "$rsp" ] && kill -INT -- "-$rsp" 2>/dev/null
}
trap cleanup EXIT
rosparam set --textfile "$urdf" /robot_description && rosparam set /RosAdapter/publish_flange_tf false \
  && rosparam set /Guard/report_file "$tmp/robot_model.dat" || { echo "run_robot_model_test: rosparam set failed"; exit 1; }
# As the launch file: every joint state (100 Hz) becomes TF (publish_frequency above it).
setsid rosrun robot_state_publisher robot_state_publisher joint_states:=/tactile/joint_states \
  __name:=$rsp_node _publish_frequency:=200 > "$tmp/rsp.log" 2>&1 &
rsp=$!
done_file="$tmp/deployer.done"
/usr/bin/python3 "$src/tests/ros/check_robot_model.py" "$urdf" "$done_file" "$rsp_node" > "$tmp/check.log" 2>&1 &
checker=$!
(cd "$src/deployments" && "${DEPLOYER:-$orocos/bin/deployer-gnulinux}" --check -lwarning \
   -s "$src/tests/ros/ops/edge_exploration_ros.ops" < /dev/null > "$tmp/deployer.log" 2>&1)
rc=$?
touch "$done_file"
wait "$checker"
crc=$?
checker=""
echo "---- deployer (exit $rc) ----"; grep -E "deployment step failed|ERROR|after [0-9.]+ s" "$tmp/deployer.log" | head -20
echo "---- robot_state_publisher ----"; tail -n 5 "$tmp/rsp.log"
echo "---- check_robot_model (exit $crc) ----"; cat "$tmp/check.log"
[ "$rc" -eq 0 ] || { echo "run_robot_model_test: deployer exit $rc"; tail -n 40 "$tmp/deployer.log"; exit 1; }
[ "$crc" -eq 0 ] || exit 1
echo "run_robot_model_test: passed"
