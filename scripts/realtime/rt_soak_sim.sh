#!/usr/bin/env bash
# Soak of the simulated deployment on a looping scene (a long run, not a
# test): one hour of wall clock without drift.
#
#   scripts/realtime/rt_soak_sim.sh [MINUTES]          default 60 (CI: 2, ctest RtSoakSim)
#
# Runs the simulated deployment (deployments/sim_loop.ops: tactile::SimClock,
# LwrSimComponent, WtsSimComponent, FeatureComponent, ServoComponent,
# OCL::FileReporting) on params/scenes/bar_loop.yaml: the bent bar slid back and
# forth between flange x = 0.72 and 0.62 m (program
# params/programs/bar_loop.yaml; the deployment script below turns
# it on the measured flange position), at wall-clock speed (Clock.realtime_factor
# = 1) for MINUTES (the staged scene's duration). Output in
# out/rt_soak/sim_<MINUTES>min/:
#   soak.dat     the reporter's table, every servo cycle (100 Hz): Servo.phase
#                (index, status), Servo.integral (the PI integrator ∫Δs_task dt,
#                Eq. 13), Servo.last_status, Robot.truth (the simulator's true
#                contact force: layer and housing force, wrench on the sensor)
#   rss.txt      the deployer's resident memory (VmRSS), every minute
#   deployer.log one line per minute ("soak minute N": simulated time, ticks,
#                phase, flange x, turns of the loop, clock and arm status)
#   rt_soak_sim.md, rt_soak_sim.png   per-minute table and plot, with the checks
#                of scripts/realtime/rt_soak_sim_report.py (exit status 1 on a failure).
# Environment: BUILD (default <repo>/build), OROCOS (default /opt/orocos),
# DEPLOYER (default $OROCOS/bin/deployer-gnulinux; the sanitizer builds: their wrapper),
# RT_SOAK_OUT (default out/rt_soak/sim_<MINUTES>min), RT_SOAK_REALTIME_FACTOR
# (default 1: wall clock; 0 = as fast as possible, to try the script out).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${BUILD:-$root/build}"
orocos="${OROCOS:-/opt/orocos}"
deployer="${DEPLOYER:-$orocos/bin/deployer-gnulinux}"
minutes=${1:-60}
[ "$minutes" -ge 1 ] 2>/dev/null && [ "$minutes" -le 1440 ] || { echo "usage: $0 [MINUTES >= 1]" >&2; exit 2; }
[ -x "$deployer" ] || { echo "rt_soak_sim: $deployer missing" >&2; exit 1; }
[ -e "$build/lib/orocos" ] || { echo "rt_soak_sim: $build/lib/orocos missing (build with -DTACTILE_WITH_RTT=ON)" >&2; exit 1; }
out="${RT_SOAK_OUT:-$root/out/rt_soak/sim_${minutes}min}"
secs=$((minutes * 60))

