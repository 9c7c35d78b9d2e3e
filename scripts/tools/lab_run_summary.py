#!/usr/bin/python3
"""The robot path's summary of one experiment run through the unchanged robot
deployment against lab_sim (scripts/run_robot_lab.sh): the deployment's own
summary (RUN_DIR/run/summary.json, scripts/tools/deployment_to_run.py: what
the robot sees) with the simulator's ground truth filled in from lab_sim's
truth CSV (what the controller never sees), the scene's criteria judged on it,
and the robot path's verdict.

usage: lab_run_summary.py RUN_DIR --scene SCENE.yaml --program PROGRAM.yaml
                          [--controller-mode MODE] [--experiment NAME]
                          [--deployer-exit N] [--lab-exit N]

RUN_DIR holds run/ (run_robot.sh --out: report.dat, timeseries.csv,
summary.json), truth.csv (lab_sim --truth-out) and lab_sim.log. Writes
RUN_DIR/summary.json and RUN_DIR/truth.png.

The two clocks (the reporter's TimeStamp, lab_sim's world time) are aligned
on the flange's z (plot_lab_truth.align_offset: its first 2 mm of descent,
or of rise); each truth row takes the
servo's phase and force set point of the reporter's row at that time. The
true force and the flange's path then go through the headless runner's two
windows (the slide and the scored window: deployment_to_run.windows, the
rule of core/sim/runner/src/metrics.cpp), so force_true_*, slide_* and
path_length_m mean what they mean in a headless summary.json; the path is the
flange's while the world says the pad touches (the runner's is the true
contact point's). force_true_run_max_n is the true force's maximum over the
whole run, from the bridge's first reply to its last, any phase. A tray's
recovery time and translation (measured data) count from its move on the
world's clock, which lab_sim started before the deployment.

The verdict: "pass" when the experiment's state machine ended FINISHED
(deployer exit 0) and the true force never exceeded FORCE_BOUND_N in the whole
run; else "fail". The scene's criteria are judged on the same figures and
reported beside it (criteria_passed, criteria_failed; criteria on quantities
the truth does not carry are listed under criteria_not_judged).
"""
import argparse
import csv
import json
import math
import os
import re
import sys

import numpy as np
import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import deployment_to_run as d2r  # noqa: E402
import plot_lab_truth  # noqa: E402

# The project's bound on the true contact force (every scene's force_true_max_n
# criterion, the "never above 7 N true").
FORCE_BOUND_N = 7.0


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run_dir")
    ap.add_argument("--scene", required=True)
    ap.add_argument("--program", required=True)
    ap.add_argument("--controller-mode", default="")
    ap.add_argument("--experiment", default="")
    ap.add_argument("--deployer-exit", type=int, default=0)
    ap.add_argument("--lab-exit", type=int, default=0)
    return ap.parse_args()


def truth_on_reporter(truth, ts, offset):
    """Per truth row inside the reporter's span: time (reporter clock), phase name, sd_force, force_true,
    flange position, in_contact."""
    t_rep = np.array([float(r["time"]) for r in ts])
    tt = np.array([float(r["t"]) for r in truth]) - offset
    inside = (tt >= t_rep[0]) & (tt <= t_rep[-1])
    idx = np.clip(np.searchsorted(t_rep, tt[inside], side="right") - 1, 0, len(ts) - 1)
    rows = [truth[i] for i in np.nonzero(inside)[0]]
    return {
        "t": tt[inside],
        "names": [ts[i]["phase_name"] for i in idx],
        "sd_force": np.array([float(ts[i]["sd_force"]) for i in idx]),
        "force": np.array([float(r["force_true"]) for r in rows]),
        "pos": np.array([[float(r[f"flange_{c}"]) for c in "xyz"] for r in rows]).reshape(-1, 3),
        "in_contact": np.array([r["in_contact"] in ("1", "true") for r in rows], dtype=bool),
    }


def truth_figures(tr, prog, scene):
    """The runner's truth metrics over its two windows, from the truth rows."""
    metrics = scene.get("metrics", {}) or {}
    scored_names = metrics.get("force_phases") or [n for n, d in zip(prog["names"], prog["scored_default"]) if d]
    transient = float(metrics.get("transient_s", 0.0))
    band = float(metrics.get("force_band_n", 1.0))
    slide, scored = d2r.windows(tr["t"], tr["names"], scored_names, transient)
    args = (tr["t"], tr["force"], tr["sd_force"], tr["pos"], tr["in_contact"], band)
    sw, sc = d2r.window_figures(slide, *args), d2r.window_figures(scored, *args)
    lost = int(np.sum(slide[1:] & slide[:-1] & tr["in_contact"][:-1] & ~tr["in_contact"][1:]))
    return {
        "force_true_mean_n": sc["mean_n"], "force_true_max_n": sc["max_n"],
        "force_true_rms_error_n": sc["rms_error_n"], "force_true_in_band_fraction": sc["in_band_fraction"],
        "scored_path_m": sc["path_m"], "scored_mean_speed_mps": sc["speed_mps"],
        "path_length_m": sc["path_m"], "slide_speed_mps": sc["speed_mps"],
        "slide_path_m": sw["path_m"], "slide_mean_speed_mps": sw["speed_mps"],
        "slide_force_true_mean_n": sw["mean_n"], "slide_force_true_max_n": sw["max_n"],
        "slide_force_true_rms_error_n": sw["rms_error_n"],
        "slide_force_true_in_band_fraction": sw["in_band_fraction"],
        "contact_lost_count": lost,
    }


