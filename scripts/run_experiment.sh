#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs every experiment
# of the registry (experiments.yaml: the edge exploration, Sec. 5.2, Fig. 9/10;
# the bent bar with the proposed controller, the Li et al. (RSS 2013) baseline
# and the no_rotation ablation, Sec. 5.2.1, Fig. 12; tray co-manipulation,
# Sec. 5.3, Fig. 14; a sphere; the closed contours; the first touch) headless
# against the simulated LWR 4+ and WTS0614 (tactile_sim -> out/<experiment>/).
# Then the sweeps: the three controllers on every scene, with the shipped
# programs and with the paper's (scripts/sweeps/compare_controllers.py ->
# out/compare/, out/compare_paper/), the force estimate against the tactile
# force (sweep_force.py -> out/force/), its bound against the image
# (sweep_correction.py -> out/correction/), the true force on every scene
# (force_targets.py -> out/force_targets/), the slide speed on the bent bar
# (sweep_speed.py -> out/speed/) and on the family of bars of sim/scenes/curved
# (sweep_family.py -> out/family/), and the whole closed contours
# (run_contours.py -> out/contours/, out/contours_sensor_effects/). Then every
# registry experiment again as Orocos components under the OCL deployer
# (scripts/run_deployment.sh -> out/deploy/<experiment>/, out/deploy/report.md),
# the first day on the real arm rehearsed against the simulated lab
# (scripts/rehearse_first_day.sh -> out/rehearsal/), every robot experiment
# through the unchanged robot deployment against the simulated lab
# (scripts/run_robot_lab.sh -> out/robot_lab/), each fault of the pad and of
# the wrench headless and on the robot path (fault_table.py --robot ->
# out/faults/, docs/faults.md), and last the results
# pages (scripts/tools/results_docs.py -> docs/results.md, the README's table).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/setup/setup_deps.sh"
bash "$root/scripts/setup/setup_orocos.sh"
bash "$root/scripts/setup/build.sh"
sim="$root/build/bin/tactile_sim"
out="$root/out"
mkdir -p "$out"

run() {  # run NAME SCENE [args]: a non-zero exit is reported, not fatal (the no_rotation ablation is expected to fail)
  local name="$1" scene="$2"; shift 2
  local rc=0
  "$sim" run "$root/$scene" --out "$out/$name" "$@" || rc=$?
  [ "$rc" -eq 0 ] || echo "  ($name $*: exit code $rc, status in $out/$name/summary.json)"
}

# Every experiment of the registry (experiments.yaml): its scene with its
# controller, into out/<experiment>/.
registry() {  # one line per registry entry: NAME SCENE CONTROLLER ('-' for the program's own)
  /usr/bin/python3 "$root/scripts/tools/registry.py" rows
}
experiments="$(registry)"
while read -r name scene controller; do
  if [ "$controller" = "-" ]; then run "$name" "$scene"; else run "$name" "$scene" --controller "$controller"; fi
done <<< "$experiments"
/usr/bin/python3 "$root/scripts/tools/plot_run.py" "$out/bent_bar" --compare "$out/bent_bar_baseline" "$out/bent_bar_no_rotation"
/usr/bin/python3 "$root/scripts/tools/experiment_report.py" "$out"
/usr/bin/python3 "$root/scripts/sweeps/compare_controllers.py" --sim "$sim" --out "$out/compare" || echo "  (compare_controllers.py failed)"
/usr/bin/python3 "$root/scripts/sweeps/compare_controllers.py" --sim "$sim" --out "$out/compare_paper" --paper || echo "  (compare_controllers.py --paper failed)"
/usr/bin/python3 "$root/scripts/sweeps/sweep_correction.py" --sim "$sim" --seeds 3 --out "$out/correction" > "$out/correction.log" 2>&1 || echo "  (sweep_correction.py failed: $out/correction.log)"
/usr/bin/python3 "$root/scripts/sweeps/sweep_force.py" --seeds 3 --out "$out/force" > "$out/force.log" 2>&1 || echo "  (sweep_force.py failed: $out/force.log)"
/usr/bin/python3 "$root/scripts/sweeps/force_targets.py" --sim "$sim" --seeds 3 --out "$out/force_targets" > "$out/force_targets.log" 2>&1 \
  || echo "  (force_targets.py: a scene misses the true-force targets or did not run: $out/force_targets.log)"
