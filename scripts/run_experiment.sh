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
# (sweep_speed.py -> out/speed/) and on the family of bars of params/scenes/curved
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
#
# Order: the Debian packages, the simulator alone, and the registry's
# experiments headless (the first results, a few minutes from a fresh machine);
# then Orocos and the whole build, and the same experiments as deployed (about
# a minute on a built tree); then the sweeps, the rehearsals, the robot path
# and the faults, each a numbered stage that prints its progress every 30 s
# and its time. `--quick` stops after the experiments and their deployments
# (the results pages are then not regenerated).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
quick=0
case "${1:-}" in
  --quick) quick=1 ;;
  "") ;;
  *) echo "usage: run_experiment.sh [--quick]   (--quick: the experiments and their deployments only)" >&2; exit 2 ;;
esac
# First the Debian packages and the simulator alone, so that the headless
# experiments show a result before Orocos is built: a fresh build directory is
# configured without the RTT layer for this step (a tree already configured with
# it keeps its configuration), and the full configuration later reuses the
# simulator's objects.
bash "$root/scripts/setup/setup_deps.sh"
bash "$root/scripts/setup/realtime_host.sh"
first_rtt=OFF
if grep -qs '^TACTILE_WITH_RTT:STRING=ON$' "$root/build/CMakeCache.txt" && [ "${TACTILE_WITH_RTT:-ON}" != OFF ]; then first_rtt=ON; fi
if [ "$first_rtt" = OFF ]; then
  TACTILE_WITH_RTT=OFF TACTILE_WITH_ROS=OFF TACTILE_BUILD_TARGETS=tactile_sim bash "$root/scripts/setup/build.sh"
else
  TACTILE_BUILD_TARGETS=tactile_sim bash "$root/scripts/setup/build.sh"
fi
sim="$root/build/bin/tactile_sim"
out="$root/out"
mkdir -p "$out"
t_main=$SECONDS

run() {  # run NAME SCENE [args]: a non-zero exit is reported, not fatal (the no_rotation ablation is expected to fail)
  local name="$1" scene="$2"; shift 2
  local rc=0
  "$sim" run "$root/$scene" --out "$out/$name" "$@" || rc=$?
  [ "$rc" -eq 0 ] || echo "  ($name $*: exit code $rc, status in $out/$name/summary.json)"
}

# stage LABEL LOG CMD...: runs CMD with its output in LOG; prints the start,
# every 30 s the log's last progress line ("[k/n] ..."), and the time it took.
# A failure is reported with the log's path, not fatal (the next stage runs).
n_stages=8
k_stage=0
stage() {
  local label="$1" log="$2"; shift 2
  k_stage=$((k_stage + 1))
  local t0=$SECONDS
  echo "main job: [$k_stage/$n_stages] $label (log $log)"
  "$@" > "$log" 2>&1 &
  local pid=$! last=$SECONDS rc=0
  while kill -0 "$pid" 2> /dev/null; do
    sleep 2
    if [ $((SECONDS - last)) -ge 30 ]; then
      last=$SECONDS
      local line
      line="$(grep -aE '^\[(robot |pooled )?[0-9]+/[0-9]+\]|^run_robot_lab: \[' "$log" | tail -n 1 | cut -c1-110 || true)"
      echo "  ... $((SECONDS - t0)) s${line:+: $line}"
    fi
  done
  wait "$pid" || rc=$?
  if [ "$rc" -eq 0 ]; then
    echo "  done in $((SECONDS - t0)) s"
  else
    echo "  ($label: exit code $rc after $((SECONDS - t0)) s; log $log)"
  fi
}

# Every experiment of the registry (experiments.yaml): its scene with its
# controller, into out/<experiment>/.
registry() {  # one line per registry entry: NAME SCENE PROGRAM CONTROLLER ('-' for the program's own)
  /usr/bin/python3 "$root/scripts/tools/registry.py" rows
}
experiments="$(registry)"
echo "main job: the registry's experiments headless (tactile_sim -> $out/<experiment>/)"
while read -r name scene program controller; do
  if [ "$controller" = "-" ]; then run "$name" "$scene" --program "$root/$program"
  else run "$name" "$scene" --program "$root/$program" --controller "$controller"; fi
done <<< "$experiments"
/usr/bin/python3 "$root/scripts/tools/plot_run.py" "$out/bent_bar" --compare "$out/bent_bar_baseline" "$out/bent_bar_no_rotation"
/usr/bin/python3 "$root/scripts/tools/experiment_report.py" "$out"
echo "main job: the experiments headless in $((SECONDS - t_main)) s"

# Orocos and rtt_ros (when missing), then the whole build: the RTT layer, the
# ROS face, the tools and the tests.
bash "$root/scripts/setup/setup_orocos.sh"
bash "$root/scripts/setup/build.sh"
t_built=$SECONDS

# The same experiments as deployed (the loop that runs on the robot, with the
# simulated arm and sensor swapped in).
deploy() {  # deploy EXPERIMENT: a non-zero exit is reported, not fatal
  local rc=0 log="$out/deploy_$1.log"
  bash "$root/scripts/run_deployment.sh" "$@" > "$log" 2>&1 || rc=$?
  tail -n 1 "$log"
  [ "$rc" -eq 0 ] || echo "  (deployment $*: exit code $rc, log in $log)"
}
echo "main job: the same experiments deployed under the OCL deployer (scripts/run_deployment.sh -> $out/deploy/)"
while read -r name _; do deploy "$name"; done <<< "$experiments"
/usr/bin/python3 "$root/scripts/tools/experiment_report.py" "$out/deploy"
echo "main job: the deployments in $((SECONDS - t_built)) s"
if [ "$quick" -eq 1 ]; then
  echo "main job: --quick: the sweeps, the rehearsals, the robot path and the faults not run; docs/results.md not regenerated"
  exit 0
