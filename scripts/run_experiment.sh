#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs the paper's
# experiments headless against the simulated LWR 4+ and WTS0614:
#   edge exploration (Sec. 5.2, Fig. 9/10), the bent bar with the proposed
#   controller, the Li et al. (RSS 2013) baseline and the no_rotation ablation
#   (Sec. 5.2.1, Fig. 12), tray co-manipulation (Sec. 5.3, Fig. 14), and a
#   sphere (point contact). Then the three controllers on every scene, with the
#   shipped programs (the force estimate) and with the paper's (Eq. 2's force
#   alone) (scripts/sweeps/compare_controllers.py -> out/compare/compare.md and
#   out/compare_paper/compare.md, ~10 s each), the force estimate against the
#   tactile force over edge radii, yaw and bend directions
#   (scripts/sweeps/sweep_force.py -> out/force/force.md, ~2 min), and the force
#   estimate's bound against the image (scripts/sweeps/sweep_correction.py ->
#   out/correction/correction.md, ~10 s), and the whole closed contours (ring,
#   rounded square, S-curve, gap bars; scripts/sweeps/run_contours.py ->
#   out/contours/contours.md, and with every sensor effect on, seeds 1-3,
#   out/contours_sensor_effects/contours.md; ~10 s).
# Results and PNG plots go to out/<scene>/. Then every experiment again as
# Orocos components under the OCL deployer (scripts/run_deployment.sh: the
# simulated deployment on tactile::SimClock, the experiment's state machine,
# OCL's reporter), into out/deploy/<scene>/, with its own out/deploy/report.md.
# Last, the first day on the real arm rehearsed against the simulated lab
# (scripts/rehearse_first_day.sh -> out/rehearsal/).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/setup/setup_deps.sh"
bash "$root/scripts/setup/setup_orocos.sh"
bash "$root/scripts/setup/build.sh"
sim="$root/build/bin/tactile_sim"
out="$root/out"
mkdir -p "$out"

run() {  # run SCENE DIR [args]: a non-zero exit is reported, not fatal (the no_rotation ablation is expected to fail)
  local scene="$1" dir="$2"; shift 2
  local rc=0
  "$sim" run "$root/sim/scenes/$scene.yaml" --out "$out/$dir" "$@" || rc=$?
  [ "$rc" -eq 0 ] || echo "  ($scene $*: exit code $rc, status in $out/$dir/summary.json)"
}

run edge_exploration edge_exploration
run bent_bar bent_bar --controller proposed
run bent_bar bent_bar_baseline --controller baseline
run bent_bar bent_bar_no_rotation --controller no_rotation
run co_manipulation co_manipulation
run sphere_table sphere_table
# The bent bar to its end cap (bent_bar_to_end_cap.yaml: bent_bar.yaml's program, ending at the bar's end).
run bent_bar_fused bent_bar_fused
/usr/bin/python3 "$root/scripts/tools/plot_run.py" "$out/bent_bar" --compare "$out/bent_bar_baseline" "$out/bent_bar_no_rotation"
/usr/bin/python3 "$root/scripts/tools/experiment_report.py" "$out"
/usr/bin/python3 "$root/scripts/sweeps/compare_controllers.py" --sim "$sim" --out "$out/compare" || echo "  (compare_controllers.py failed)"
/usr/bin/python3 "$root/scripts/sweeps/compare_controllers.py" --sim "$sim" --out "$out/compare_paper" --paper || echo "  (compare_controllers.py --paper failed)"
/usr/bin/python3 "$root/scripts/sweeps/sweep_correction.py" --sim "$sim" --seeds 3 --out "$out/correction" > "$out/correction.log" 2>&1 || echo "  (sweep_correction.py failed: $out/correction.log)"
/usr/bin/python3 "$root/scripts/sweeps/sweep_force.py" --seeds 3 --out "$out/force" > "$out/force.log" 2>&1 || echo "  (sweep_force.py failed: $out/force.log)"
/usr/bin/python3 "$root/scripts/sweeps/force_targets.py" --sim "$sim" --seeds 3 --out "$out/force_targets" > "$out/force_targets.log" 2>&1 \
  || echo "  (force_targets.py: a scene misses the true-force targets or did not run: $out/force_targets.log)"
/usr/bin/python3 "$root/scripts/sweeps/run_contours.py" --sim "$sim" --out "$out/contours" > "$out/contours.log" 2>&1 || echo "  (run_contours.py failed: $out/contours.log)"
/usr/bin/python3 "$root/scripts/sweeps/run_contours.py" --sim "$sim" --out "$out/contours_sensor_effects" --seeds 3 --sensor-effects \
  > "$out/contours_sensor_effects.log" 2>&1 || echo "  (run_contours.py --sensor-effects failed: $out/contours_sensor_effects.log)"

# The same experiments as deployed (the loop that runs on the robot, with the
# simulated arm and sensor swapped in).
deploy() {  # deploy EXPERIMENT [--controller C]: a non-zero exit is reported, not fatal
  local rc=0 log="$out/deploy_$1${2:+_${3:-}}.log"
  bash "$root/scripts/run_deployment.sh" "$@" > "$log" 2>&1 || rc=$?
  tail -n 1 "$log"
  [ "$rc" -eq 0 ] || echo "  (deployment $*: exit code $rc, log in $log)"
}
deploy edge_exploration
deploy bent_bar
deploy bent_bar --controller baseline
deploy bent_bar --controller no_rotation
deploy bent_bar_fused
deploy co_manipulation
deploy sphere_table
deploy ring
deploy gap_bars
/usr/bin/python3 "$root/scripts/tools/experiment_report.py" "$out/deploy"

# The first day on the real arm, rehearsed against the simulated lab (the KRC
# over FRI and the WTS on a PTY: lab_sim): the bring-up tools in order, the dry
# run, the first touch and the edge exploration through the unchanged robot
# deployments, the KRC started as KRL starts it and interrupted in the slide
# (scripts/rehearse_first_day.sh -> out/rehearsal/rehearsal.md, rehearsal.png; ~1.5 min).
bash "$root/scripts/rehearse_first_day.sh" --out "$out/rehearsal" > "$out/rehearsal.log" 2>&1 \
  || echo "  (rehearse_first_day.sh: a step failed: $out/rehearsal.log)"
tail -n 1 "$out/rehearsal.log"

# The results pages from this run's outputs: docs/results.md,
# docs/results/results.json (with the commit and the machine), docs/img/ and
# the README's results table (scripts/tools/results_docs.py).
/usr/bin/python3 "$root/scripts/tools/results_docs.py" --out "$out" || echo "  (results_docs.py failed)"