/usr/bin/python3 "$root/scripts/sweeps/sweep_speed.py" --sim "$sim" --seeds 3 --out "$out/speed" > "$out/speed.log" 2>&1 || echo "  (sweep_speed.py failed: $out/speed.log)"
/usr/bin/python3 "$root/scripts/sweeps/sweep_family.py" --sim "$sim" --seeds 3 --pool-seeds 15 --out "$out/family" > "$out/family.log" 2>&1 || echo "  (sweep_family.py failed: $out/family.log)"
/usr/bin/python3 "$root/scripts/sweeps/run_contours.py" --sim "$sim" --out "$out/contours" > "$out/contours.log" 2>&1 || echo "  (run_contours.py failed: $out/contours.log)"
/usr/bin/python3 "$root/scripts/sweeps/run_contours.py" --sim "$sim" --out "$out/contours_sensor_effects" --seeds 3 --sensor-effects \
  > "$out/contours_sensor_effects.log" 2>&1 || echo "  (run_contours.py --sensor-effects failed: $out/contours_sensor_effects.log)"

# The same experiments as deployed (the loop that runs on the robot, with the
# simulated arm and sensor swapped in).
deploy() {  # deploy EXPERIMENT: a non-zero exit is reported, not fatal
  local rc=0 log="$out/deploy_$1.log"
  bash "$root/scripts/run_deployment.sh" "$@" > "$log" 2>&1 || rc=$?
  tail -n 1 "$log"
  [ "$rc" -eq 0 ] || echo "  (deployment $*: exit code $rc, log in $log)"
}
while read -r name _; do deploy "$name"; done <<< "$experiments"
/usr/bin/python3 "$root/scripts/tools/experiment_report.py" "$out/deploy"

# The first day rehearsed at friOpen(2) (the KRC's cycle 2 ms: the copies of
# fri.yaml and the KRL program at 2 ms; out/rehearsal_2ms/, ~1.5 min), then
# at friOpen(1) below; both with the KRC's timing rule and $STIFFNESS limits.
bash "$root/scripts/rehearse_first_day.sh" --cycle-ms 2 --out "$out/rehearsal_2ms" > "$out/rehearsal_2ms.log" 2>&1 \
  || echo "  (rehearse_first_day.sh --cycle-ms 2: a step failed: $out/rehearsal_2ms.log)"
tail -n 1 "$out/rehearsal_2ms.log"

# The first day on the real arm, rehearsed against the simulated lab (the KRC
# over FRI and the WTS on a PTY: lab_sim): the bring-up tools in order, the dry
# run, the first touch and the edge exploration through the unchanged robot
# deployments, the KRC started as KRL starts it and interrupted in the slide
# (scripts/rehearse_first_day.sh -> out/rehearsal/rehearsal.md, rehearsal.png; ~1.5 min).
bash "$root/scripts/rehearse_first_day.sh" --out "$out/rehearsal" > "$out/rehearsal.log" 2>&1 \
  || echo "  (rehearse_first_day.sh: a step failed: $out/rehearsal.log)"
tail -n 1 "$out/rehearsal.log"

# Every robot experiment (experiments.yaml, robot: true) on the robot path:
# the unchanged robot deployment against lab_sim on its scene, in real time,
# one after the other, its verdict beside the headless one
# (scripts/run_robot_lab.sh -> out/robot_lab/<experiment>/summary.json;
# each costs its experiment's duration plus the deployer's start-up, ~6 min
# in all). One line per experiment on the console.
echo "robot path against lab_sim (scripts/run_robot_lab.sh -> $out/robot_lab/, log $out/robot_lab.log):"
{ bash "$root/scripts/run_robot_lab.sh" --out "$out/robot_lab" 2>&1 || echo "run_robot_lab: exit $? (a run failed or did not run)"; } \
  | tee "$out/robot_lab.log" | grep --line-buffered "^run_robot_lab: " || true

# Each fault of the pad and of the arm's wrench during the edge exploration,
# against its stated outcome, headless (seconds) and on the robot path against
# lab_sim (one run per fault in real time, ~10 min; scripts/sweeps/fault_table.py
# --robot -> out/faults/, docs/faults.md). One line per run on the console.
echo "faults, headless and on the robot path (scripts/sweeps/fault_table.py --robot -> $out/faults/, log $out/faults.log):"
{ /usr/bin/python3 "$root/scripts/sweeps/fault_table.py" --sim "$sim" --out "$out/faults" --robot 2>&1 \
    || echo "fault_table.py: a fault's outcome differs from the stated one (docs/faults.md)"; } \
  | tee "$out/faults.log" | grep --line-buffered "^\[\|^fault_table" || true

# The results pages from this run's outputs: docs/results.md,
# docs/results/results.json (with the commit and the machine), docs/img/ and
# the README's results table (scripts/tools/results_docs.py).
/usr/bin/python3 "$root/scripts/tools/results_docs.py" --out "$out" || echo "  (results_docs.py failed)"
