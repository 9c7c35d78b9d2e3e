#!/usr/bin/env bash
# ctest lab_sim_robot_verdict_<experiment>: one robot experiment (experiments.yaml,
# robot: true) headless (tactile_sim run on its scene, with its controller)
# and on the robot path (scripts/run_robot_lab.sh: the UNCHANGED robot
# deployment against lab_sim on the same scene, the KRC in command mode from
# its first packet, to the state machine's end), and headless again on seeds
# 1-20, then check_lab_sim_robot_verdict.py: the same verdict on both paths
# (or an outcome the headless runner also gives on one of those seeds), the true
# force never above 7 N on either, and at the normal end of the run the KRL
# program asked to stop (friStop) and lab_sim's KRC out of command mode.
# Wall clock: the experiment's duration plus the deployer's start-up.
#   run_lab_sim_robot_verdict_test.sh SOURCE_DIR BUILD_DIR EXPERIMENT PORT
# Environment: OROCOS (default /opt/orocos), DEPLOYER.
set -uo pipefail
exp="$3"
port="$4"
name="lab_sim_robot_verdict_$exp"
export BUILD="$2"
root="$1"
build="$2"
py=/usr/bin/python3
out="$build/lab_sim_test/robot_verdict"
head="$out/headless/$exp"
scene="$root/$("$py" "$root/scripts/tools/registry.py" get "$exp" scene)"
controller="$("$py" "$root/scripts/tools/registry.py" get "$exp" controller)"
rm -rf "$head"
mkdir -p "$head"
"$build/bin/tactile_sim" run "$scene" --out "$head" ${controller:+--controller "$controller"} > "$head/tactile_sim.log" 2>&1
[ -s "$head/summary.json" ] || { cat "$head/tactile_sim.log"; echo "$name: no headless summary" >&2; exit 1; }
# The headless outcomes over seeds 1-20 (the noise's realizations; a few seconds, no plots).
seeds="$out/headless_seeds/$exp"
rm -rf "$seeds"
for s in $(seq 1 20); do
  "$build/bin/tactile_sim" run "$scene" --seed "$s" --no-plots --out "$seeds/seed_$s" ${controller:+--controller "$controller"} \
    > /dev/null 2>&1
done
bash "$root/scripts/run_robot_lab.sh" "$exp" --out "$out/robot_lab" --port "$port"
echo "run_robot_lab.sh exit $?"
"$py" "$root/tests/lab_sim/check_lab_sim_robot_verdict.py" "$head" "$out/robot_lab/$exp" "$seeds"
