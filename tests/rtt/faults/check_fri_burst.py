#!/usr/bin/python3
"""ctest rtt_fault_fri_burst: checks of run_fri_burst_test.sh's run (the robot
deployment against fri_sim_krc with a burst of 20 lost measurement packets).

usage: check_fri_burst.py OUT_DIR KRC_EXIT DEPLOYER_EXIT PROGRAM_YAML FRI_YAML

  * the simulated KRC saw no protocol violation (exit 0: MON echo, flags, no
    non-finite command), it lost exactly the 20 packets of the burst;
  * the bridge named the loss: its `lost` counter (sequence gap) is 20, 0
    before the burst; the deployment's steps all passed;
  * never a jump: the largest step between consecutive commands the KRC
    applied is within the bridge's rate limits (fri.yaml max_lin_speed and
    max_rot_speed times the KRC's 1 ms cycle), over the whole run and so
    across the burst (the KRC holds its set point during it);
  * the arm moved at the fastest speed the controller supports before and
    after the burst: the flange advanced >= 90 % of max_trans_speed over the
    1000 packets around it (the 20 ms hold included);
  * the loop resumed: the bridge answered every packet it received, its last
    status is commanding or limited, the servo is still sliding (phase slide,
    status free_motion or limited: no watchdog).
Not checked: latencies and missed replies (a virtual machine's scheduling; see
scripts/realtime/rt_latency.sh).
"""
import math
import re
import sys

import yaml
import os

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "scripts", "tools"))
import program_yaml  # noqa: E402  (a program as the servo merges it: tactile_sim program)

out, krc_rc, dep_rc, program, fri_file = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4], sys.argv[5]
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


v_max = float(program_yaml.load(program)["safety"]["max_trans_speed"])
fri = yaml.safe_load(open(fri_file))["fri"]
lin, rot = float(fri["max_lin_speed"]), float(fri["max_rot_speed"])
period = 0.001
krc = open(f"{out}/krc.log").read()
log = open(f"{out}/deployer.log").read()

m = re.search(r"fri_sim_krc: cycles (\d+) sent (\d+) replies (\d+) .* applied (\d+) .* nonfinite (\d+) "
              r"mon_echo_errors (\d+) max_step ([0-9.e+-]+) m ([0-9.e+-]+) rad .* injected loss (\d+)", krc)
check(m is not None, "fri_sim_krc printed its statistics")
if m:
    cycles, sent, replies, applied, nonfinite, mon_err = (int(m.group(i)) for i in range(1, 7))
    step_m, step_rad, lost_inj = float(m.group(7)), float(m.group(8)), int(m.group(9))
    check(krc_rc == 0, f"the simulated KRC saw no protocol violation (exit {krc_rc})")
    check(nonfinite == 0 and mon_err == 0, f"no non-finite command, no MON echo error ({nonfinite}, {mon_err})")
    check(cycles == 3000 and lost_inj == 20 and sent == cycles - 20, f"the burst: 20 of {cycles} measurements not sent "
          f"(injected {lost_inj}, sent {sent})")
    check(applied > 2500, f"the KRC applied the bridge's commands ({applied} of {cycles})")
    check(step_m <= lin * period + 1e-9, f"largest applied command step {step_m * 1e6:.2f} um <= max_lin_speed x 1 ms = "
          f"{lin * period * 1e6:.2f} um: never a jump")
    check(step_rad <= rot * period + 1e-9, f"largest applied rotation step {step_rad * 1e3:.4f} mrad <= "
          f"{rot * period * 1e3:.4f} mrad")
    print(f"measured: KRC replies {replies}/{sent}, max command step {step_m * 1e6:.2f} um {step_rad * 1e3:.4f} mrad")

check(dep_rc == 0 and "deployment step failed" not in log, f"every deployment step passed (deployer exit {dep_rc})")
at = re.findall(r"fri_burst at received (\d+) lost (\d+) x ([0-9.e+-]+) y ([0-9.e+-]+) z ([0-9.e+-]+)", log)
end = re.search(r"fri_burst end received (\d+) replies (\d+) lost (\d+) timeouts (\d+) socket_errors (\d+) bridge (\w+) "
                r"servo_status (\d+) phase (\w+)", log)
check(len(at) == 2 and end is not None, "the deployment printed its counters")
if len(at) == 2 and end:
    r1, l1 = int(at[0][0]), int(at[0][1])
    r2, l2 = int(at[1][0]), int(at[1][1])
    p1 = [float(v) for v in at[0][2:]]
    p2 = [float(v) for v in at[1][2:]]
    received, replies, lost, timeouts, sock = (int(end.group(i)) for i in range(1, 6))
    bridge, servo_status, phase = end.group(6), int(end.group(7)), end.group(8)
    check(l1 == 0, f"no loss before the burst (lost {l1} at {r1} packets)")
    check(l2 == 20 and lost == 20, f"the bridge counts the burst: lost {l2} at {r2} packets, {lost} at the end")
    # KRC cycles between the two samples: packets received + the 20 lost.
    span = (r2 - r1 + 20) * period
    d = math.dist(p1, p2)
    print(f"measured: flange moved {d * 1e3:.2f} mm in {span * 1e3:.0f} KRC cycles around the burst: "
          f"{d / span * 1e3:.1f} mm/s; bridge timeouts {timeouts}, last status {bridge}")
    check(d / span >= 0.9 * v_max, f"moving at the step limit around the burst: {d / span * 1e3:.1f} mm/s >= "
          f"90 % of {v_max * 1e3:.0f} mm/s")
    check(replies == received and sock == 0, f"the bridge answered every packet it received ({replies}/{received}), "
          f"no socket error ({sock})")
    check(bridge in ("commanding", "limited"), f"the bridge follows again after the burst ({bridge})")
    check(phase == "slide" and servo_status in (1, 4), f"the servo still slides (phase {phase}, status {servo_status}: "
          "free_motion 1 or limited 4, no watchdog)")

print(f"{len(failures)} failed")
sys.exit(1 if failures else 0)
