# Sourced by the lab_sim robot tests (run_lab_sim_robot_*.sh), after
# scripts/realtime/rt_common.sh (root, build, deployer, rt_stage_deployments,
# pids and their cleanup): the unchanged robot deployment, staged with the
# bridge on a port of the test's own, against lab_sim on a scene, run
# unattended by scripts/run_robot.sh.

# lab_robot_stage OUT PORT: a fresh OUT with a staged copy of deployments/
# whose FRI bridge listens on PORT, and of the KRL program the KRC runs
# (OUT/krc: krc/TactileServo.src and the .dat beside it).
lab_robot_stage() {
  local out="$1" port="$2"
  for t in "$deployer" "$build/bin/lab_sim"; do
    [ -x "$t" ] || { echo "$name: $t missing" >&2; exit 1; }
  done
  rm -rf "$out"
  mkdir -p "$out"
  rt_stage_deployments "$out"
  sed -i "/name=\"port\"/,/<\/simple>/ s#<value>-1</value>#<value>$port</value>#" "$out/deployments/fri_bridge.cpf"
  grep -q "<value>$port</value>" "$out/deployments/fri_bridge.cpf" || { echo "$name: could not set the bridge's port"; exit 1; }
  mkdir -p "$out/krc"
  cp "$root/krc/TactileServo.src" "$root/krc/TactileServo.dat" "$out/krc/"
}

# lab_robot_start OUT PORT SCENE [lab_sim arguments]: lab_sim on SCENE, the
# KRC in command mode from its first packet, running the staged KRL program
# (--krl: estExtTcpFT in its FRAMETYPE's axes, its MAXFORCE / CPMAXDELTA
# applied), the WTS on OUT/wts0 (waited for); its pid in `lab`, its log in
# OUT/lab_sim.log.
lab_robot_start() {
  local out="$1" port="$2" scene="$3"
  shift 3
  # krc_prio: scripts/realtime/rt_common.sh (sourced first)
  "${krc_prio[@]}" "$build/bin/lab_sim" "$scene" --fri-port "$port" --wts-link "$out/wts0" \
    --krc "0:friOpen,0:friStart" --krl "$out/krc/TactileServo.src" "$@" >"$out/lab_sim.log" 2>&1 &
  lab=$!
  pids+=($lab)
  for _ in $(seq 100); do [ -e "$out/wts0" ] && break; sleep 0.05; done
  [ -e "$out/wts0" ] || { cat "$out/lab_sim.log"; echo "$name: lab_sim's PTY did not appear" >&2; exit 1; }
}

# lab_robot_run EXPERIMENT OUT TIMEOUT_S: scripts/run_robot.sh to the
# experiment's end (OUT/run, its log OUT/run_robot.log, printed), then lab_sim
# stopped; run_robot.sh's exit in `dep_rc`, lab_sim's in `lab_rc`.
lab_robot_run() {
  local exp="$1" out="$2" timeout="$3"
  dep_rc=0
  BUILD="$build" bash "$root/scripts/run_robot.sh" "$exp" --deployments "$out/deployments" --out "$out/run" \
    --timeout "$timeout" >"$out/run_robot.log" 2>&1 || dep_rc=$?
  kill -TERM "$lab" 2>/dev/null
  lab_rc=0
  wait "$lab" || lab_rc=$?
  cat "$out/run_robot.log"
}

