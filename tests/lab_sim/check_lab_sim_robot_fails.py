#!/usr/bin/python3
"""ctest lab_sim_robot_first_touch_fails: checks of run_lab_sim_robot_fails_test.sh's
run (the robot deployment of the first touch against lab_sim with nothing
under the pad: the program ends in no_contact, the state machine FAILED).

usage: check_lab_sim_robot_fails.py RUN_DIR RUN_ROBOT_LOG RUN_ROBOT_EXIT

A failed run reads as cleanly as a passing one:
  * the deployer's log has no script error (no failed checkpoint, no parse or
    semantic error) and no failed deployment step;
  * it names the run's outcome and the verdict ("[Guard] run FAILED: the state
    machine FirstTouchExperiment ended in FAILED (... phase no_contact)",
    "[Guard] verdict: FAILED: ..."), the state machine's own reason (11, no
    contact) and the robot's status at the end; the reporter stopped;
  * the deployer and run_robot.sh exit 255, run_robot.sh reports FAIL;
  * timeseries.csv, summary.json and the plots are written: the summary's
    status experiment_failed at fault_time_s, the entry of no_contact, which
    the table reaches.
"""
import csv
import glob
import json
import re
import sys

run, robot_log, rc = sys.argv[1], sys.argv[2], int(sys.argv[3])
failures = []
# The approach's own timeout (params/programs/first_touch.yaml): 12 s
# of commandable time after the servo's start; the reporter's time starts with
# the servo, within a few cycles. Asserted within 1 s.
APPROACH_TIMEOUT_S = 12.0
TIME_TOL_S = 1.0


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


log = open(f"{run}/deployer.log", errors="replace").read()
bad = re.search(r"Attempt to initialize|[Ss]emantic error|[Pp]arse error|[Ss]yntax error|encountered an error", log)
check(bad is None, "no script error in the deployer's log" + (f" (found: {bad.group(0)})" if bad else ""))
check("deployment step failed" not in log, "no failed deployment step")
outcome = re.search(r"\[Guard\] run FAILED: the state machine FirstTouchExperiment ended in FAILED \(servo status (\w+), "
                    r"phase (\w+)\)", log)
check(outcome is not None and outcome.group(2) == "no_contact",
      "the outcome: run FAILED, the state machine in FAILED, the program in no_contact"
      + (f" (servo status {outcome.group(1)}, phase {outcome.group(2)})" if outcome else ""))
check(re.search(r"\[FirstTouchExperiment\] failed: reason 11 ", log) is not None,
      "the state machine names the fault: reason 11 (no contact)")
check(re.search(r"robot status at the end: \w+", log) is not None, "the robot's status at the end logged")
check(re.search(r"ok: stop Reporter \(closes first_touch_robot\.dat\)", log) is not None, "the reporter stopped")
verdict = re.search(r"\[Guard\] verdict: (FAILED: the state machine FirstTouchExperiment ended in FAILED .*) "
                    r"\(deployer exit 255\)", log)
check(verdict is not None, "the verdict: FAILED, the deployer's exit 255")
robot = open(robot_log, errors="replace").read()
check(rc == 255 and "run_robot: FAIL: first_touch (deployer exit 255): FAILED: the state machine" in robot,
      f"run_robot.sh exits 255 and reports FAIL with the verdict (exit {rc})")

s = json.load(open(f"{run}/summary.json"))
names = [p["name"] for p in s["phases"]]
t_none = next((p["t_enter"] for p in s["phases"] if p["name"] == "no_contact"), None)
check(names == ["approach", "no_contact"], f"phases approach, no_contact ({names})")
check(s["status"] == "experiment_failed", f"summary status experiment_failed ({s['status']})")
check(t_none is not None and s.get("fault_time_s") == t_none
      and abs(t_none - APPROACH_TIMEOUT_S) <= TIME_TOL_S,
      f"fault_time_s at the entry of no_contact, about {APPROACH_TIMEOUT_S} s ({s.get('fault_time_s')}, {t_none})")
check((s.get("verdict") or "").startswith("FAILED: the state machine FirstTouchExperiment"), "the verdict kept")
rows = list(csv.DictReader(open(f"{run}/timeseries.csv")))
check(len(rows) > 0 and float(rows[-1]["time"]) >= (t_none or 1e9),
      f"the table reaches the fault ({rows[-1]['time'] if rows else '-'} s)")
pngs = glob.glob(f"{run}/*.png")
check(len(pngs) > 0, f"plots written ({len(pngs)})")
print(f"lab_sim_robot_fails: {len(failures)} check(s) failed" if failures else "lab_sim_robot_fails: all checks passed")
sys.exit(1 if failures else 0)
