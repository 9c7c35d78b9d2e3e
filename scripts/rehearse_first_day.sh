#!/usr/bin/env bash
# The first day on the real arm (docs/bringup.md), rehearsed against the
# simulated lab: every step with the tool a lab runs on its own arm, in the
# same order, against simulated peers that speak the real protocols:
#   1 sensor       wts_check on a simulated WTS0614 (a PTY): device, rate,
#                  noise, stuck and dead taxels under a whole-pad press
#   2 calibration  a recording of the simulated pad under known loads
#                  (tactile_calibration_record), fitted by tactile_calibrate; the
#                  fitted file is the one the features read from here on
#   3 FRI link     fri_check --monitor against lab_sim's KRC in monitor mode
#   4 dry run      the robot deployment with the bridge's dry run
#                  (run_robot.sh --dry-run): the pad pressed, the servo computes
#                  and records, the arm is held
#   5 first touch  run_robot.sh first_touch: the KRC started as KRL starts it
#                  (friOpen, friStart 6 s later)
#   6 experiment   run_robot.sh edge_exploration with the KRC's friOpen,
#                  friStart, a quality drop to BAD and back, friStop and
#                  friStart in the middle of the slide: to the state machine's
#                  end, its results and plots
# Steps 3-6 run the UNCHANGED robot deployment (deployments/robot.ops, the registry's experiment)
# on a copy of deployments/ whose only changes are the bridge's UDP port, the
# WTS reader's device (the PTY) and, after step 2, the features' parameter
# file (the fitted calibration). lab_sim (devices/lab) is the KRC over UDP and the
# WTS on a PTY, both backed by one simulated world; its ground truth (never
# seen by the controller) checks each step (scripts/tools/rehearsal_report.py).
#
# The simulated KRC rates the link from the bridge's answers (lab_sim
# --quality-rule on: missed or late answers lower the quality, below OK it
# leaves command mode) and applies the KRL program's $STIFFNESS.MAXFORCE and
# CPMAXDELTA (lab_sim --krl): a step passes only without a KRC fault.
#
#   scripts/rehearse_first_day.sh [--out DIR] [--steps 1,2,3,4,5,6] [--cycle-ms 1|2]
#   --cycle-ms C  the FRI cycle, friOpen(C): the KRC sends every C ms, and the
#                 copies of fri.yaml (cycle_time_s) and krc/TactileServo.src
#                 (friOpen) the steps use say C, as a lab switching to C ms
#                 would change them (default 1)
# Prints PASS/FAIL per step and what to do next; writes DIR/rehearsal.md and
# DIR/rehearsal.png. Exit 0 when every step passed. Wall clock: about 3 min.
# Environment: BUILD (default <repo>/build), OROCOS (default /opt/orocos).
set -uo pipefail
name=rehearse_first_day
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# root, build, orocos, deployer, rt_stage_deployments, pids + cleanup trap
source "$root/scripts/realtime/rt_common.sh"
py=/usr/bin/python3
out="$root/out/rehearsal"
steps="1,2,3,4,5,6"
cycle_ms=1
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out="$2"; shift 2 ;;
    --steps) steps="$2"; shift 2 ;;
    --cycle-ms)
      case "$2" in 1|2) cycle_ms="$2" ;; *) echo "$name: --cycle-ms must be 1 or 2 (friOpen's ms)" >&2; exit 2 ;; esac
      shift 2 ;;
    *) sed -n '2,30p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2 ;;
  esac
done
mkdir -p "$out" && out="$(cd "$out" && pwd)"  # absolute: the steps run from other directories
for t in "$deployer" "$build/bin/lab_sim" "$build/bin/wts_check" "$build/bin/wts_sim" "$build/bin/fri_check" \
         "$build/bin/tactile_calibrate" "$build/bin/tactile_calibration_record"; do
  [ -x "$t" ] || { echo "$name: $t missing: build the project first (scripts/setup/build.sh, RTT on)" >&2; exit 1; }
