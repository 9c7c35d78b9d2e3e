#!/usr/bin/env bash
# ctest rtt_fault_fri_burst: a burst of 20 lost FRI packets while the arm
# moves at the bar programs' step limit, through the robot
# deployment (deployments/robot_loop.ops: the FRI bridge on its
# FileDescriptorActivity, the WTS reader, features, servo, real-time
# settings) against the simulated KRC on loopback (fri_sim_krc, 1 kHz, in
# CMD from its first packet, `--burst 1500:20`: the measurements of cycles
# 1500-1519 are not sent, the KRC holds its set point meanwhile) and the
# simulated WTS on a PTY (wts_sim --pattern zero: no contact). There is no
# bar on this side (the KRC's plant is a first-order tracker), so the servo
# slides in free motion at the step limit (free_slide.yaml: 0.05 m/s, under
# the bridge's max_lin_speed). The only place where the FRI bridge component
# receives packets; wall clock (about 3 s of KRC cycles), but no timing is
# asserted: counts and bounds only (check_fri_burst.py).
#   run_fri_burst_test.sh SOURCE_DIR BUILD_DIR
# Environment: OROCOS (default /opt/orocos). UDP port 49958 (not fri.yaml's
# 49938: the other robot deployment runs on this host may hold that one).
set -uo pipefail
name=rtt_fault_fri_burst
export BUILD="$2"
# root, build, orocos, deployer, rt_check_tools, rt_stage_deployments, rt_start_wts_sim (kills its peers on exit)
source "$1/scripts/realtime/rt_common.sh"
rt_check_tools
port=49958
out="$build/fault_test/fri_burst"
rm -rf "$out"
mkdir -p "$out"
rt_stage_deployments "$out"
cp "$root/tests/rtt/faults/servo_free_slide.cpf" "$out/deployments/"
sed -i "s#\.\./#$root/#g" "$out/deployments/servo_free_slide.cpf"
sed -i "/name=\"port\"/,/<\/simple>/ s#<value>-1</value>#<value>$port</value>#" "$out/deployments/fri_bridge.cpf"
grep -q "<value>$port</value>" "$out/deployments/fri_bridge.cpf" || { echo "$name: could not set the bridge's port"; exit 1; }

cat > "$out/deployments/fri_burst.ops" <<'EOF'
// rtt_fault_fri_burst: the robot deployment, the servo sliding in free motion;
// the counters after 1000 and 2000 KRC packets (the burst lies between) and
// at the end of the KRC's 3000 cycles.
import("tactile")
import("ocl")
loadComponent("Guard", "tactile::DeployGuard")
Guard.experiment = "fri_burst"
Guard.servo_cpf = "servo_free_slide.cpf"
Guard.timeout = 40.0
Guard.step(runScript("robot_loop.ops"), "robot_loop.ops")
var int robot_side_started(Guard.verdict())
if Guard.ok then Guard.step(Features.start(), "start Features")
if Guard.ok then Guard.step(Servo.start(), "start Servo (fri_burst ready)")
var int servo_started(Guard.verdict())
var double waited = 0.0
var /tactile/Pose p
while Guard.ok && waited < Guard.timeout && Robot.received < 1000 {
  Guard.sleep(0.002)
  waited = waited + 0.002
}
p = Robot.flange_pose.last()
Guard.step(true, "fri_burst at received " + Robot.received + " lost " + Robot.lost + " x " + p.p[0] + " y " + p.p[1] + " z " + p.p[2])
while Guard.ok && waited < Guard.timeout && Robot.received < 2000 {
  Guard.sleep(0.002)
  waited = waited + 0.002
}
p = Robot.flange_pose.last()
Guard.step(true, "fri_burst at received " + Robot.received + " lost " + Robot.lost + " x " + p.p[0] + " y " + p.p[1] + " z " + p.p[2])
while Guard.ok && waited < Guard.timeout && Robot.received < 2980 {
  Guard.sleep(0.002)
  waited = waited + 0.002
}
Guard.step(true, "fri_burst end received " + Robot.received + " replies " + Robot.replies + " lost " + Robot.lost + " timeouts " + Robot.timeouts + " socket_errors " + Robot.socket_errors + " bridge " + Robot.statusName() + " servo_status " + Servo.last_status + " phase " + Servo.phaseName())
var int fri_burst_done(Guard.verdict())
EOF

rt_start_wts_sim_zero() {  # rt_start_wts_sim with no contact (no tactile force: no force-mismatch watchdog)
  "$build/bin/wts_sim" --link "$out/wts0" --pattern zero >"$out/wts_sim.log" 2>&1 &
  pids+=($!)
  for _ in $(seq 50); do [ -e "$out/wts0" ] && break; sleep 0.1; done
  [ -e "$out/wts0" ] || { echo "$name: wts_sim did not start" >&2; exit 1; }
}
rt_start_wts_sim_zero

( cd "$out/deployments" && RTT_COMPONENT_PATH="$build/lib/orocos:$orocos/lib/orocos" \
    exec "$deployer" --check -l info -s fri_burst.ops < /dev/null ) >"$out/deployer.log" 2>&1 &
dep=$!
pids+=($dep)
for _ in $(seq 600); do
  grep -q "fri_burst ready\|deployment step failed" "$out/deployer.log" 2>/dev/null && break
  sleep 0.05
done
grep -q "ok: start Servo (fri_burst ready)" "$out/deployer.log" || { cat "$out/deployer.log"; echo "$name: the deployment did not start"; exit 1; }
krc=(chrt -f 95)
chrt -f 1 true 2>/dev/null || krc=()
"${krc[@]}" "$build/bin/fri_sim_krc" --port $port --cycles 3000 --period-ms 1 --schedule 0:CMD:PERFECT \
  --burst 1500:20 >"$out/krc.log" 2>&1
krc_rc=$?
dep_rc=0
wait "$dep" || dep_rc=$?
grep -E "fri_burst|deployment step failed" "$out/deployer.log" | sed 's/^.*\] //'
cat "$out/krc.log"
/usr/bin/python3 "$root/tests/rtt/faults/check_fri_burst.py" "$out" "$krc_rc" "$dep_rc" \
  "$root/tests/rtt/faults/free_slide.yaml" "$root/params/sensors/fri.yaml"
