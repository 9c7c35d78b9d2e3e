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
source "$1/tests/lab_sim/lab_robot_common.sh"  # lab_robot_stage, lab_robot_start, lab_robot_run
exp=first_touch
out="$build/lab_sim_test/robot_${exp}_fails"
lab_robot_stage "$out" 49972
lab_robot_start "$out" 49972 "$root/params/scenes/$exp.yaml" --set 'objects=[]'
lab_robot_run $exp "$out" 60
/usr/bin/python3 "$root/tests/lab_sim/check_lab_sim_robot_fails.py" "$out/run" "$out/run_robot.log" "$dep_rc"