done
port=49985          # the bridge's UDP port here (fri.yaml's 49938 may be in use on this host)
start_after=6       # s of monitor mode before friStart: the deployment is up by then
rm -rf "$out"
mkdir -p "$out"
rt_stage_deployments "$out"
dep="$out/deployments"
sed -i "/name=\"port\"/,/<\/simple>/ s#<value>-1</value>#<value>$port</value>#" "$dep/fri_bridge.cpf"
grep -q "<value>$port</value>" "$dep/fri_bridge.cpf" || { echo "$name: could not set the bridge's port" >&2; exit 1; }
# The FRI cycle: fri.yaml's cycle_time_s and the KRL program's friOpen, both
# copied with C ms (the one change a lab makes for another cycle), the
# bridge's copy of fri.yaml in the staged fri_bridge.cpf.
fri_yaml="$out/fri.yaml"
krl="$out/krc/TactileServo.src"
cycle_s=$(printf '0.%03d' "$cycle_ms")
sed -E "s#^( *cycle_time_s:) *[0-9.eE+-]+#\1 $cycle_s#" "$root/params/sensors/fri.yaml" > "$fri_yaml"
mkdir -p "$out/krc" && cp "$root"/krc/TactileServo.dat "$root"/krc/dlrrc.ini "$out/krc/"
sed -E "s#friOpen\( *1 *\)#friOpen($cycle_ms)#" "$root/krc/TactileServo.src" > "$krl"
grep -qE "^ *cycle_time_s: $cycle_s" "$fri_yaml" && grep -q "friOpen($cycle_ms)" "$krl" ||
  { echo "$name: could not set the cycle to $cycle_ms ms in $fri_yaml / $krl" >&2; exit 1; }
sed -i "s#<value>[^<]*fri.yaml</value>#<value>$fri_yaml</value>#" "$dep/fri_bridge.cpf"
grep -q "<value>$fri_yaml</value>" "$dep/fri_bridge.cpf" || { echo "$name: could not point the bridge at $fri_yaml" >&2; exit 1; }
# Step 0's check on the two copies: the KRC side agrees with the RT PC's files.
"$py" "$root/krc/check_krc_config.py" --krc "$out/krc" --fri-yaml "$fri_yaml" > "$out/check_krc_config.log" 2>&1 ||
  { echo "$name: check_krc_config.py on the $cycle_ms ms copies failed: $out/check_krc_config.log" >&2; exit 1; }
echo "== the FRI cycle: $cycle_ms ms (friOpen($cycle_ms), fri.cycle_time_s $cycle_s); the KRC's quality from the answers' timing, its \$STIFFNESS limits from $krl"
results=()
want() { case ",$steps," in *,"$1",*) return 0 ;; esac; return 1; }
verdict() {  # step title rc next
  if [ "$3" -eq 0 ]; then
    echo "== step $1 $2: PASS"
    results+=("$1|$2|PASS|")
  else
    echo "== step $1 $2: FAIL: $4"
    results+=("$1|$2|FAIL|$4")
  fi
}

# lab_sim SCENE KRC_SCRIPT DIR [args]: the simulated lab in the background, its PTY at $out/wts0.
lab_pid=""
start_lab() {
  local scene="$1" krc="$2" dir="$3"
  shift 3
  rm -f "$out/wts0"
  "${krc_prio[@]}" "$build/bin/lab_sim" "$scene" --fri-port $port --wts-link "$out/wts0" --krc "$krc" \
    --krc-cycle-ms "$cycle_ms" --truth-period-ms 10 --quality-rule on --krl "$krl" \
    --truth-out "$dir/truth.csv" "$@" > "$dir/lab_sim.log" 2>&1 &
  lab_pid=$!
  pids+=($lab_pid)
  for _ in $(seq 100); do [ -e "$out/wts0" ] && return 0; sleep 0.05; done
  echo "$name: lab_sim did not start (see $dir/lab_sim.log)" >&2
  return 1
}
stop_lab() {
  [ -n "$lab_pid" ] || return 0
  kill -TERM "$lab_pid" 2>/dev/null
  wait "$lab_pid" 2>/dev/null
  lab_pid=""
}