fi

py() { /usr/bin/python3 "$@"; }
sweeps() {  # the controllers compared, the force estimate and its bound, the true force on every scene, the speed
  py "$root/scripts/sweeps/compare_controllers.py" --sim "$sim" --out "$out/compare" || echo "compare_controllers.py failed"
  py "$root/scripts/sweeps/compare_controllers.py" --sim "$sim" --out "$out/compare_paper" --paper || echo "compare_controllers.py --paper failed"
  py "$root/scripts/sweeps/sweep_correction.py" --sim "$sim" --seeds 3 --out "$out/correction" > "$out/correction.log" 2>&1 || echo "sweep_correction.py failed: $out/correction.log"
  py "$root/scripts/sweeps/sweep_force.py" --seeds 3 --out "$out/force" > "$out/force.log" 2>&1 || echo "sweep_force.py failed: $out/force.log"
  py "$root/scripts/sweeps/force_targets.py" --sim "$sim" --seeds 3 --out "$out/force_targets" > "$out/force_targets.log" 2>&1 \
    || echo "force_targets.py: a scene misses the true-force targets or did not run: $out/force_targets.log"
  py "$root/scripts/sweeps/sweep_speed.py" --sim "$sim" --seeds 3 --out "$out/speed" > "$out/speed.log" 2>&1 || echo "sweep_speed.py failed: $out/speed.log"
}
stage "sweeps: controllers, force estimate, force targets, slide speed (~1 min)" "$out/sweeps.log" sweeps
stage "the family of bent bars (sweep_family.py, ~4400 runs, ~3 min)" "$out/family.log" \
  py "$root/scripts/sweeps/sweep_family.py" --sim "$sim" --seeds 3 --pool-seeds 15 --out "$out/family"
stage "closed contours (run_contours.py)" "$out/contours.log" py "$root/scripts/sweeps/run_contours.py" --sim "$sim" --out "$out/contours"
stage "closed contours with every sensor effect (run_contours.py --sensor-effects)" "$out/contours_sensor_effects.log" \
  py "$root/scripts/sweeps/run_contours.py" --sim "$sim" --out "$out/contours_sensor_effects" --seeds 3 --sensor-effects

# The first day on the real arm, rehearsed against the simulated lab (the KRC
# over FRI and the WTS on a PTY: lab_sim): the bring-up tools in order, the dry
# run, the first touch and the edge exploration through the unchanged robot
# deployments, the KRC started as KRL starts it and interrupted in the slide
# (scripts/rehearse_first_day.sh -> out/rehearsal/rehearsal.md, rehearsal.png;
# ~1.5 min), first at friOpen(2) (the KRC's cycle 2 ms: the copies of fri.yaml
# and the KRL program at 2 ms; out/rehearsal_2ms/), then at friOpen(1); both
# with the KRC's timing rule and $STIFFNESS limits.
stage "the first day rehearsed at friOpen(2) (~1.5 min)" "$out/rehearsal_2ms.log" \
  bash "$root/scripts/rehearse_first_day.sh" --cycle-ms 2 --out "$out/rehearsal_2ms"
tail -n 1 "$out/rehearsal_2ms.log"
stage "the first day rehearsed at friOpen(1) (~1.5 min)" "$out/rehearsal.log" \
  bash "$root/scripts/rehearse_first_day.sh" --out "$out/rehearsal"
tail -n 1 "$out/rehearsal.log"

# Every robot experiment (experiments.yaml, robot: true) on the robot path:
# the unchanged robot deployment against lab_sim on its scene, in real time,
# one after the other, its verdict beside the headless one
# (scripts/run_robot_lab.sh -> out/robot_lab/<experiment>/summary.json;
# each costs its experiment's duration plus the deployer's start-up, ~6 min
# in all). One line per experiment on the console.
stage "every robot experiment on the robot path against lab_sim (~6 min)" "$out/robot_lab.log" \
  bash "$root/scripts/run_robot_lab.sh" --out "$out/robot_lab"
grep "^run_robot_lab: " "$out/robot_lab.log" || true

# Each fault of the pad and of the arm's wrench during the edge exploration,
# against its stated outcome, headless (seconds) and on the robot path against
# lab_sim (one run per fault in real time, ~10 min; scripts/sweeps/fault_table.py
# --robot -> out/faults/, docs/faults.md).
stage "faults, headless and on the robot path (fault_table.py --robot, ~10 min)" "$out/faults.log" \
  py "$root/scripts/sweeps/fault_table.py" --sim "$sim" --out "$out/faults" --robot
grep -a "^\[\|^Commit" "$out/faults.log" | grep -a "DIFFERS\|^Commit" || true

# The results pages from this run's outputs: docs/results.md,
# docs/results/results.json (with the commit and the machine), docs/img/ and
# the README's results table (scripts/tools/results_docs.py).
py "$root/scripts/tools/results_docs.py" --out "$out" || echo "  (results_docs.py failed)"
echo "main job: done in $((SECONDS - t_built)) s after the build"
