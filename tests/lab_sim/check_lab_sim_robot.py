#!/usr/bin/python3
"""ctest lab_sim_robot_edge_exploration: checks of run_lab_sim_robot_test.sh's
run (the unchanged robot deployment of the edge exploration against lab_sim,
the KRC in CMD from its first packet).

usage: check_lab_sim_robot.py OUT_DIR LAB_SIM_EXIT DEPLOYER_EXIT SCENE_YAML PROGRAM_YAML FRI_YAML

  * the deployment ran to its end: deployer exit 0, no failed step, the
    state machine FINISHED;
  * the KRC side: lab_sim exit 0 (no MON echo / flag / non-finite error), the
    bridge answered >= 95 % of the measurements between its first and its
    last reply (before and after, the deployment was starting / stopped; a
    shared 2-core machine misses some 1 ms deadlines, the bridge holds
    through them), never a jump
    (largest step between applied commands <= fri.yaml's max_lin_speed /
    max_rot_speed x the 1 ms cycle), the world never in a fatal state;
  * the edge was explored: the servo's phases free_motion, align,
    edge_control and explore were reached in that order (the reporter's
    table, converted by run_robot.sh); while exploring (after the scene's
    metrics.transient_s) the TRUE force (lab_sim's truth, which the
    controller never sees) has its mean within the scene's criterion
    (force_true_mean_n) and its RMS error about the program's target below
    1 N (the scene's own 0.4 N criterion is the headless runner's; here the
    loop runs on a shared machine's wall clock: reported, not judged), and the
    flange slid at least the scene's slide_path_m along the bar (the whole
    slide: explore from its start).
The two time bases (the reporter's TimeStamp, lab_sim's world time) are
aligned on the flange's z, which both record (the descent of free_motion).
"""
import csv
import json
import re
import sys

import os

import numpy as np
import yaml

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "tools"))
import plot_lab_truth  # noqa: E402
import program_yaml  # noqa: E402  (a program as the servo merges it: tactile_sim program)

out, lab_rc, dep_rc = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
scene = yaml.safe_load(open(sys.argv[4]))
program = program_yaml.load(sys.argv[5])
fri = yaml.safe_load(open(sys.argv[6]))["fri"]
failures = []
PERIOD = 0.001  # the KRC's cycle in this test (lab_sim's default)
EXPLORE_RMS_MAX_N = 1.0
# Measurements without their reply in their 1 ms cycle while the deployment
# ran: a scheduling bound, not a timing test (measured 0.1 % on the shared
# 2-core machine with other tests running; the bridge holds through a miss).
LOST_MAX = 0.05


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def criterion(name, key):
    c = scene.get("metrics", {}).get("criteria", {}).get(name, {})
    return float(c[key]) if key in c else None


# --- the deployment -----------------------------------------------------------
log = open(f"{out}/run/deployer.log").read()
check(dep_rc == 0 and "deployment step failed" not in log, f"every deployment step passed (deployer exit {dep_rc})")
check(re.search(r"the state machine TimedPhaseExperiment ended in FINISHED", log) is not None,
      "the experiment's state machine ended in FINISHED")
m = re.search(r"\[TimedPhaseExperiment\] finished: (\w+)", log)
print(f"measured: TimedPhaseExperiment result {m.group(1) if m else '?'}")

# --- lab_sim ------------------------------------------------------------------
lab = open(f"{out}/lab_sim.log").read()
check(lab_rc == 0, f"lab_sim: no protocol violation (exit {lab_rc})")
m = re.search(r"KRC cycles (\d+) sent (\d+) replies (\d+) lost (\d+) .* overruns (\d+) applied (\d+)", lab)
s = re.search(r"max_step ([0-9.e+-]+) m ([0-9.e+-]+) rad .* max_entry_offset ([0-9.e+-]+) m ([0-9.e+-]+) rad", lab)
wl = re.search(r"world steps (\d+) not_converged (\d+) invalid_commands (\d+) fatal (\d+)", lab)
fr = re.search(r"first reply at t ([0-9.]+) s, last at t ([0-9.]+) s; between them sent (\d+) lost (\d+)", lab)
check(m is not None and s is not None and wl is not None and fr is not None, "lab_sim printed its statistics")
if m and s and wl and fr:
    cycles, sent, replies, lost, overruns, applied = (int(m.group(i)) for i in range(1, 7))
    step_m, step_rad, entry_m, entry_rad = (float(s.group(i)) for i in range(1, 5))
    lin, rot = float(fri["max_lin_speed"]), float(fri["max_rot_speed"])
    t_first, t_last, sent_on, lost_on = float(fr.group(1)), float(fr.group(2)), int(fr.group(3)), int(fr.group(4))
    check(lost_on <= LOST_MAX * sent_on, f"the bridge answered all but {lost_on} of the {sent_on} measurements "
          f"between its first and last reply (t {t_first:.3f} - {t_last:.3f} s)")
    check(step_m <= lin * PERIOD + 1e-7, f"no jump: largest applied step {step_m * 1e6:.2f} um <= {lin * PERIOD * 1e6:.1f} um")
    check(step_rad <= rot * PERIOD + 1e-6, f"no jump: largest applied rotation {step_rad * 1e3:.4f} mrad <= "
          f"{rot * PERIOD * 1e3:.4f} mrad")
    check(int(wl.group(4)) == 0, f"the world never in a fatal state ({wl.group(4)} steps)")
    print(f"measured: KRC cycles {cycles} sent {sent} replies {replies} lost {lost} overruns {overruns} applied {applied}; "
          f"max step {step_m * 1e6:.2f} um {step_rad * 1e3:.4f} mrad; entry offset {entry_m * 1e6:.3f} um "
          f"{entry_rad * 1e3:.4f} mrad; world not_converged {wl.group(2)}")

