#!/usr/bin/env bash
# Latency and jitter of the robot deployment, measured (a benchmark, not a test).
#
#   scripts/realtime/rt_latency.sh [SECONDS]        default 30 s per configuration
#
# The robot deployment (deployments/robot_loop.ops: FRI bridge, WTS reader,
# features, servo with the edge exploration program; RealtimeCheck) runs under
# the OCL deployer against the simulated KRC (build/bin/fri_sim_krc, 1 kHz on
# loopback, MON then CMD) and the simulated WTS0614 (build/bin/wts_sim on a
# PTY). The KRC records, per packet, the time from the measurement's departure
# to the matched command's arrival: the bridge's reply latency plus two
# loopback hops. Four configurations:
#   fifo_idle   the deployment's SCHED_FIFO priorities, machine otherwise idle
#   fifo_load   the same under `stress-ng --cpu N --vm 1` (CPU and memory load)
#   other_idle  no real-time rights (as user nobody, RLIMIT_RTPRIO 0: RTT
#               runs every activity SCHED_OTHER), idle
#   other_load  the same under load
# cyclictest (rt-tests, SCHED_FIFO 90, 1 ms, memory locked) runs beside each
# one: the machine's own wake-up latency, the floor any loop here can reach.
# The simulated KRC itself runs SCHED_FIFO 95 (on a real robot it is a
# separate computer).
#
# Output (out/rt_latency/): per configuration <cfg>_krc.txt (one line per
# cycle: latency in us and 1/0 for on time; "nan 0" = no reply), <cfg>_cyclictest.hist, <cfg>_deployer.log;
# rt_latency.md (table: p50, p99, p99.9, max, late replies > 1 ms, replies that
# missed their tick, replies that never came; a late reply keeps its true latency)
# and rt_latency.png (histograms), written by scripts/realtime/rt_latency_report.py.
# Needs root (or CAP_SYS_NICE) for SCHED_FIFO; stress-ng and cyclictest
# (scripts/setup/setup_deps.sh installs them).
# Environment: BUILD (default <repo>/build), OROCOS (default /opt/orocos).
set -euo pipefail
name=rt_latency
# shellcheck source=scripts/realtime/rt_common.sh
source "$(dirname "${BASH_SOURCE[0]}")/rt_common.sh"
dur=${1:-30}
out="$root/out/rt_latency"
rt_check_tools
for t in stress-ng cyclictest chrt setpriv prlimit; do
  command -v "$t" >/dev/null || { echo "rt_latency: $t missing (scripts/setup/setup_deps.sh)" >&2; exit 1; }
done
[ "$(id -u)" -eq 0 ] || echo "rt_latency: not root: the fifo_* configurations run without SCHED_FIFO unless rtprio is granted" >&2

rm -rf "$out"
mkdir -p "$out/deployments"
chmod 755 "$out" "$out/deployments"
# A copy of deployments/ with absolute paths and the simulated sensor's PTY.
rt_stage_deployments "$out"
cat > "$out/deployments/rt_latency_bench.ops" <<EOF
// scripts/realtime/rt_latency.sh: the robot deployment (robot_loop.ops), the servo
// started, held for Guard.timeout s of wall clock, then the deployer exits.
import("tactile")
import("ocl")
loadComponent("Guard", "tactile::DeployGuard")
Guard.step(Guard.select("edge_exploration"), "select edge_exploration (its program) from " + Guard.registry_file)
Guard.experiment = "rt_latency"
Guard.timeout = $dur
Guard.step(runScript("robot_loop.ops"), "robot_loop.ops")
var int robot_side_started(Guard.verdict())
if Guard.ok then Guard.step(Servo.start() && Features.start(), "start Servo and Features")
var double waited = 0.0
while Guard.ok && waited < Guard.timeout { Guard.sleep(0.5); waited = waited + 0.5 }
Guard.step(true, "rt_latency: Robot received " + Robot.received + " replies " + Robot.replies + " lost " + Robot.lost + " timeouts " + Robot.timeouts + "; Sensor frames " + Sensor.frames + "; Realtime " + Realtime.report + " memory_locked " + Realtime.memory_locked)
var int bench_finished(Guard.verdict())
EOF
chmod 644 "$out"/deployments/*


rt_start_wts_sim "$out"
chmod 666 "$(readlink -f "$out/wts0")"  # the unprivileged runs open it too

ncpu=$(nproc)
krc_cycles=$(( (dur - 6) * 1000 ))
[ "$krc_cycles" -ge 1000 ] || { echo "rt_latency: SECONDS must be >= 7" >&2; exit 2; }
for cfg in fifo_idle fifo_load other_idle other_load; do
  wrap=()
  case "$cfg" in other_*) wrap=(setpriv --reuid=65534 --regid=65534 --clear-groups --inh-caps=-all prlimit --rtprio=0) ;; esac
  if [ "$(id -u)" -ne 0 ] && [ "${#wrap[@]}" -gt 0 ]; then wrap=(prlimit --rtprio=0); fi
  echo "rt_latency: $cfg (${dur} s)"
  ( cd "$out/deployments" && RTT_COMPONENT_PATH="$build/lib/orocos:$orocos/lib/orocos" \
      "${wrap[@]}" "$deployer" --check -l info -s rt_latency_bench.ops ) >"$out/${cfg}_deployer.log" 2>&1 &
  dep=$!
  pids+=($dep)
  sleep 3  # the deployment is up (loaded, configured, started)
  load=
  case "$cfg" in *_load)
    stress-ng --cpu "$ncpu" --vm 1 --vm-bytes 25% --timeout "$((dur - 4))s" >"$out/${cfg}_stress.log" 2>&1 &
    load=$!; pids+=($load) ;;
  esac
  cyclictest -m -q -p 90 -i 1000 -t 1 -D "$((dur - 5))s" -h 20000 --histfile="$out/${cfg}_cyclictest.hist" \
    >"$out/${cfg}_cyclictest.log" 2>&1 &
  ct=$!; pids+=($ct)
  chrt -f 95 "$build/bin/fri_sim_krc" --port 49938 --cycles "$krc_cycles" --period-ms 1 --wrench "$rt_press_wrench" \
    --schedule 0:MON:PERFECT,1000:CMD:PERFECT --latency-out "$out/${cfg}_krc.txt" >"$out/${cfg}_krc.log" 2>&1 || true
  wait "$ct" || true
  [ -n "$load" ] && { wait "$load" || true; }
  wait "$dep" || echo "rt_latency: $cfg: the deployer exited non-zero (see ${cfg}_deployer.log)" >&2
  grep -h "fri_sim_krc:" "$out/${cfg}_krc.log" | cut -c1-160 || true
  grep -ho "rt_latency: Robot received.*" "$out/${cfg}_deployer.log" | head -1 || true
done
/usr/bin/python3 "$root/scripts/realtime/rt_latency_report.py" "$out" | tee "$out/rt_latency.md"
