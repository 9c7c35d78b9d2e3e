#!/usr/bin/env bash
# ctest lab_sim_robot_phantom_contact: the UNCHANGED robot deployment of an
# experiment (scripts/run_robot.sh, the unattended run) against lab_sim on a
# scene whose pad is faulty, the KRC in command mode from its first packet;
# the run must end FAILED with the servo's named stop, and the arm must not
# have travelled. Here: params/scenes/faults/phantom_contact.yaml (the pad reads
# a steady 8 N press, nothing touches it, the KRC's wrench says so) under the
# edge exploration. Before the sensor checks compared the taxels' own force
# with the wrench, this run chased the press for 30 s and more than 0.5 m.
# check_lab_sim_fault.py checks the verdict, the named stop in the deployer's
# log and in summary.json, and from lab_sim's truth the flange's travel and
# the true force. Wall clock (about 15 s); counts and bounds only.
#   run_lab_sim_robot_fault_test.sh SOURCE_DIR BUILD_DIR SCENE EXPERIMENT STATUS MAX_TRAVEL_M
# Environment: OROCOS (default /opt/orocos), DEPLOYER.
set -uo pipefail
name=lab_sim_robot_fault
export BUILD="$2"
# root, build, orocos, deployer, rt_stage_deployments, pids + cleanup trap
source "$1/scripts/realtime/rt_common.sh"
scene="$root/$3"
exp="$4"
want_status="$5"
max_travel="$6"
source "$1/tests/lab_sim/lab_robot_common.sh"  # lab_robot_stage, lab_robot_start, lab_robot_run
out="$build/lab_sim_test/fault_$(basename "$scene" .yaml)"
lab_robot_stage "$out" 49973
# The KRC in command mode from its first packet: the script alone decides
# (--quality-rule off), not the link's rating, which would hold monitor mode
# for the first 100 answered cycles and end the run before the check's 100 ms.
lab_robot_start "$out" 49973 "$scene" --truth-out "$out/truth.csv" --quality-rule off
lab_robot_run "$exp" "$out" 60
/usr/bin/python3 "$root/tests/lab_sim/check_lab_sim_fault.py" "$out" "$dep_rc" "$want_status" "$max_travel"
