#!/usr/bin/env bash
# ctest lab_sim_robot_phantom_contact: the UNCHANGED robot deployment of an
# experiment (scripts/run_robot.sh, the unattended run) against lab_sim on a
# scene whose pad is faulty, the KRC in command mode from its first packet;
# the run must end FAILED with the servo's named stop, and the arm must not
# have travelled. Here: sim/scenes/faults/phantom_contact.yaml (the pad reads
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
for t in "$deployer" "$build/bin/lab_sim"; do
  [ -x "$t" ] || { echo "$name: $t missing" >&2; exit 1; }
done
port=49973
out="$build/lab_sim_test/fault_$(basename "$scene" .yaml)"
py=/usr/bin/python3
rm -rf "$out"
mkdir -p "$out"
rt_stage_deployments "$out"
sed -i "/name=\"port\"/,/<\/simple>/ s#<value>-1</value>#<value>$port</value>#" "$out/deployments/fri_bridge.cpf"
grep -q "<value>$port</value>" "$out/deployments/fri_bridge.cpf" || { echo "$name: could not set the bridge's port"; exit 1; }

"$build/bin/lab_sim" "$scene" --fri-port $port --wts-link "$out/wts0" \
  --krc "0:friOpen,0:friStart" --truth-out "$out/truth.csv" >"$out/lab_sim.log" 2>&1 &
lab=$!
pids+=($lab)
for _ in $(seq 100); do [ -e "$out/wts0" ] && break; sleep 0.05; done
[ -e "$out/wts0" ] || { cat "$out/lab_sim.log"; echo "$name: lab_sim's PTY did not appear" >&2; exit 1; }

dep_rc=0
BUILD="$build" bash "$root/scripts/run_robot.sh" "$exp" --deployments "$out/deployments" --out "$out/run" --timeout 60 \
  >"$out/run_robot.log" 2>&1 || dep_rc=$?
kill -TERM "$lab" 2>/dev/null
wait "$lab"
cat "$out/run_robot.log"
"$py" "$root/tests/lab_sim/check_lab_sim_fault.py" "$out" "$dep_rc" "$want_status" "$max_travel"
