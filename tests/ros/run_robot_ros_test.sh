#!/usr/bin/env bash
# ctest ros_robot_streams_<experiment> (run inside tests/ros/with_roscore.sh):
# the ROS variant of the robot deployment, deployments/robot_ros.ops with
# TACTILE_EXPERIMENT=<experiment>, unchanged, against the simulated peers: fri_sim_krc (the KRC over FRI/UDP,
# fri.yaml's port) and wts_sim (the WTS0614 on a PTY, a press circling the
# pad), from a staged copy of deployments/ (absolute paths, the PTY in
# wts_reader.cpf, as scripts/realtime/rt_common.sh stages them). check_robot_topics.py
# subscribes meanwhile and ends the run by switching the servo to `done`
# through the phase service.
#   run_robot_ros_test.sh SOURCE_DIR BUILD_DIR OROCOS_PREFIX EXPERIMENT
set -o pipefail
src="$1"; build="$2"; orocos="$3"; exp="$4"
[ -f "$src/deployments/robot_ros.ops" ] || { echo "run_robot_ros_test: no deployments/robot_ros.ops"; exit 2; }
out="${TACTILE_ROS_TMP:?run inside with_roscore.sh}/robot"
name=run_robot_ros_test
# shellcheck source=../../scripts/realtime/rt_common.sh
BUILD="$build" OROCOS="$orocos" source "$src/scripts/realtime/rt_common.sh"   # staging, wts_sim, the cleanup of pids
rt_stage_deployments "$out"
cat > "$out/deployments/robot_ros_test.ops" <<'EOF'
// tests/ros/run_robot_ros_test.sh: the robot ROS variant as shipped, held until
// the checker switches the servo to `done` (or Guard.timeout s), then stopped.
runScript("robot_ros.ops")
Guard.timeout = 150.0
var double waited = 0.0
while Guard.ok && waited < Guard.timeout && Servo.phaseName() != "done" {
  Guard.sleep(0.5)
  waited = waited + 0.5
}
Guard.step(true, "robot_ros: phase " + Servo.phaseName() + " after " + waited + " s; Robot received " + Robot.received + " replies " + Robot.replies + " lost " + Robot.lost + "; Sensor frames " + Sensor.frames)
Guard.step(stopComponents(), "stop all components")
var int robot_ros_finished(Guard.verdict())
EOF

rt_start_wts_sim "$out"

# The report's path as a ROS parameter (ros_params.ops): the run must write there.
report="$out/deployments/robot_ros_param_${exp}.dat"
rm -f "$report"
rosparam set /Guard/report_file "$report" || { echo "run_robot_ros_test: rosparam set failed"; exit 1; }
cd "$out/deployments" || exit 1
TACTILE_EXPERIMENT="$exp" "${DEPLOYER:-$orocos/bin/deployer-gnulinux}" --check -linfo -s robot_ros_test.ops < /dev/null > "$out/deployer.log" 2>&1 &
dep=$!
cd - > /dev/null || exit 1
pids+=($dep)
# The deployment is up once ros_streams.ops has offered the phase service.
up=0
for _ in $(seq 600); do
  rosservice list 2>/dev/null | grep -q '^/tactile/switch_phase$' && { up=1; break; }
  kill -0 "$dep" 2>/dev/null || break
  sleep 0.1
done
if [ "$up" -ne 1 ]; then
  echo "run_robot_ros_test: the deployment did not offer /tactile/switch_phase"; tail -n 40 "$out/deployer.log"; exit 1
fi
# The KRC: monitor mode for 1 s, then command mode; at most 180 s (the checker ends the run first).
# Its estExtTcpFT carries the force of wts_sim's press along the experiment's
# z_s (rt_common.sh's rt_press_wrench_tool).
press=$(rt_press_wrench_tool "$exp") || { echo "run_robot_ros_test: no sensor mount for $exp"; exit 1; }
"$build/bin/fri_sim_krc" --port 49938 --cycles 180000 --period-ms 1 --schedule 0:MON:PERFECT,1000:CMD:PERFECT --wrench-tool "$press" \
  > "$out/krc.log" 2>&1 &
krc=$!
pids+=($krc)
/usr/bin/python3 "$src/tests/ros/check_robot_topics.py" "$out/ready" 4.0 > "$out/check.log" 2>&1
crc=$?
if [ "$crc" -ne 0 ]; then  # the servo may never reach `done`: end the deployer (it cleans up on SIGINT)
  kill -INT "$dep" 2>/dev/null
  for _ in $(seq 100); do kill -0 "$dep" 2>/dev/null || break; sleep 0.1; done
  kill -KILL "$dep" 2>/dev/null
fi
wait "$dep"
rc=$?
kill "$krc" 2>/dev/null
echo "---- deployer (exit $rc) ----"
grep -E "deployment step failed|ERROR|robot_ros:" "$out/deployer.log" | cut -c1-300 | head -40
echo "---- fri_sim_krc ----"; tail -n 3 "$out/krc.log" | cut -c1-200
echo "---- check_robot_topics (exit $crc) ----"; cat "$out/check.log"
[ "$rc" -eq 0 ] || { echo "run_robot_ros_test: deployer exit $rc"; tail -n 40 "$out/deployer.log"; exit 1; }
[ "$crc" -eq 0 ] || exit 1
rows=$(grep -vc '^#' "$report" 2>/dev/null || echo 0)
[ "$rows" -gt 10 ] || { echo "run_robot_ros_test: the report named by /Guard/report_file ($report) has $rows rows"; exit 1; }
echo "run_robot_ros_test: report from the ROS parameter /Guard/report_file: $rows rows"
echo "run_robot_ros_test: passed"
