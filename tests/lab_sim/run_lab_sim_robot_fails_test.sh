#!/usr/bin/env bash
# ctest lab_sim_robot_first_touch_fails: the UNCHANGED robot deployment of the
# first touch (scripts/run_robot.sh first_touch: robot.ops, then
# deployments/experiment_finish.ops) against lab_sim with nothing under the
# pad (`--set objects=[]`, the scene's own no-contact variant): the program's
# approach ends in no_contact after 12 s and the state machine
# (first_touch_experiment.osd) fails, reason 11. A failed run must read as
# cleanly as a passing one (check_lab_sim_robot_fails.py): no script error in
# the deployer's log, the run's outcome and the verdict named, the robot's
# status at the end logged, the deployer and run_robot.sh exiting 255, and
# the reporter's table, summary.json (its status and fault time) and plots
# written up to the end. The deployment is a staged copy of deployments/
# (scripts/realtime/rt_common.sh) with the bridge's port set to 49972. Wall
# clock (about 20-30 s).
#   run_lab_sim_robot_fails_test.sh SOURCE_DIR BUILD_DIR
# Environment: OROCOS (default /opt/orocos), DEPLOYER.
set -uo pipefail
name=lab_sim_robot_first_touch_fails
export BUILD="$2"
# root, build, orocos, deployer, rt_stage_deployments, pids + cleanup trap
source "$1/scripts/realtime/rt_common.sh"
for t in "$deployer" "$build/bin/lab_sim"; do
  [ -x "$t" ] || { echo "$name: $t missing" >&2; exit 1; }
done
port=49972
exp=first_touch
out="$build/lab_sim_test/robot_${exp}_fails"
rm -rf "$out"
mkdir -p "$out"
rt_stage_deployments "$out"
sed -i "/name=\"port\"/,/<\/simple>/ s#<value>-1</value>#<value>$port</value>#" "$out/deployments/fri_bridge.cpf"
grep -q "<value>$port</value>" "$out/deployments/fri_bridge.cpf" || { echo "$name: could not set the bridge's port"; exit 1; }

"$build/bin/lab_sim" "$root/sim/scenes/$exp.yaml" --set 'objects=[]' --fri-port $port --wts-link "$out/wts0" \
  --krc "0:friOpen,0:friStart" >"$out/lab_sim.log" 2>&1 &
lab=$!
pids+=($lab)
for _ in $(seq 100); do [ -e "$out/wts0" ] && break; sleep 0.05; done
[ -e "$out/wts0" ] || { cat "$out/lab_sim.log"; echo "$name: lab_sim's PTY did not appear" >&2; exit 1; }

dep_rc=0
BUILD="$build" bash "$root/scripts/run_robot.sh" $exp --deployments "$out/deployments" --out "$out/run" --timeout 60 \
  >"$out/run_robot.log" 2>&1 || dep_rc=$?
kill -TERM "$lab" 2>/dev/null
wait "$lab" 2>/dev/null
cat "$out/run_robot.log"
/usr/bin/python3 "$root/tests/lab_sim/check_lab_sim_robot_fails.py" "$out/run" "$out/run_robot.log" "$dep_rc"
