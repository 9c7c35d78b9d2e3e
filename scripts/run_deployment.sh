#!/usr/bin/env bash
# Runs one experiment as Orocos components under the OCL deployer, on the
# simulated LWR 4+ and WTS0614, headless, and writes what `tactile_sim run`
# writes for it: out/deploy/<experiment>[_baseline|_no_rotation]/timeseries.csv,
# summary.json and the PNG plots of scripts/tools/plot_run.py.
#
#   scripts/run_deployment.sh EXPERIMENT [--controller proposed|baseline|no_rotation]
#     EXPERIMENT: a name of the experiment registry (experiments.yaml; the
#       usage lists them): its scene, program, controller and state machine
#     --controller baseline|no_rotation: the registry entries
#       bent_bar_baseline / bent_bar_no_rotation (EXPERIMENT bent_bar), as
#       before the registry; proposed: EXPERIMENT itself
#
# It runs deployments/sim_run.ops with TACTILE_EXPERIMENT=<entry> and
# `deployer-gnulinux --check -s` from deployments/ (the deployer exits after
# the script: 0, or 255 at the first failed step, named in the log). The
# simulated loop runs on
# tactile::SimClock as fast as possible, the loop of `tactile_sim run` (same
# stages, schedule, seed and end rule), with the experiment's state machine in
# the servo and OCL::FileReporting sampling every servo cycle. The reporter's
# file (deployments/<entry>_sim.dat) is moved to the output directory
# and turned into timeseries.csv and summary.json by `tactile_sim summarize`
# (the runner's own rows and metrics; the reporter keeps 6 significant
# digits). One run at a time (the report file and deployments/orocos.log are
# per directory). A robot run's table is converted by scripts/tools/deployment_to_run.py.
# Environment: BUILD (default <repo>/build), OROCOS (default /opt/orocos),
# DEPLOYER (default $OROCOS/bin/deployer-gnulinux; scripts/realtime/sanitize.sh sets its
# wrapper), DEPLOY_OUT (default <repo>/out/deploy; the ctests use the build tree).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD:-$root/build}"
orocos="${OROCOS:-/opt/orocos}"
py=/usr/bin/python3

registry="$root/experiments.yaml"
# One field of the registry entry $1 ($2: a key, e.g. scene), or the names (no arguments).
registry_get() {
  if [ $# -eq 0 ]; then "$py" "$root/scripts/tools/registry.py" --file "$registry" names
  else "$py" "$root/scripts/tools/registry.py" --file "$registry" get "$1" "$2"; fi
}
names="$(registry_get)"
usage() { echo "usage: $0 EXPERIMENT [--controller proposed|baseline|no_rotation]" >&2
          echo "  EXPERIMENT (experiments.yaml): $names" >&2; exit 2; }
[ $# -ge 1 ] || usage
exp="$1"; shift
controller=proposed
while [ $# -gt 0 ]; do
  case "$1" in
    --controller) [ $# -ge 2 ] || usage; controller="$2"; shift 2 ;;
    *) usage ;;
  esac
done
case "$controller" in
  proposed) run="$exp" ;;
  baseline|no_rotation) run="${exp}_$controller" ;;
  *) usage ;;
esac
case " $names " in
  *" $run "*) ;;
  *) echo "$0: no experiment $run in $registry (experiments: $names)" >&2; exit 2 ;;
esac
scene="$root/$(registry_get "$run" scene)"
program="$root/$(registry_get "$run" program)"
controller="$(registry_get "$run" controller)"  # '': the program's controller.mode

deployer="${DEPLOYER:-$orocos/bin/deployer-gnulinux}"
[ -x "$deployer" ] || { echo "$0: no OCL deployer at $deployer" >&2; exit 1; }
[ -d "$build/lib/orocos" ] || { echo "$0: no RTT components in $build/lib/orocos (build with -DTACTILE_WITH_RTT=ON)" >&2; exit 1; }
out="${DEPLOY_OUT:-$root/out/deploy}/$run"
mkdir -p "$out"
dep="$root/deployments"
report="$dep/${run}_sim.dat"
rm -f "$report"

echo "run_deployment: $run (deployments/sim_run.ops, TACTILE_EXPERIMENT=$run) -> $out"
rc=0
(cd "$dep" && TACTILE_EXPERIMENT="$run" RTT_COMPONENT_PATH="$build/lib/orocos:$orocos/lib/orocos" \
   "$deployer" --check -linfo -s sim_run.ops < /dev/null) > "$out/deployer.log" 2>&1 || rc=$?
cp "$dep/orocos.log" "$out/orocos.log" 2>/dev/null || true
grep -E "deployment step failed|status at the end|state machine .* at the end|\[(BentBar|CoManipulation|Sphere|Edge|Contour|FirstTouch|TimedPhase)[A-Za-z]*\]" "$out/deployer.log" | sed 's/^[0-9.]* \[[^]]*\]\[[^]]*\] //' || true
if [ ! -s "$report" ]; then
  echo "run_deployment: no report file (deployer exit $rc); see $out/deployer.log" >&2
  exit 1
fi
mv "$report" "$out/report.dat"
clock=$(sed -n 's/.*clock status at the end: \([a-z_]*\) exit_code \([0-9-]*\) sim_time \([0-9.e+-]*\).*/\1 \2 \3/p' "$out/deployer.log" | tail -1)
extra=()
if [ -n "$clock" ]; then
  read -r status exit_code sim_time <<< "$clock"
  extra=(--sim-time "$sim_time")
else
  status=deployment_failed; exit_code=8  # 3-7: the loop's own end statuses (tactile_sim)
fi
src=0
"$build/bin/tactile_sim" summarize "$scene" "$out/report.dat" --out "$out" --program "$program" ${controller:+--controller "$controller"} \
  --status "$status" --exit-code "$exit_code" "${extra[@]}" --no-plots || src=$?
[ "$src" -le 8 ] || { echo "run_deployment: tactile_sim summarize failed ($src)" >&2; exit 1; }
"$py" "$root/scripts/tools/plot_run.py" "$out"
# Another controller on the bent bar's scene: compared with the proposed one's run.
if [ "$run" != bent_bar ] && [ "$scene" = "$root/params/scenes/bent_bar.yaml" ] && [ -f "$root/out/deploy/bent_bar/summary.json" ]; then
  "$py" "$root/scripts/tools/plot_run.py" "$root/out/deploy/bent_bar" --compare "$out"
fi
echo "run_deployment: deployer exit $rc, run status $status; $out/{timeseries.csv,summary.json,*.png}"
exit "$rc"