rm -rf "$out"
mkdir -p "$out/deployments"
# Staged copies with absolute paths; the scene's duration is the soak's.
cp "$root"/deployments/*.ops "$root"/deployments/*.cpf "$out/deployments/"
sed -i "s#\.\./#$root/#g" "$out"/deployments/*.cpf
sed -e "s#^duration: .*#duration: $secs#" -e "s#\.\./#$root/params/#g" "$root/params/scenes/bar_loop.yaml" >"$out/bar_loop.yaml"
cat > "$out/deployments/lwr_sim_bar_loop.cpf" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<!DOCTYPE properties SYSTEM "cpf.dtd">
<properties>
  <simple name="scene_file" type="string"><description>scene YAML</description><value>$out/bar_loop.yaml</value></simple>
  <simple name="program_file" type="string"><description>the servo's program (the pad's mount)</description><value>$root/params/programs/bar_loop.yaml</value></simple>
</properties>
XML
cat > "$out/deployments/servo_bar_loop.cpf" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<!DOCTYPE properties SYSTEM "cpf.dtd">
<properties>
  <simple name="program_file" type="string"><description>YAML phase program</description><value>$root/params/programs/bar_loop.yaml</value></simple>
  <simple name="controller_mode" type="string"><description>the program's</description><value></value></simple>
  <simple name="period" type="double"><description>servo period (s)</description><value>0.01</value></simple>
</properties>
XML
cat > "$out/deployments/rt_soak_sim.ops" <<EOF2
// scripts/realtime/rt_soak_sim.sh: the simulated deployment on the looping bar for
// $minutes min of wall clock (Clock.realtime_factor = 1), one line per minute.
// The loop: this script turns the servo's program between its two sliding
// phases (Servo.switchPhase, a ClientThread operation applied at the next
// servo cycle) on the measured flange position (Robot.flange_pose), polled
// every 0.02 s (15 mm/s: the turning point varies by ~0.3 mm): slide_out
// until x <= x_min, slide_back until x >= x_max. Closed on position, the loop
// cannot drift along the bar. (Not an .osd in the servo: a state machine's
// copy of a struct variable leaves its array members dangling in RTT 2.10,
// so pose.p[0] reads garbage there; a program script reads it correctly.)
import("tactile")
import("ocl")
loadComponent("Guard", "tactile::DeployGuard")
Guard.experiment = "rt_soak_sim"
Guard.servo_cpf = "servo_bar_loop.cpf"
Guard.sim_cpf = "lwr_sim_bar_loop.cpf"
Guard.report_file = "$out/soak.dat"
Guard.timeout = $secs + 120.0
Guard.step(runScript("sim_loop.ops"), "sim_loop.ops")
var int robot_side_started(Guard.verdict())
// The reporter (sim_loop.ops reports Robot.truth): the servo's phase, status and integrator.
Reporter.ReportFile = Guard.report_file
Reporter.WriteHeader = true
Reporter.ComplexDecompose = true
if Guard.ok then Guard.step(addPeer("Reporter", "Servo"), "Servo as a peer of Reporter")
if Guard.ok then Guard.step(Reporter.reportPort("Servo", "phase"), "report Servo.phase")
if Guard.ok then Guard.step(Reporter.reportData("Servo", "integral"), "report Servo.integral (the PI integrator)")
if Guard.ok then Guard.step(Reporter.reportData("Servo", "last_status"), "report Servo.last_status")
if Guard.ok then Guard.step(Reporter.configure(), "configure Reporter")
if Guard.ok then Guard.step(Reporter.start(), "start Reporter")
if Guard.ok then Guard.step(Features.start(), "start Features")
if Guard.ok then Guard.step(Servo.start(), "start Servo")
Clock.realtime_factor = ${RT_SOAK_REALTIME_FACTOR:-1.0}
if Guard.ok then Guard.step(Robot.start() && Clock.start(), "start Robot and Clock (realtime_factor " + Clock.realtime_factor + ")")
var int started(Guard.verdict())
// The loop in its own file: parsed once Robot exists (a port of a peer,
// Robot.flange_pose, cannot be parsed before the peer is loaded).
Guard.step(runScript("rt_soak_sim_loop.ops"), "rt_soak_sim_loop.ops")
EOF2
cat > "$out/deployments/rt_soak_sim_loop.ops" <<EOF2
// scripts/realtime/rt_soak_sim.sh: the loop of rt_soak_sim.ops (see there).
var int i_out = Servo.phaseIndexOf("slide_out")
var int i_back = Servo.phaseIndexOf("slide_back")
if Guard.ok then Guard.step(i_out >= 0 && i_back >= 0, "the program has slide_out and slide_back")
var double x_min = 0.62
var double x_max = 0.72
var /tactile/Pose pose_now
var double x = 0.0
var int phase_now = -1
var int turns = 0
// the phase requested by the last switch, until the servo has entered it
// (switchPhase takes effect at the next servo cycle): no decision before
var int pending = -1
var double waited = 0.0
var int minute = 0
while Guard.ok && waited < Guard.timeout && !Clock.finished {
  Guard.sleep(0.02)
  waited = waited + 0.02
  pose_now = Robot.flange_pose.last()
  x = pose_now.p[0]
  phase_now = Servo.phaseIndex()
  if pending >= 0 && phase_now == pending then pending = -1
  if pending < 0 && phase_now == i_out && x <= x_min then {
    Servo.switchPhase("slide_back")
    pending = i_back
    turns = turns + 1
  }
  if pending < 0 && phase_now == i_back && x >= x_max then {
    Servo.switchPhase("slide_out")
    pending = i_out
    turns = turns + 1
  }
  if Clock.sim_time >= 60.0 * (minute + 1) then {
    minute = minute + 1
    Guard.step(true, "soak minute " + minute + " sim_time " + Clock.sim_time + " wall " + waited + " ticks " + Clock.ticks + " phase " + Servo.phaseName() + " x " + x + " turns " + turns + " clock_exit_code " + Clock.exit_code + " robot " + Robot.statusName() + " sensor_frames " + Sensor.frames)
  }
}
if Guard.ok then Guard.step(Clock.finished, "the simulated run ended within Guard.timeout s of wall clock")
Guard.step(true, "soak end: clock " + Clock.status + " exit_code " + Clock.exit_code + " sim_time " + Clock.sim_time + " turns " + turns + " phase " + Servo.phaseName())
Guard.step(Reporter.stop(), "stop Reporter")
Guard.step(stopComponents(), "stop all components")
var int soak_finished(Guard.verdict())
EOF2

echo "rt_soak_sim: $minutes min -> $out"
( cd "$out/deployments" && RTT_COMPONENT_PATH="$build/lib/orocos:$orocos/lib/orocos" \
    exec "$deployer" --check -l info -s rt_soak_sim.ops ) >"$out/deployer.log" 2>&1 &
dep=$!
trap 'kill $dep 2>/dev/null || true' EXIT
# Resident memory of the deployer, once a minute (3 s before the minute's end).
: >"$out/rss.txt"
t0=$SECONDS
for m in $(seq 1 "$minutes"); do
  while [ $((SECONDS - t0)) -lt $((m * 60 - 3)) ]; do
    kill -0 "$dep" 2>/dev/null || break 2
    sleep 1
  done
  rss=$(awk '/VmRSS/ {print $2}' "/proc/$dep/status" 2>/dev/null || echo nan)
  echo "$m $rss" >>"$out/rss.txt"
done
dep_rc=0
wait "$dep" || dep_rc=$?
trap - EXIT
/usr/bin/python3 "$root/scripts/realtime/rt_soak_sim_report.py" "$out" "$minutes" "$dep_rc" | tee "$out/rt_soak_sim.md"
exit "${PIPESTATUS[0]}"
