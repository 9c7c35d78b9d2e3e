# Sourced by scripts/realtime/rt_latency.sh, scripts/realtime/rt_soak.sh and tests/ros/run_robot_*_test.sh: what they do
# before their own runs. Needs `name` (the script's name for messages) set by the caller.
# Sets root, build, orocos, deployer; defines rt_check_tools, rt_stage_deployments
# and rt_start_wts_sim (with the cleanup trap of the background processes in pids).
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${BUILD:-$root/build}"
orocos="${OROCOS:-/opt/orocos}"
deployer="${DEPLOYER:-$orocos/bin/deployer-gnulinux}"  # scripts/realtime/sanitize.sh: its wrapper

# The simulated peers' priorities where the machine grants SCHED_FIFO (as the
# deployment's threads get theirs): lab_sim stands for the KRC, a controller of
# its own (95); fri_check answers the KRC where the FRI bridge will (90, the
# bridge's priority), so its verdict on the cycle is the bridge's and not that
# of whatever else runs. Empty where not granted.
krc_prio=(chrt -f 95)
bridge_prio=(chrt -f 90)
chrt -f 1 true 2>/dev/null || { krc_prio=(); bridge_prio=(); }

# The deployer and the two simulated peers must be built.
rt_check_tools() {
  local t
  for t in "$deployer" "$build/bin/fri_sim_krc" "$build/bin/wts_sim"; do
    [ -x "$t" ] || { echo "$name: $t missing (build with -DTACTILE_WITH_RTT=ON)" >&2; exit 1; }
  done
}

# A copy of deployments/ in $1/deployments with absolute paths and the
# simulated sensor's PTY ($1/wts0) in place of /dev/ttyACM0.
rt_stage_deployments() {
  local out="$1"
  mkdir -p "$out/deployments"
  cp "$root"/deployments/*.ops "$root"/deployments/*.cpf "$root"/deployments/*.osd "$out/deployments/"
  sed -i "s#\.\./#$root/#g" "$out"/deployments/*.cpf
  sed -i "s#<value>/dev/ttyACM0</value>#<value>$out/wts0</value>#" "$out/deployments/wts_reader.cpf"
  # The experiment registry where the copy's Guard looks (../experiments.yaml), its paths absolute.
  sed -E "s#^( +(scene|program|file): )([^/\"])#\1$root/\3#" "$root/experiments.yaml" > "$out/experiments.yaml"
}

# The simulated WTS0614 on the PTY $1/wts0 (a press circling the pad), killed on exit.
pids=()
rt_cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap rt_cleanup EXIT
# The force wts_sim's press (--pattern blob) would put on the arm, for
# fri_sim_krc --wrench: 6.3 N along z_g, the blob's mean total over its circle
# (5.4-6.9 N). With it the servo's sensor checks see two sensors that agree;
# without it the press is a phantom contact, and the servo stops the run.
rt_press_wrench="0,0,6.3"
# rt_press_wrench_tool EXPERIMENT: the same press in the flange's axes for
# fri_sim_krc --wrench-tool: the contact pushes the pad back toward the
# flange, along -z_s (z_s from the program's controller.sensor_mount; the
# servo reads a press as -F . z_s, force_estimator.hpp; the program with its
# `base:` merged, as `tactile_sim program` prints it).
rt_press_wrench_tool() {
  TACTILE_SIM="$build/bin/tactile_sim" /usr/bin/python3 - "$root" "$1" <<'PY'
import math, subprocess, sys
root, exp = sys.argv[1], sys.argv[2]
sys.path.insert(0, f"{root}/scripts/tools")
import program_yaml  # noqa: E402
prog = subprocess.run(["/usr/bin/python3", f"{root}/scripts/tools/registry.py", "get", exp, "program"],
                      capture_output=True, text=True, check=True).stdout.strip()
mount = (program_yaml.load(f"{root}/{prog}").get("controller", {}) or {}).get("sensor_mount", {}) or {}
r, p, y = (math.radians(a) for a in mount.get("rpy_deg", [0, 0, 0]))
# z_s in {e}: the third column of Rz(y) Ry(p) Rx(r)
z = (math.cos(y) * math.sin(p) * math.cos(r) + math.sin(y) * math.sin(r),
     math.sin(y) * math.sin(p) * math.cos(r) - math.cos(y) * math.sin(r),
     math.cos(p) * math.cos(r))
print(",".join(f"{-6.3 * c:.4f}" for c in z))
PY
}
rt_start_wts_sim() {
  local out="$1"
  "$build/bin/wts_sim" --link "$out/wts0" --pattern blob >"$out/wts_sim.log" 2>&1 &
  pids+=($!)
  for _ in $(seq 50); do [ -e "$out/wts0" ] && break; sleep 0.1; done
  [ -e "$out/wts0" ] || { echo "$name: wts_sim did not start" >&2; exit 1; }
}