def tray_on_world_clock(scene, ts, offset):
    """The tray's DZMP_y recovery time and translation along x_s (deployment_to_run.tray_figures, measured
    data) with the tray's move placed on the reporter's clock: lab_sim's world moves it at move_start_s of
    its own time, which started before the deployment's (by the offset). (None, None) without a tray."""
    trays = [o for o in scene.get("objects", []) or [] if o.get("type") == "tray"]
    if not trays:
        return None, None
    shifted = dict(scene, objects=[dict(trays[0], move_start_s=float(trays[0].get("move_start_s", 0.0)) - offset)])
    col = lambda k: np.array([float(r[k]) for r in ts])  # noqa: E731
    pos = np.stack([col("act_x"), col("act_y"), col("act_z")], axis=1)
    rpy = np.stack([col("act_roll"), col("act_pitch"), col("act_yaw")], axis=1)
    return d2r.tray_figures(shifted, col("time"), col("dzmp_y"), col("contact") > 0, pos, rpy)


def align(truth, report_z):
    """plot_lab_truth.align_offset on the flange's first 2 mm of descent, or, for a program that starts by
    lifting (the tray's take), of rise: (offset, rms) or None."""
    fit = plot_lab_truth.align_offset(truth, report_z)
    if fit is None and len(report_z):
        flipped = [dict(r, flange_z=str(-float(r["flange_z"]))) for r in truth]
        fit = plot_lab_truth.align_offset(flipped, report_z * np.array([1.0, -1.0]))
    return fit


def judge(scene, summary):
    """(passed, failed, not_judged): the scene's criteria on the summary's figures."""
    failed, not_judged = [], []
    for key, c in ((scene.get("metrics", {}) or {}).get("criteria", {}) or {}).items():
        v = summary.get(key)
        if v is None or (isinstance(v, float) and not math.isfinite(v)):
            not_judged.append(key)
            continue
        if "min" in c and v < float(c["min"]):
            failed.append(f"{key} = {v:.4g} < {c['min']}")
        if "max" in c and v > float(c["max"]):
            failed.append(f"{key} = {v:.4g} > {c['max']}")
    return not failed, failed, not_judged


def lab_statistics(log):
    """lab_sim's end-of-run figures (its last lines)."""
    out = {}
    m = re.search(r"first reply at t ([0-9.]+) s, last at t ([0-9.]+) s; between them sent (\d+) lost (\d+)", log)
    if m:
        out.update(first_reply_s=float(m.group(1)), last_reply_s=float(m.group(2)),
                   fri_sent=int(m.group(3)), fri_lost=int(m.group(4)))
    m = re.search(r"max_step ([0-9.e+-]+) m ([0-9.e+-]+) rad", log)
    if m:
        out.update(fri_max_step_m=float(m.group(1)), fri_max_step_rad=float(m.group(2)))
    return out


def main():
    a = parse_args()
    run = os.path.join(a.run_dir, "run")
    summary = json.load(open(os.path.join(run, "summary.json")))
    scene = yaml.safe_load(open(a.scene))
    prog = d2r.load_program(a.program, a.controller_mode)
    truth = plot_lab_truth.read_truth(os.path.join(a.run_dir, "truth.csv"))
    ts = list(csv.DictReader(open(os.path.join(run, "timeseries.csv"))))
    log = open(os.path.join(a.run_dir, "lab_sim.log")).read()
    lab = lab_statistics(log)
    fit = align(truth, plot_lab_truth.read_report_z(os.path.join(run, "report.dat")))
    tt = np.array([float(r["t"]) for r in truth])
    ft = np.array([float(r["force_true"]) for r in truth])
    span = (tt >= lab.get("first_reply_s", 0.0)) & (tt <= lab.get("last_reply_s", math.inf))
    run_max = float(np.max(ft[span])) if span.any() else float(np.max(ft))
    summary.update(fidelity="robot deployment against lab_sim (wall clock)", source="robot_lab",
                   experiment=a.experiment or summary.get("scene"), scene_file=a.scene,
                   deployer_exit=a.deployer_exit, lab_sim_exit=a.lab_exit, force_true_run_max_n=run_max,
                   truth_time_offset_s=None, truth_align_rms_m=None, **lab)
    if fit is not None:
        summary.update(truth_time_offset_s=round(fit[0], 4), truth_align_rms_m=fit[1])
        summary.update(truth_figures(truth_on_reporter(truth, ts, fit[0]), prog, scene))
        recovery, translation = tray_on_world_clock(scene, ts, fit[0])
        if translation is not None:
            summary.update(dzmp_recovery_time_s=recovery, translation_x_m=translation)
    passed, failed, not_judged = judge(scene, summary)
    summary.update(criteria_passed=passed, criteria_failed=failed, criteria_not_judged=not_judged)
    ok = a.deployer_exit == 0 and run_max <= FORCE_BOUND_N
    summary["robot_verdict"] = "pass" if ok else "fail"
    with open(os.path.join(a.run_dir, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
        f.write("\n")
    sys.argv = ["plot_lab_truth.py", os.path.join(a.run_dir, "truth.csv"), os.path.join(a.run_dir, "truth.png"),
                "--run", run]
    plot_lab_truth.main()
    speed = summary.get("slide_mean_speed_mps")
    print(f"lab_run_summary: {summary['experiment']}: {summary['robot_verdict']} (state machine "
          f"{'FINISHED' if a.deployer_exit == 0 else 'FAILED'}, status {summary.get('status')}), true force max "
          f"{max(run_max, 0.0):.2f} N (bound {FORCE_BOUND_N} N), slide speed "
          f"{'-' if speed is None else '%.1f mm/s' % (speed * 1e3)}, criteria "
          f"{'passed' if passed else 'FAILED: ' + '; '.join(failed)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
