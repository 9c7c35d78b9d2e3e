#!/usr/bin/env bash
# The unattended robot run: one experiment on the real KUKA LWR 4+ and WTS0614
# (or on the simulated lab, scripts/rehearse_first_day.sh), from the deployer's
# start to the end of the experiment's state machine, and its verdict as the
# exit code.
#
#   scripts/run_robot.sh EXPERIMENT [--dry-run] [--timeout S] [--out DIR]
#                        [--deployments DIR] [--ros]
#     EXPERIMENT   an entry of the experiment registry (experiments.yaml) with
#                  robot: true (listed below)
#     --dry-run    the FRI bridge holds the arm in command mode whatever the
#                  servo asks; the servo computes and records its commands as if
#                  the arm followed (bring-up, docs/bringup.md step 4)
#     --timeout S  longest wait for the state machine, wall clock (default 600 s:
#                  the KRC's friOpen/friStart by the operator included)
#     --out DIR    where the run goes (default out/robot/<experiment>[_dry_run])
#     --deployments DIR  the deployment folder (default deployments/; the
#                  rehearsal passes a copy rewired to the simulated peers)
#     --ros        robot_ros.ops (ROS topics for rviz) instead of robot.ops
#
# It runs the interactive entry deployments/robot.ops unchanged with
# TACTILE_EXPERIMENT=EXPERIMENT, with Guard.registry_file (this tree's
# experiments.yaml), Guard.timeout and Guard.dry_run set around its own Guard lines, then
# experiment_finish.ops (waits for FINISHED or FAILED, stops every
# component), under `deployer-gnulinux --check` so that the deployer exits when
# the script ends: 0 when the state machine ended FINISHED, 255 after a failed
# run or step (tactile::DeployGuard's verdict, the log's last "[Guard] verdict:"
# line: "FAILED: the state machine ... ended in FAILED (servo status ...)" or
# "FAILED: deployment step failed: ..."). The reporter's table, written up to
# the run's end or fault, becomes timeseries.csv, summary.json (its status
# names the fault, fault_time_s when it happened; the scene's metrics give the
# slide and the scored window) and the PNG plots (deployment_to_run.py,
# plot_run.py). The KRC may start in monitor mode: the servo holds until the
# operator's friStart (status waiting_for_robot), and the wait does not count
# against the state machine's own timeouts.
# Exit: 0 FINISHED, 1 set-up or report error, 2 usage, 255 the run failed.
# Environment: BUILD (default <repo>/build), OROCOS (default /opt/orocos),
# DEPLOYER (default $OROCOS/bin/deployer-gnulinux).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD:-$root/build}"
orocos="${OROCOS:-/opt/orocos}"
py=/usr/bin/python3

registry="$root/experiments.yaml"
# The registry's robot experiments (no argument), or one field ($1 entry, $2 key).
registry_get() {
  if [ $# -eq 0 ]; then "$py" "$root/scripts/tools/registry.py" --file "$registry" names --robot
  else "$py" "$root/scripts/tools/registry.py" --file "$registry" get "$1" "$2"; fi
}
usage() { sed -n '6,19p' "$0" | sed 's/^# \{0,1\}//' >&2
          echo "  robot experiments (experiments.yaml): $(registry_get)" >&2; exit 2; }
[ $# -ge 1 ] || usage
exp="$1"; shift
dry=false
timeout=600
out=""
dep="$root/deployments"
suffix=robot
while [ $# -gt 0 ]; do
  case "$1" in
    --dry-run) dry=true; shift ;;
    --timeout) [ $# -ge 2 ] || usage; timeout="$2"; shift 2 ;;
    --out) [ $# -ge 2 ] || usage; out="$2"; shift 2 ;;
    --deployments) [ $# -ge 2 ] || usage; dep="$(cd "$2" && pwd)"; shift 2 ;;
    --ros) suffix=robot_ros; shift ;;
    *) usage ;;
  esac
done
case "$timeout" in ''|*[!0-9.]*) echo "run_robot: --timeout must be a number of seconds" >&2; exit 2 ;; esac
robot_names="$(registry_get)"
case " $robot_names " in
  *" $exp "*) ;;
  *) echo "run_robot: no robot experiment $exp in $registry (robot: true: $robot_names)" >&2; exit 2 ;;