# ---- 1 sensor ---------------------------------------------------------------
if want 1; then
  d="$out/1_sensor"; mkdir -p "$d"
  echo "== step 1 sensor: wts_check --press on the simulated WTS0614 (the press comes after 8 s)"
  rm -f "$out/wts0"
  "$build/bin/wts_sim" --link "$out/wts0" --pattern press --press-after 8 > "$d/wts_sim.log" 2>&1 &
  sim=$!; pids+=($sim)
  for _ in $(seq 100); do [ -e "$out/wts0" ] && break; sleep 0.05; done
  rc=0
  "$build/bin/wts_check" --device "$out/wts0" --params "$root/params/sensors/wts0614.yaml" \
    --seconds 3 --press --no-prompt --json "$d/wts_check.json" > "$d/wts_check.log" 2>&1 || rc=$?
  kill "$sim" 2>/dev/null; wait "$sim" 2>/dev/null
  grep -E "PASS|FAIL|WARN" "$d/wts_check.log" | sed 's/^/   /'
  verdict 1 sensor "$rc" "wts_check exit $rc: $d/wts_check.log says which stage and what to do"
fi

# ---- 2 calibration ----------------------------------------------------------
calib="$root/params/sensors/wts0614.yaml"
if want 2; then
  d="$out/2_calibration"; mkdir -p "$d"
  echo "== step 2 calibration: a recording under known loads, fitted"
  rc=0
  "$build/bin/tactile_calibration_record" --params "$root/params/sensors/wts0614.yaml" --ref-noise 0.01 \
    --out "$d/recording.csv" > "$d/record.log" 2>&1 || rc=$?
  if [ "$rc" -eq 0 ]; then
    "$build/bin/tactile_calibrate" --recording "$d/recording.csv" --params "$calib" \
      --out "$d/wts0614_fitted.yaml" > "$d/calibrate.log" 2>&1 || rc=$?
  fi
  sed -n '1,40p' "$d/calibrate.log" 2>/dev/null | grep -E "PASS|FAIL|RMS|residual" | sed 's/^/   /'
  if [ "$rc" -eq 0 ] && [ -s "$d/wts0614_fitted.yaml" ]; then
    calib="$d/wts0614_fitted.yaml"
    # From here on the features read the fitted file, as features.cpf would on the arm.
    sed -i "s#<value>[^<]*wts0614.yaml</value>#<value>$calib</value>#" "$dep/features.cpf"
    grep -q "<value>$calib</value>" "$dep/features.cpf" || rc=1
  fi
  verdict 2 calibration "$rc" "$d/record.log, $d/calibrate.log"
fi

# ---- 3 FRI link -------------------------------------------------------------
if want 3; then
  d="$out/3_fri_link"; mkdir -p "$d"
  echo "== step 3 FRI link: fri_check --monitor against the KRC after friOpen (monitor mode)"
  # The simulated KRC runs beside the tests on a host without a real-time
  # kernel: its packet timing is not the KRC's. The jitter and period
  # bands are widened here (5 ms, 100 %), and the cycle's (at most 30 %
  # missed or late, PERFECT in 80 %: 14 % of the answers late at 2 ms with
  # the test suite running beside it); a quality drop that recovers is a
  # WARN (such a host's wake-up latency reaches 5 ms, five cycles:
  # docs/realtime.md), [cycle] judging the link; on the arm keep
  # fri_check's defaults.
  rc=0
  if start_lab "$root/params/scenes/edge_exploration.yaml" "0:friOpen" "$d"; then
    "${bridge_prio[@]}" "$build/bin/fri_check" --monitor --port $port --params "$fri_yaml" \
      --seconds 3 --max-jitter-ms 5 --period-tolerance 1.0 --max-late-share 0.3 --min-perfect-share 0.8 \
      --quality-drop warn \
      --json "$d/fri_check.json" > "$d/fri_check.log" 2>&1 || rc=$?
    stop_lab
  else
    rc=1
  fi
  grep -E "PASS|FAIL|WARN" "$d/fri_check.log" | sed 's/^/   /'
  verdict 3 "FRI link" "$rc" "fri_check exit $rc: $d/fri_check.log"
fi