# --- the reporter's table: phases -------------------------------------------------
ts = list(csv.DictReader(open(f"{out}/run/timeseries.csv")))
check(len(ts) > 100, f"reporter rows: {len(ts)}")
order = []
t_enter = {}
for r in ts:
    if not order or order[-1] != r["phase_name"]:
        order.append(r["phase_name"])
        t_enter.setdefault(r["phase_name"], float(r["time"]))
want = ["free_motion", "align", "edge_control", "explore"]
seen = [p for p in order if p in want]
check(seen[:4] == want, f"phases in order: {' -> '.join(order)}")
summary = json.load(open(f"{out}/run/summary.json"))

# --- align the time bases on the flange's z (scripts/tools/plot_lab_truth.py) --------
truth = list(csv.DictReader(open(f"{out}/truth.csv")))
tt = np.array([float(r["t"]) for r in truth])
fit = plot_lab_truth.align_offset(truth, plot_lab_truth.read_report_z(f"{out}/run/report.dat"))
check(fit is not None, "both records see the free-motion descent (2 mm)")
if fit is not None:
    offset, rms_align = fit
    check(rms_align < 5e-4, f"time bases aligned: world t = reporter t + {offset:.3f} s (z residual {rms_align * 1e6:.0f} um)")
    if "explore" in t_enter:
        t0 = t_enter["explore"] + offset + float(scene.get("metrics", {}).get("transient_s", 2.0))
        after = [p for p in order[order.index("explore") + 1:]] if "explore" in order else []
        t1 = (min(float(r["time"]) for r in ts if r["phase_name"] == after[0] and float(r["time"]) > t_enter["explore"])
              + offset) if after else tt[-1]
        sel = (tt >= t0) & (tt < t1)
        f = np.array([float(truth[i]["force_true"]) for i in np.nonzero(sel)[0]])
        target = float(next(p for p in program["phases"] if p["name"] == "explore")["s_d"]["force"])
        band = float(scene.get("metrics", {}).get("force_band_n", 0.5))
        check(len(f) > 1000, f"truth rows while exploring (after the transient): {len(f)} ({(t1 - t0):.2f} s)")
        if len(f):
            mean, rms = float(np.mean(f)), float(np.sqrt(np.mean((f - target) ** 2)))
            inband = float(np.mean(np.abs(f - target) <= band))
            lo, hi = criterion("force_true_mean_n", "min"), criterion("force_true_mean_n", "max")
            check(lo <= mean <= hi, f"true force while exploring: mean {mean:.3f} N in [{lo}, {hi}] (target {target} N)")
            check(rms <= EXPLORE_RMS_MAX_N, f"true force RMS error {rms:.3f} N <= {EXPLORE_RMS_MAX_N} N")
            sel_all = (tt >= t_enter["explore"] + offset) & (tt < t1)
            pa = np.array([[float(truth[i][f"flange_{c}"]) for c in "xyz"] for i in np.nonzero(sel_all)[0]])
            path = float(np.sum(np.linalg.norm(np.diff(pa, axis=0), axis=1))) if len(pa) > 1 else 0.0
            need = criterion("slide_path_m", "min")
            check(path >= need, f"slid {path * 1e3:.1f} mm along the bar while exploring (>= {need * 1e3:.0f} mm)")
            tactile = summary.get("force_measured_mean_n")
            print(f"measured: explore from reporter t {t_enter['explore']:.2f} s for {t1 - t_enter['explore'] - offset:.2f} s; "
                  f"true force mean {mean:.3f} N sd {float(np.std(f)):.3f} N min {float(np.min(f)):.3f} "
                  f"max {float(np.max(f)):.3f} N, RMS error {rms:.3f} N, within +-{band} N {inband * 100:.1f} %; "
                  f"path {path * 1e3:.1f} mm; the tactile force (features) mean "
                  f"{'%.3f N' % tactile if tactile is not None else '?'}")
print("measured: phase entries (reporter time) " + ", ".join(f"{k} {v:.2f} s" for k, v in t_enter.items()))

print(f"lab_sim_robot: {len(failures)} check(s) failed" if failures else "lab_sim_robot: all checks passed")
sys.exit(1 if failures else 0)
