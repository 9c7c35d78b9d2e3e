#!/usr/bin/python3
"""Plot lab_sim's ground truth (--truth-out) of a rehearsal against the
simulated lab: the KRC's state, the true contact force and the flange's
travel over time, with the servo's phases of the deployment's run when its
run directory (scripts/run_robot.sh --out: report.dat, timeseries.csv) is
given. docs/lab_sim.md.

usage: plot_lab_truth.py TRUTH.csv OUT.png [--run RUN_DIR] [--target-force N]

The deployment's reporter and lab_sim have their own clocks; the phases are
placed on lab_sim's time by align_offset(): the shift that maps the
reporter's flange z (Robot.flange_pose, what the bridge received) onto the
truth's, found around the first 2 mm of descent.
"""
import argparse
import csv
import math
import os

import numpy as np


def read_truth(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_report_z(path):
    """(TimeStamp, flange z) of an OCL::FileReporting table with Robot.flange_pose."""
    head, out = None, []
    for ln in open(path):
        v = ln.split()
        if not v:
            continue
        if head is None:
            head = {h: i for i, h in enumerate(v)}
            continue
        out.append((float(v[head["TimeStamp"]]), float(v[head["Robot.flange_pose.p.Element2"]])))
    return np.array(out)


def align_offset(truth, report_z, drop_m=0.002, search_s=0.2):
    """(offset, rms): lab_sim time = reporter time + offset, and the z residual (m)
    of that fit; None when either record never descends by drop_m."""
    tt = np.array([float(r["t"]) for r in truth])
    tz = np.array([float(r["flange_z"]) for r in truth])
    z0 = tz[0]

    def first_below(t, z):
        i = int(np.argmax(z < z0 - drop_m))
        return t[i] if z[i] < z0 - drop_m else None

    a, b = first_below(report_z[:, 0], report_z[:, 1]), first_below(tt, tz)
    if a is None or b is None:
        return None
    span = (report_z[:, 0] >= a - 1.0) & (report_z[:, 0] <= a + 3.0)
    best = min((float(np.mean((np.interp(report_z[span, 0] + off, tt, tz) - report_z[span, 1]) ** 2)), off)
               for off in np.arange(b - a - search_s, b - a + search_s, 0.001))
    return best[1], math.sqrt(best[0])


def phase_entries(timeseries_csv):
    """[(name, reporter time of entry)] in order."""
    out = []
    with open(timeseries_csv, newline="") as f:
        for r in csv.DictReader(f):
            if not out or out[-1][0] != r["phase_name"]:
                out.append((r["phase_name"], float(r["time"])))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("truth")
    ap.add_argument("out")
    ap.add_argument("--run", default="")
    ap.add_argument("--target-force", type=float, default=None)
    a = ap.parse_args()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = read_truth(a.truth)
    t = np.array([float(r["t"]) for r in rows])
    level = {"closed": 0, "OFF": 0, "MON": 1, "CMD": 2}
    state = np.array([level.get(r["krc_state"], 0) + (1 if r["krc_state"] == "CMD" and r["krc_quality"] in ("OK", "PERFECT")
                                                      and r["krc_power"] == "1" else 0) for r in rows])
    force = np.array([float(r["force_true"]) for r in rows])
    p = np.array([[float(r[f"flange_{c}"]) for c in "xyz"] for r in rows])
    travel = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])

    fig, ax = plt.subplots(3, 1, figsize=(9, 7), sharex=True)
    ax[0].step(t, state, where="post")
    ax[0].set_yticks([0, 1, 2, 3], ["closed / OFF", "MON", "CMD, quality < OK\nor drives off", "CMD, commandable"])
    ax[0].set_title("lab_sim: the KRC (script), the world's true contact force and the flange's travel"
                    + ("\n(grey lines: the servo's phase entries)" if a.run else ""))
    ax[1].plot(t, force, lw=0.8)
    if a.target_force is not None:
        ax[1].axhline(a.target_force, color="k", ls="--", lw=0.8, label=f"program's target {a.target_force} N")
        ax[1].legend(loc="lower right")
    ax[1].set_ylabel("true force (N)")
    ax[2].plot(t, 1e3 * travel)
    ax[2].set_ylabel("flange travel (mm)")
    ax[2].set_xlabel("lab_sim time (s)")
    if a.run:
        fit = align_offset(rows, read_report_z(os.path.join(a.run, "report.dat")))
        if fit is not None:
            for name, te in phase_entries(os.path.join(a.run, "timeseries.csv")):
                for k in range(3):
                    ax[k].axvline(te + fit[0], color="0.6", lw=0.8)
                ax[2].text(te + fit[0], 0.97, " " + name, rotation=90, fontsize=8, va="top",
                           transform=ax[2].get_xaxis_transform())
    for k in range(3):
        ax[k].grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(a.out, dpi=90)
    print(f"plot_lab_truth: {a.out}")


if __name__ == "__main__":
    main()
