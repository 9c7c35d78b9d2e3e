#!/usr/bin/env bash
# Runs one experiment as Orocos components under the OCL deployer, on the
# simulated LWR 4+ and WTS0614, headless, and writes what `tactile_sim run`
# writes for it: out/deploy/<experiment>[_baseline|_no_rotation]/timeseries.csv,
# summary.json and the PNG plots of scripts/plot_run.py.
#
#   scripts/run_deployment.sh EXPERIMENT [--controller proposed|baseline|no_rotation]
#     EXPERIMENT: edge_exploration | bent_bar | bent_bar_fused (the force estimate) |
#       co_manipulation | sphere_table | ring | gap_bars (whole closed contours) |
#       first_touch (docs/bringup.md step 5)
#     --controller baseline: the Li et al. (RSS 2013) baseline, no_rotation: the
#       ablation (bent bar only; the servo's .cpf servo_bent_bar_<controller>.cpf,
#       the same program)
#
# It runs deployments/<experiment>_sim_run.ops with `deployer-gnulinux
# --check -s` from deployments/ (the deployer exits after the script: 0, or
# 255 at the first failed step, named in the log). The simulated loop runs on
# tactile::SimClock as fast as possible, the loop of `tactile_sim run` (same
# stages, schedule, seed and end rule), with the experiment's state machine in
# the servo and OCL::FileReporting sampling every servo cycle. The reporter's
# file (deployments/<experiment>_sim.dat) is moved to the output directory
# and turned into timeseries.csv and summary.json by `tactile_sim summarize`
# (the runner's own rows and metrics; the reporter keeps 6 significant
# digits). One run at a time (the report file and deployments/orocos.log are
# per directory). A robot run's table is converted by scripts/deployment_to_run.py.
# Environment: BUILD (default <repo>/build), OROCOS (default /opt/orocos),
# DEPLOYER (default $OROCOS/bin/deployer-gnulinux; scripts/sanitize.sh sets its
# wrapper), DEPLOY_OUT (default <repo>/out/deploy; the ctests use the build tree).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD:-$root/build}"
orocos="${OROCOS:-/opt/orocos}"
py=/usr/bin/python3

usage() { echo "usage: $0 edge_exploration|bent_bar|bent_bar_fused|co_manipulation|sphere_table|ring|gap_bars|first_touch [--controller proposed|baseline|no_rotation]" >&2; exit 2; }
[ $# -ge 1 ] || usage
exp="$1"; shift
controller=proposed
while [ $# -gt 0 ]; do
  case "$1" in
    --controller) [ $# -ge 2 ] || usage; controller="$2"; shift 2 ;;
    *) usage ;;
  esac
done
case "$exp" in
  edge_exploration) servo_cpf=servo_edge_exploration.cpf ;;
  bent_bar) servo_cpf=servo_bent_bar.cpf ;;
  bent_bar_fused) servo_cpf=servo_bent_bar_fused.cpf ;;
  co_manipulation) servo_cpf=servo_co_manipulation.cpf ;;
  sphere_table) servo_cpf=servo_edge_exploration.cpf ;;
  ring|gap_bars) servo_cpf=servo_closed_contour.cpf ;;
  first_touch) servo_cpf=servo_first_touch.cpf ;;
  *) usage ;;
esac
case "$controller" in
  proposed) run="$exp" ;;
  baseline|no_rotation)
    [ "$exp" = bent_bar ] || { echo "$0: --controller $controller: only the bent bar has a $controller deployment" >&2; exit 2; }
    run=bent_bar_$controller; servo_cpf=servo_bent_bar_$controller.cpf ;;
  *) usage ;;
esac

deployer="${DEPLOYER:-$orocos/bin/deployer-gnulinux}"
[ -x "$deployer" ] || { echo "$0: no OCL deployer at $deployer" >&2; exit 1; }
[ -d "$build/lib/orocos" ] || { echo "$0: no RTT components in $build/lib/orocos (build with -DTACTILE_WITH_RTT=ON)" >&2; exit 1; }
out="${DEPLOY_OUT:-$root/out/deploy}/$run"
mkdir -p "$out"
dep="$root/deployments"
report="$dep/${run}_sim.dat"
rm -f "$report"

echo "run_deployment: $run (deployments/${run}_sim_run.ops) -> $out"
rc=0
(cd "$dep" && RTT_COMPONENT_PATH="$build/lib/orocos:$orocos/lib/orocos" \
   "$deployer" --check -linfo -s "${run}_sim_run.ops" < /dev/null) > "$out/deployer.log" 2>&1 || rc=$?
cp "$dep/orocos.log" "$out/orocos.log" 2>/dev/null || true
grep -E "deployment step failed|status at the end|state machine .* at the end|\[(BentBar|CoManipulation|Sphere|Edge|Contour|FirstTouch)[A-Za-z]*\]" "$out/deployer.log" | sed 's/^[0-9.]* \[[^]]*\]\[[^]]*\] //' || true
if [ ! -s "$report" ]; then
  echo "run_deployment: no report file (deployer exit $rc); see $out/deployer.log" >&2
  exit 1
fi
mv "$report" "$out/report.dat"
scene="$root/sim/scenes/$exp.yaml"
clock=$(sed -n 's/.*clock status at the end: \([a-z_]*\) exit_code \([0-9-]*\) sim_time \([0-9.e+-]*\).*/\1 \2 \3/p' "$out/deployer.log" | tail -1)
extra=()
if [ -n "$clock" ]; then
  read -r status exit_code sim_time <<< "$clock"
  extra=(--sim-time "$sim_time")
else
  status=deployment_failed; exit_code=8  # 3-7: the loop's own end statuses (tactile_sim)
fi
src=0
"$build/bin/tactile_sim" summarize "$scene" "$out/report.dat" --out "$out" --controller "$controller" \
  --status "$status" --exit-code "$exit_code" "${extra[@]}" --no-plots || src=$?
[ "$src" -le 8 ] || { echo "run_deployment: tactile_sim summarize failed ($src)" >&2; exit 1; }
"$py" "$root/scripts/plot_run.py" "$out"
if [ "$run" != bent_bar ] && [ "$exp" = bent_bar ] && [ -f "$root/out/deploy/bent_bar/summary.json" ]; then
  "$py" "$root/scripts/plot_run.py" "$root/out/deploy/bent_bar" --compare "$out"
fi
echo "run_deployment: deployer exit $rc, run status $status; $out/{timeseries.csv,summary.json,*.png}"
exit "$rc"
