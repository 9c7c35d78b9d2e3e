#!/usr/bin/env bash
# Soak of the real-time robot path (a long run, not a test; the simulated
# deployment on a looping scene: scripts/realtime/rt_soak_sim.sh): nothing grows,
# nothing NaNs, nothing is lost over MINUTES of wall clock.
#
#   scripts/realtime/rt_soak.sh [MINUTES]           default 60 (CI: 2)
#
# Runs the robot deployment (deployments/robot_loop.ops: FRI bridge, WTS
# reader, features, servo with the edge exploration program, RealtimeCheck;
# the deployment's SCHED_FIFO priorities where permitted) against the
# simulated KRC (build/bin/fri_sim_krc, 1 kHz on loopback, CMD after 1 s) and
# the simulated WTS0614 (build/bin/wts_sim --pattern blob: a press circling
# over the pad, so the features and the servo see contact come and go all the
# time). Every minute it records: the deployer's resident memory (VmRSS) and
# the components' counters and statuses (Robot received, replies, lost,
# timeouts, socket_errors, bridge_status; Sensor frames, timeouts,
# read_status; Features frames, last_status; Servo phase, last_status: the
# ServoStatus number of tactile_types/types.hpp). At the
# end scripts/realtime/rt_soak_report.py prints the per-minute table
# (out/rt_soak/robot/rt_soak.md) and checks, exit status 1 on a failure:
#   * resident memory after minute 1 grows by less than 1 MiB (memory is
#     locked, mlockall: a per-cycle allocation would show);
#   * every minute: >= 90 % of 60000 KRC packets received and answered, no
#     socket error, no KRC silence, WTS frames every minute;
#   * the simulated KRC saw no protocol violation and no non-finite command
#     (fri_sim_krc exit status 0: MON echo, flags, NaN);
#   * the deployment ran to the end (every step ok).
# Environment: BUILD (default <repo>/build), OROCOS (default /opt/orocos).
set -euo pipefail
name=rt_soak
# shellcheck source=scripts/realtime/rt_common.sh
source "$(dirname "${BASH_SOURCE[0]}")/rt_common.sh"
minutes=${1:-60}
out="$root/out/rt_soak/robot"  # the sim soak (rt_soak_sim.sh) writes out/rt_soak/sim_*
rt_check_tools
[ "$minutes" -ge 1 ] 2>/dev/null && [ "$minutes" -le 1440 ] || { echo "usage: $0 [MINUTES >= 1]" >&2; exit 2; }

rm -rf "$out"
mkdir -p "$out/deployments"
rt_stage_deployments "$out"
secs=$((minutes * 60))
cat > "$out/deployments/rt_soak.ops" <<EOF
// scripts/realtime/rt_soak.sh: the robot deployment for $minutes min of wall clock,
// one line of counters per minute ("soak minute N ...").
import("tactile")
import("ocl")
loadComponent("Guard", "tactile::DeployGuard")
Guard.step(Guard.select("edge_exploration"), "select edge_exploration (its program) from " + Guard.registry_file)
Guard.experiment = "rt_soak"
Guard.timeout = $secs
Guard.step(runScript("robot_loop.ops"), "robot_loop.ops")
var int robot_side_started(Guard.verdict())
if Guard.ok then Guard.step(Servo.start(), "start Servo")
if Guard.ok then Guard.step(Features.start(), "start Features")
var double waited = 0.0
var int minute = 0
while Guard.ok && waited < Guard.timeout {
  Guard.sleep(1.0)
  waited = waited + 1.0
  if waited >= 60.0 * (minute + 1) then {
    minute = minute + 1
    Guard.step(true, "soak minute " + minute + " robot_received " + Robot.received + " robot_replies " + Robot.replies + " robot_lost " + Robot.lost + " robot_timeouts " + Robot.timeouts + " robot_socket_errors " + Robot.socket_errors + " bridge_status " + Robot.statusName() + " sensor_frames " + Sensor.frames + " sensor_timeouts " + Sensor.timeouts + " sensor_status " + Sensor.statusName() + " features_frames " + Features.frames + " features_status " + Features.last_status + " servo_status " + Servo.last_status + " phase " + Servo.phaseName())
  }
}
Guard.step(true, "soak end: " + Realtime.report + " memory_locked " + Realtime.memory_locked)
var int soak_finished(Guard.verdict())
EOF

rt_start_wts_sim "$out"

echo "rt_soak: $minutes min"
( cd "$out/deployments" && RTT_COMPONENT_PATH="$build/lib/orocos:$orocos/lib/orocos" \
    exec "$deployer" --check -l info -s rt_soak.ops ) >"$out/deployer.log" 2>&1 &
dep=$!
pids+=($dep)
sleep 3
krc=(chrt -f 95)
chrt -f 1 true 2>/dev/null || krc=()
"${krc[@]}" "$build/bin/fri_sim_krc" --port 49938 --cycles $(( (secs - 5) * 1000 )) --period-ms 1 --wrench "$rt_press_wrench" \
  --schedule 0:MON:PERFECT,1000:CMD:PERFECT >"$out/krc.log" 2>&1 &
kpid=$!
pids+=($kpid)
# resident memory of the deployer, once a minute (minute N: 3 s before its end,
# while the deployer surely still runs)
: >"$out/rss.txt"
t0=$SECONDS
for m in $(seq 1 "$minutes"); do
  while [ $((SECONDS - t0)) -lt $((m * 60 - 3)) ]; do sleep 1; done
  rss=$(awk '/VmRSS/ {print $2}' "/proc/$dep/status" 2>/dev/null || echo nan)
  echo "$m $rss" >>"$out/rss.txt"
done
dep_rc=0
wait "$dep" || dep_rc=$?
krc_rc=0
wait "$kpid" || krc_rc=$?
/usr/bin/python3 "$root/scripts/realtime/rt_soak_report.py" "$out" "$minutes" "$dep_rc" | tee "$out/rt_soak.md"
exit "${PIPESTATUS[0]}"
