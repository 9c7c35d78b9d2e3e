#!/usr/bin/env bash
# ctest ros_sim_streams (run inside tests/ros/with_roscore.sh: a roscore of
# its own on the loopback address): the simulated edge exploration with ROS
# streams (tests/ros/ops/edge_exploration_ros.ops, run from deployments/) and
# tests/ros/check_topics.py subscribing meanwhile.
# With BAG_OUT, record_bag.py records /tactile/image and /tactile/features meanwhile
# into that file (for ctest ros_bag_replay: tests/ros/check_bag.py).
#   run_ros_test.sh SOURCE_DIR BUILD_DIR OROCOS_PREFIX ROS_PREFIX [BAG_OUT]
set -o pipefail
src="$1"; build="$2"; orocos="$3"; ros_prefix="$4"; bag_out="${5:-}"
tmp="${TACTILE_ROS_TMP:?run inside with_roscore.sh}"
checker=""
recorder=""
cleanup() {
  [ -n "$checker" ] && kill "$checker" 2>/dev/null
  [ -n "$recorder" ] && kill -INT -- "-$recorder" 2>/dev/null
  rm -f "$src/deployments/edge_exploration_sim_ros_test.dat" "$src/deployments/edge_exploration_sim_ros_test_param.dat"
}
trap cleanup EXIT

# The report's path comes as a ROS parameter (deployments/ros_params.ops): the
# checker reads this file, so a parameter that did not take effect fails.
report_name="edge_exploration_sim_ros_test_param.dat"
rosparam set /Guard/report_file "$report_name" || { echo "run_ros_test: rosparam set failed"; exit 1; }
report="$src/deployments/$report_name"
done_file="$tmp/deployer.done"
rm -f "$report"
/usr/bin/python3 "$src/tests/ros/check_topics.py" "$report" "$done_file" "$src/params/scenes/edge_exploration.yaml" \
  "$src/params/programs/edge_exploration.yaml" > "$tmp/check.log" 2>&1 &
checker=$!
if [ -n "$bag_out" ]; then
  # The recorder (subscribed before the deployment advertises; record_bag.py:
  # rosbag's recorder drops messages under load); SIGINT writes the bag.
  rm -f "$bag_out" "$tmp/run.bag"
  setsid /usr/bin/python3 "$src/tests/ros/record_bag.py" "$tmp/run.bag" __name:=tactile_test_bag \
    > "$tmp/rosbag.log" 2>&1 &
  recorder=$!
  for _ in $(seq 100); do
    rosnode list 2>/dev/null | grep -q tactile_test_bag && break
    sleep 0.1
  done
fi
(cd "$src/deployments" && "${DEPLOYER:-$orocos/bin/deployer-gnulinux}" --check -lwarning -s "$src/tests/ros/ops/edge_exploration_ros.ops" \
   < /dev/null > "$tmp/deployer.log" 2>&1)
rc=$?
touch "$done_file"
if [ -n "$recorder" ]; then
  sleep 1  # the last messages in flight
  kill -INT -- "-$recorder" 2>/dev/null
  for _ in $(seq 300); do kill -0 "$recorder" 2>/dev/null || break; sleep 0.1; done  # it writes the bag
  recorder=""
  if [ -f "$tmp/run.bag" ]; then
    mkdir -p "$(dirname "$bag_out")" && cp "$tmp/run.bag" "$bag_out" && echo "run_ros_test: bag $bag_out"
  else
    echo "run_ros_test: rosbag wrote no bag"; cat "$tmp/rosbag.log"; ls "$tmp"
  fi
fi
wait "$checker"
crc=$?
checker=""
echo "---- deployer (exit $rc) ----"; grep -E "deployment step failed|ERROR|\[ERROR\]|after [0-9.]+ s|file paths" "$tmp/deployer.log" | head -40
echo "---- check_topics (exit $crc) ----"; cat "$tmp/check.log"
[ "$rc" -eq 0 ] || { echo "run_ros_test: deployer exit $rc"; tail -n 40 "$tmp/deployer.log"; exit 1; }
[ "$crc" -eq 0 ] || exit 1
echo "run_ros_test: passed"