esac
entry="$dep/$suffix.ops"
[ -f "$entry" ] || { echo "run_robot: no $entry" >&2; exit 2; }
grep -q '^Guard.report_file = ' "$entry" || { echo "run_robot: $entry sets no Guard.report_file" >&2; exit 1; }
deployer="${DEPLOYER:-$orocos/bin/deployer-gnulinux}"
[ -x "$deployer" ] || { echo "run_robot: no OCL deployer at $deployer" >&2; exit 1; }
[ -d "$build/lib/orocos" ] || { echo "run_robot: no RTT components in $build/lib/orocos" >&2; exit 1; }
name="$exp"; [ "$dry" = true ] && name="${exp}_dry_run"
out="${out:-$root/out/robot/$name}"
mkdir -p "$out"
report="${exp}_$suffix.dat"  # the entry's Guard.report_file
program="$root/$(registry_get "$exp" program)"
scene="$root/$(registry_get "$exp" scene)"
controller_mode="$(registry_get "$exp" controller)"
rm -f "$dep/$report"
# The program within the bridge's rate limits (the fri.yaml its fri_bridge.cpf reads), else no run.
fri_yaml="$(sed -n '/name="param_file"/,/<\/simple>/ s#.*<value>\(.*\)</value>.*#\1#p' "$dep/fri_bridge.cpf")"
case "$fri_yaml" in /*) ;; *) fri_yaml="$dep/$fri_yaml" ;; esac
"$py" "$root/scripts/tools/check_robot_limits.py" --fri-yaml "$fri_yaml" "$exp" > "$out/check_robot_limits.log" 2>&1 \
  || { cat "$out/check_robot_limits.log" >&2; echo "run_robot: $exp's program asks for more than the bridge lets through" >&2; exit 1; }

# The entry, with this run's settings after its own Guard lines, then the finish.
gen="$dep/.run_robot_${exp}_$$.ops"
trap 'rm -f "$gen"' EXIT
sed -e "/^loadComponent(\"Guard\"/a Guard.registry_file = \"$registry\"" \
    -e "/^Guard.report_file = /a Guard.timeout = $timeout\nGuard.dry_run = $dry" "$entry" > "$gen"
cat >> "$gen" <<'EOF'
Guard.step(runScript("experiment_finish.ops"), "experiment_finish.ops")
var int experiment_run = Guard.finish()
EOF

echo "run_robot: $exp ($(basename "$entry"), dry run $dry, timeout $timeout s) -> $out"
t0=$(date +%s%N)
rc=0
(cd "$dep" && TACTILE_EXPERIMENT="$exp" RTT_COMPONENT_PATH="$build/lib/orocos:$orocos/lib/orocos" \
   "$deployer" --check -linfo -s "$(basename "$gen")" < /dev/null) > "$out/deployer.log" 2>&1 || rc=$?
ms=$(( ($(date +%s%N) - t0) / 1000000 ))
wall="$((ms / 1000)).$(printf %03d $((ms % 1000)))"
cp "$dep/orocos.log" "$out/orocos.log" 2>/dev/null || true
grep -E "deployment step failed|DRY RUN|status at the end|KRL program at the end|\[Guard\] (run|verdict)|\[(BentBar|CoManipulation|Sphere|Edge|Contour|FirstTouch|TimedPhase)[A-Za-z]*\]" \
  "$out/deployer.log" | sed 's/^[0-9.]* \[[^]]*\]\[[^]]*\] //' || true
if [ ! -s "$dep/$report" ]; then
  echo "run_robot: no report file $report (deployer exit $rc); see $out/deployer.log" >&2
  [ "$rc" -ne 0 ] && exit "$rc"
  exit 1
fi
mv "$dep/$report" "$out/report.dat"
robot_status=$(sed -n 's/.*robot status at the end: \([a-z_]*\).*/\1/p' "$out/deployer.log" | tail -1)
verdict=$(sed -n 's/.*\[Guard\] verdict: \(.*\) (deployer exit [0-9]*).*/\1/p' "$out/deployer.log" | tail -1)
"$py" "$root/scripts/tools/deployment_to_run.py" "$out/report.dat" "$out" --program "$program" --controller-mode "$controller_mode" \
  --scene "$scene" --experiment "$name" --source robot --deployer-exit "$rc" --wall-time "$wall" \
  ${robot_status:+--robot-status "$robot_status"} ${verdict:+--verdict "$verdict"} \
  || { echo "run_robot: the report could not be converted" >&2; exit 1; }
"$py" "$root/scripts/tools/plot_run.py" "$out" || { echo "run_robot: plotting failed" >&2; exit 1; }
if [ "$rc" -eq 0 ]; then
  echo "run_robot: PASS: $exp ended FINISHED; $out/{timeseries.csv,summary.json,*.png}"
else
  echo "run_robot: FAIL: $exp (deployer exit $rc): ${verdict:-the first failed step is above}; $out/deployer.log"
fi
exit "$rc"
