#!/usr/bin/env bash
# The robot path against the simulated lab: experiments of the registry
# (experiments.yaml, robot: true) run through the UNCHANGED robot deployment
# (scripts/run_robot.sh: deployments/robot.ops, then experiment_finish.ops)
# against lab_sim (the KRC over FRI on loopback UDP, the WTS0614 on a PTY, one
# simulated world), each to its state machine's end, one after the other.
#
#   scripts/run_robot_lab.sh [EXPERIMENT ...] [--scene FILE] [--out DIR]
#                            [--port P] [--timeout S] [-- LAB_SIM_ARGS ...]
#     EXPERIMENT  a robot: true entry of experiments.yaml; none: all of them
#     --scene F   the world lab_sim simulates (default: the experiment's own
#                 scene, params/scenes/*.yaml); any scene file, e.g. one with a
#                 `faults:` list (params/scenes/faults/*.yaml); one experiment only
#     --out DIR   where the runs go (default out/robot_lab): DIR/<experiment>/
#     --port P    the FRI bridge's UDP port on loopback (default 49975)
#     --timeout S longest wall-clock wait for the state machine (default 240 s)
#     -- ARGS     passed on to lab_sim (e.g. --krc "0:friOpen,2:friStart")
#
# Per experiment, DIR/<experiment>/ holds: deployments/ (the staged copy of
# deployments/, tests/lab_sim/lab_robot_common.sh: the bridge's port and the
# PTY, nothing else changed), lab_sim.log, truth.csv (lab_sim's ground truth),
# run/ (run_robot.sh's: deployer.log, report.dat, timeseries.csv, summary.json
# and plots), summary.json (run/summary.json with the truth's figures, the
# scene's criteria judged on them and robot_verdict: "pass" when the state
# machine ended FINISHED and the true force stayed <= 7 N;
# scripts/tools/lab_run_summary.py) and truth.png. One line per experiment on
# the console: its verdict, true force max, slide speed and wall time.
# lab_sim runs in real time: each run costs its experiment's duration plus the
# deployer's start-up. UDP: one run at a time per --port on the machine (the
# ctests that run it hold the lab_sim_udp resource lock).
# Exit: 0 every run's verdict pass, 3 a run failed (the others still run),
# 1 set-up error, 2 usage.
# Environment: BUILD (default <repo>/build), OROCOS, DEPLOYER.
set -uo pipefail
name=run_robot_lab
# root, build, orocos, deployer, rt_stage_deployments, pids + cleanup trap
source "$(dirname "${BASH_SOURCE[0]}")/realtime/rt_common.sh"
source "$root/tests/lab_sim/lab_robot_common.sh"  # lab_robot_stage, lab_robot_start, lab_robot_run
py=/usr/bin/python3
registry_get() { "$py" "$root/scripts/tools/registry.py" --file "$root/experiments.yaml" "$@"; }
usage() { sed -n '7,15p' "$0" | sed 's/^# \{0,1\}//' >&2
          echo "  robot experiments (experiments.yaml): $(registry_get names --robot | tr '\n' ' ')" >&2; exit 2; }

exps=()
scene_arg=""
out_root="$root/out/robot_lab"
port=49975
timeout=240
lab_args=()
while [ $# -gt 0 ]; do
  case "$1" in
    --scene) [ $# -ge 2 ] || usage; scene_arg="$(cd "$(dirname "$2")" && pwd)/$(basename "$2")"; shift 2 ;;
    --out) [ $# -ge 2 ] || usage; mkdir -p "$2"; out_root="$(cd "$2" && pwd)"; shift 2 ;;
    --port) [ $# -ge 2 ] || usage; port="$2"; shift 2 ;;
    --timeout) [ $# -ge 2 ] || usage; timeout="$2"; shift 2 ;;
    --) shift; lab_args=("$@"); break ;;
    -*) usage ;;
    *) exps+=("$1"); shift ;;
  esac
done
robot_names=" $(registry_get names --robot | tr '\n' ' ') "
[ ${#exps[@]} -gt 0 ] || read -r -a exps <<< "$robot_names"
for e in "${exps[@]}"; do
  case "$robot_names" in *" $e "*) ;; *) echo "$name: no robot experiment $e in experiments.yaml (robot: true:$robot_names)" >&2; exit 2 ;; esac
done
[ -z "$scene_arg" ] || [ ${#exps[@]} -eq 1 ] || { echo "$name: --scene takes one experiment" >&2; exit 2; }
[ -z "$scene_arg" ] || [ -f "$scene_arg" ] || { echo "$name: no scene file $scene_arg" >&2; exit 2; }
case "$port" in ''|*[!0-9]*) echo "$name: --port must be a UDP port number" >&2; exit 2 ;; esac

# run_one EXPERIMENT K N: one experiment to its end, its summary and one console line.
failed=0
run_one() {
  local exp="$1" dir="$out_root/$1" t0 scene program mode line
  scene="${scene_arg:-$root/$(registry_get get "$exp" scene)}"
  program="$root/$(registry_get get "$exp" program)"
  mode="$(registry_get get "$exp" controller)"
  echo "$name: [$2/$3] $exp on $(basename "$scene") -> $dir"
  t0=$(date +%s)
  lab_robot_stage "$dir" "$port"
  lab_robot_start "$dir" "$port" "$scene" --program "$program" --truth-out "$dir/truth.csv" "${lab_args[@]}"
  lab_robot_run "$exp" "$dir" "$timeout" > "$dir/run_robot.out"
  pids=()  # lab_sim has been waited for: no pid of this run left to clean up
  if [ ! -s "$dir/run/summary.json" ]; then
    echo "$name: [$2/$3] $exp: FAIL: no report (run_robot.sh exit $dep_rc, lab_sim exit $lab_rc): $dir/run_robot.log"
    failed=1
    return
  fi
  line=$("$py" "$root/scripts/tools/lab_run_summary.py" "$dir" --scene "$scene" --program "$program" \
           --controller-mode "$mode" --experiment "$exp" --deployer-exit "$dep_rc" --lab-exit "$lab_rc" 2>"$dir/summary.err" \
         | grep '^lab_run_summary:') || { echo "$name: [$2/$3] $exp: FAIL: summary: $(tail -n 1 "$dir/summary.err")"; failed=1; return; }
  grep -q '"robot_verdict": "pass"' "$dir/summary.json" || failed=1
  echo "$name: [$2/$3] ${line#lab_run_summary: } ($(( $(date +%s) - t0 )) s)"
}
k=0
for e in "${exps[@]}"; do
  k=$((k + 1))
  run_one "$e" "$k" "${#exps[@]}"
done
[ "$failed" -eq 0 ] && exit 0
exit 3