# run_step N TITLE SCENE KRC EXPERIMENT [run_robot args]: lab_sim, then the unattended robot run.
run_step() {
  local n="$1" title="$2" scene="$3" krc="$4" exp="$5"
  shift 5
  local d="$out/$n"
  mkdir -p "$d"
  local rc=0
  if start_lab "$scene" "$krc" "$d"; then
    bash "$root/scripts/run_robot.sh" "$exp" --deployments "$dep" --out "$d/run" --timeout 300 "$@" \
      > "$d/run_robot.log" 2>&1 || rc=$?
    stop_lab
  else
    rc=1
  fi
  sed 's/^/   /' "$d/run_robot.log" | grep -E "PASS|FAIL|failed|finished|DRY" | head -8
  return "$rc"
}

# ---- 4 dry run --------------------------------------------------------------
if want 4; then
  echo "== step 4 dry run: the pad pressed, the servo computes and records, the bridge holds the arm"
  rc=0
  run_step 4_dry_run "dry run" "$root/params/lab_scenes/bringup_press.yaml" "0:friOpen,$start_after:friStart" \
    first_touch --dry-run || rc=$?
  [ "$rc" -eq 0 ] && { "$py" "$root/scripts/tools/rehearsal_report.py" check "$out/4_dry_run" --fri-yaml "$fri_yaml" --dry-run --start "$start_after" || rc=$?; }
  verdict 4 "dry run" "$rc" "$out/4_dry_run/run_robot.log; the arm must not move and the commands must"
fi

# ---- 5 first touch ----------------------------------------------------------
if want 5; then
  echo "== step 5 first touch: friOpen, friStart after ${start_after} s, the gentle program to its end"
  rc=0
  run_step 5_first_touch "first touch" "$root/params/scenes/first_touch.yaml" "0:friOpen,$start_after:friStart" \
    first_touch || rc=$?
  [ "$rc" -eq 0 ] && { "$py" "$root/scripts/tools/rehearsal_report.py" check "$out/5_first_touch" --fri-yaml "$fri_yaml" --start "$start_after" --max-force 5.0 || rc=$?; }
  verdict 5 "first touch" "$rc" "$out/5_first_touch/run_robot.log"
fi

# ---- 6 the experiment -------------------------------------------------------
if want 6; then
  t0=$start_after
  krc="0:friOpen,$t0:friStart,$((t0 + 8)):quality=BAD,$((t0 + 8)).3:quality=PERFECT,$((t0 + 14)):friStop,$((t0 + 14)).5:friStart"
  echo "== step 6 edge exploration: the KRC $krc"
  rc=0
  run_step 6_edge_exploration "edge exploration" "$root/params/scenes/edge_exploration.yaml" "$krc" edge_exploration || rc=$?
  [ "$rc" -eq 0 ] && { "$py" "$root/scripts/tools/rehearsal_report.py" check "$out/6_edge_exploration" --fri-yaml "$fri_yaml" --start "$t0" --target-force 5.0 || rc=$?; }
  # The same verdict as a run started in command mode (ctest lab_sim_robot_edge_exploration): the bar's end.
  if [ "$rc" -eq 0 ]; then
    if grep -q "finished: program_ended" "$out/6_edge_exploration/run/deployer.log"; then
      echo "   PASS: the state machine's verdict program_ended (the bar's end), as started in command mode"
    else
      echo "   FAIL: the state machine did not end at the bar's end (program_ended)"; rc=1
    fi
  fi
  verdict 6 "edge exploration" "$rc" "$out/6_edge_exploration/run_robot.log"
fi

printf '%s\n' "${results[@]}" > "$out/steps.txt"
"$py" "$root/scripts/tools/rehearsal_report.py" report "$out" || true
fails=$(grep -c '|FAIL|' "$out/steps.txt")
if [ "$fails" -eq 0 ]; then
  echo "rehearsal: PASS: every step (${#results[@]}); $out/rehearsal.md, $out/rehearsal.png"
  exit 0
fi
echo "rehearsal: FAIL: $fails of ${#results[@]} steps; $out/rehearsal.md"
exit 1
