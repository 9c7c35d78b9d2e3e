#!/usr/bin/python3
"""ctest lab_sim_robot_verdict_<experiment>: the robot path gives the headless
verdict (run_lab_sim_robot_verdict_test.sh).

usage: check_lab_sim_robot_verdict.py HEADLESS_DIR ROBOT_LAB_DIR SEEDS_DIR

  * headless (tactile_sim run): its verdict, status ok and the scene's
    criteria passed ("pass"), else "fail";
  * robot path (scripts/run_robot_lab.sh: summary.json's robot_verdict):
    the state machine FINISHED and lab_sim's true force never above 7 N;
  * both verdicts the same; or else the robot path's outcome (its status,
    e.g. servo_surface_too_curved) one the headless runner ends with on one of
    the seeds under SEEDS_DIR (seed_<n>/summary.json): the robot path is one
    more realization of the sensors' noise and of the loop's timing, and an
    experiment whose headless verdict depends on the seed gets no stricter
    test on the robot path (the seeds' outcomes are printed);
  * the true force's maximum over the whole run at most 7 N on both paths
    (headless: its table's force_true; robot path: lab_sim's truth between
    the bridge's first and last reply);
  * the run ended as the headless one does: for a state machine that ends on
    its run_time (the scene's duration), the robot path's run lasted no more
    than the scene's duration plus RUN_END_SLACK_S of the reporter's time;
  * the KRL program ended its run by itself: the deployer's log names the
    program's step at the end ("KRL program at the end: closed"), and
    lab_sim's KRC left command mode after the bridge's request (a state change
    to MON that no script word caused).
Prints the table's row: verdicts, true force max and slide speed of each.
"""
import csv
import json
import os
import re
import sys

import yaml

FORCE_BOUND_N = 7.0
# The reporter's table spans the deployer's start-up before the state machine
# counts (the servo waits for the first packets) and the finish script's end
# (the stop request, the components stopped): a few seconds on a loaded machine.
RUN_END_SLACK_S = 6.0

head_dir, lab_dir, seeds_dir = sys.argv[1], sys.argv[2], sys.argv[3]
failures = []


def rmax_ok(summary):
    v = summary.get("force_true_run_max_n")
    return v is not None and v <= FORCE_BOUND_N


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


h = json.load(open(os.path.join(head_dir, "summary.json")))
with open(os.path.join(head_dir, "timeseries.csv"), newline="") as f:
    head_max = max(float(r["force_true"]) for r in csv.DictReader(f))
head_verdict = "pass" if h.get("status") == "ok" and h.get("criteria_passed") else "fail"
path = os.path.join(lab_dir, "summary.json")
check(os.path.exists(path), f"the robot path's summary {path}")
if not os.path.exists(path):
    sys.exit(1)
r = json.load(open(path))
rv = r.get("robot_verdict")
seeds = {}
for d in sorted(os.listdir(seeds_dir) if os.path.isdir(seeds_dir) else [], key=lambda n: int(n.split("_")[-1])):
    p = os.path.join(seeds_dir, d, "summary.json")
    if os.path.exists(p):
        s = json.load(open(p))
        seeds.setdefault(s.get("status"), []).append(d.replace("seed_", ""))
print("measured: headless outcomes over the seeds: " + "; ".join(f"{k} on {len(v)} ({', '.join(v)})" for k, v in seeds.items()))
same = rv == head_verdict
check(same or (rv == "fail" and r.get("status") in seeds and rmax_ok(r)),
      f"{'the same verdict' if same else 'an outcome of the headless runner'}: headless {head_verdict} "
      f"(status {h.get('status')}, criteria "
      f"{'passed' if h.get('criteria_passed') else 'failed'}), robot path {rv} (deployer exit {r.get('deployer_exit')}, "
      f"status {r.get('status')})" + ("" if same else f"; the headless runner ends {r.get('status')} on seeds "
                                     f"{', '.join(seeds.get(r.get('status'), [])) or 'none'}"))
check(head_max <= FORCE_BOUND_N, f"headless true force max {head_max:.2f} N <= {FORCE_BOUND_N} N")
rmax = r.get("force_true_run_max_n")
check(rmax is not None and rmax <= FORCE_BOUND_N, f"robot path true force max {rmax:.2f} N <= {FORCE_BOUND_N} N")

log = open(os.path.join(lab_dir, "run", "deployer.log")).read()
if "run_time" in log and re.search(r"s of the run \(run_time [0-9.]+ s\): switchPhase", log):
    scene = yaml.safe_load(open(r["scene_file"]))
    check(r["sim_time_s"] <= float(scene["duration"]) + RUN_END_SLACK_S,
          f"ended on run_time: the reporter's run {r['sim_time_s']:.1f} s <= the scene's duration "
          f"{scene['duration']} s + {RUN_END_SLACK_S} s")
m = re.search(r"KRL program at the end: (\w+)", log)
check(m is not None and m.group(1) == "closed", f"the KRL program at the end: {m.group(1) if m else '?'} (closed)")
lab = open(os.path.join(lab_dir, "lab_sim.log")).read()
check(re.search(r"cycle \d+: KRC MON", lab) is not None,
      "lab_sim's KRC left command mode by the bridge's request (no script word)")
sp = lambda s: "-" if s.get("slide_mean_speed_mps") is None else f"{s['slide_mean_speed_mps'] * 1e3:.1f} mm/s"  # noqa: E731
print(f"measured: {os.path.basename(lab_dir)} | headless {head_verdict}, true force max {head_max:.2f} N, "
      f"slide {sp(h)}, {h.get('sim_time_s')} s | robot path {rv}, true force max {rmax:.2f} N, slide {sp(r)}, "
      f"{r.get('sim_time_s')} s, criteria {'passed' if r.get('criteria_passed') else r.get('criteria_failed')}")
print(f"lab_sim_robot_verdict: {len(failures)} check(s) failed" if failures else "lab_sim_robot_verdict: all checks passed")
sys.exit(1 if failures else 0)
