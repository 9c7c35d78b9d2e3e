#!/usr/bin/env bash
# ctest lab_sim_robot_edge_exploration: the UNCHANGED robot deployment
# (deployments/robot.ops with TACTILE_EXPERIMENT=edge_exploration: the FRI bridge on its
# FileDescriptorActivity, the WTS reader, features, servo, the experiment's
# state machine, the reporter) against lab_sim on the edge exploration scene
# (params/scenes/edge_exploration.yaml), the KRC in command mode from its first
# packet, to the experiment's end: scripts/run_robot.sh (the unattended
# robot run: the entry script, then deployments/experiment_finish.ops, which
# waits for the state machine to reach FINISHED, here at most 240 s, and
# stops; the reporter's table converted by scripts/tools/deployment_to_run.py).
# The deployment is a staged copy of deployments/ (scripts/realtime/rt_common.sh:
# absolute paths, the WTS reader on lab_sim's PTY) with the bridge's port
# set to 49971; nothing else is changed. check_lab_sim_robot.py checks,
# from it and lab_sim's truth CSV, that the edge was explored (phases reached,
# the true force near the program's target while exploring, the path slid).
# Wall clock (about 30-40 s); counts and bounds only, no timing asserted.
#   run_lab_sim_robot_test.sh SOURCE_DIR BUILD_DIR
# Environment: OROCOS (default /opt/orocos), DEPLOYER.
set -uo pipefail
name=lab_sim_robot_edge_exploration
export BUILD="$2"
# root, build, orocos, deployer, rt_stage_deployments, pids + cleanup trap
source "$1/scripts/realtime/rt_common.sh"
source "$1/tests/lab_sim/lab_robot_common.sh"  # lab_robot_stage, lab_robot_start, lab_robot_run
port=49971
exp=edge_exploration
out="$build/lab_sim_test/robot_$exp"
py=/usr/bin/python3
lab_robot_stage "$out" $port
grep -q "<value>$out/wts0</value>" "$out/deployments/wts_reader.cpf" || { echo "$name: could not set the WTS device"; exit 1; }
lab_robot_start "$out" $port "$root/params/scenes/$exp.yaml" --truth-out "$out/truth.csv"
lab_robot_run $exp "$out" 240
cat "$out/lab_sim.log"
[ -s "$out/run/timeseries.csv" ] || { echo "$name: no converted report in $out/run (run_robot.sh exit $dep_rc)" >&2; exit 1; }
"$py" "$root/tests/lab_sim/check_lab_sim_robot.py" "$out" "$lab_rc" "$dep_rc" "$root/params/scenes/$exp.yaml" \
  "$root/params/programs/$exp.yaml" "$root/params/sensors/fri.yaml"
