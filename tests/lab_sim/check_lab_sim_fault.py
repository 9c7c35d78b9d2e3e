#!/usr/bin/python3
"""ctest lab_sim_robot_phantom_contact: checks of run_lab_sim_robot_fault_test.sh's
run (the unchanged robot deployment against lab_sim on a faulty scene).

usage: check_lab_sim_fault.py OUT_DIR DEPLOYER_EXIT STATUS MAX_TRAVEL_M

  * the unattended run failed (run_robot.sh's exit non-zero, its verdict FAIL)
    and says why: the experiment's state machine names the servo's status
    STATUS (`watchdog STATUS: ...`), without an error of the finishing script;
  * summary.json (the reporter's table converted) names STATUS and when it
    came, and the table reaches it;
  * lab_sim's truth (which the controller never sees): the flange travelled
    at most MAX_TRAVEL_M from where the KRC's first command found it, and the
    true force on the pad stayed below 1 N (nothing is in reach).
"""
import csv
import json
import math
import re
import sys

out, dep_rc, want, max_travel = sys.argv[1], int(sys.argv[2]), sys.argv[3], float(sys.argv[4])
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


log = open(f"{out}/run/deployer.log").read()
run_log = open(f"{out}/run_robot.log").read()
check(dep_rc != 0 and "run_robot: FAIL" in run_log, f"the unattended run failed (run_robot.sh exit {dep_rc})")
check(re.search(r"watchdog " + re.escape(want) + r"\b", log) is not None,
      f"the state machine names the servo's stop ({want})")
parse_errors = [ln for ln in log.splitlines() if re.search(r"Parse error|Attempt to initialize|Semantic error", ln)]
check(not parse_errors, "no script error after the failed run" + (f": {parse_errors[0][:160]}" if parse_errors else ""))

summary = json.load(open(f"{out}/run/summary.json"))
status = str(summary.get("status"))
check(want in status or want == summary.get("servo_status") or want in str(summary.get("fault", "")),
      f"summary.json names the stop: status {status}")
rows = list(csv.DictReader(open(f"{out}/run/timeseries.csv")))
stops = [float(r["time"]) for r in rows if r["servo_status"] == want]
check(bool(stops), f"the reporter's table reaches the stop ({len(rows)} rows)")
if stops:
    print(f"measured: the stop at reporter t {stops[0]:.3f} s")

truth = list(csv.DictReader(open(f"{out}/truth.csv")))
cmd = [r for r in truth if r["krc_state"] == "CMD"]
check(len(cmd) > 10, f"the KRC was in command mode ({len(cmd)} truth rows)")
if cmd:
    p0 = [float(cmd[0][k]) for k in ("flange_x", "flange_y", "flange_z")]
    travel = max(math.dist(p0, [float(r[k]) for k in ("flange_x", "flange_y", "flange_z")]) for r in cmd)
    fmax = max(float(r["force_true"]) for r in truth)
    check(travel <= max_travel, f"the flange travelled {travel * 1e3:.2f} mm <= {max_travel * 1e3:.1f} mm")
    check(fmax < 1.0, f"true force max {fmax:.2f} N < 1 N")
print(("FAILED: " + "; ".join(failures)) if failures else "all checks passed")
sys.exit(1 if failures else 0)
