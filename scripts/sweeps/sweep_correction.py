#!/usr/bin/python3
"""The force estimate's bound: the true force against the tactile image.

usage: sweep_correction.py [--out out/correction] [--jobs N] [--seeds N] [--sim PATH]

The shipped edge-exploration and bent-bar programs regulate the tactile force
corrected by the arm's estimated wrench (force_estimator.hpp), the correction
bounded by force_estimate.max_correction_n. The bound trades two things:
  * the true force: the correction takes up the load the image does not report
    (taxels below the 0.2 N firing threshold, the sensor's gain and crosstalk
    errors); a small bound leaves the true force above the set point;
  * the image: every newton of correction is a newton less on the taxels, so
    more of them fall below the threshold and the contact features (CoP, the
    contact-point cloud) follow a thinner, broken image.
For each bound (the paper's tactile-only program, then 1 to 4.5 N) and seed it
runs each scene as shipped (effects, wrench error) and with every simulated
effect on (scripts/sweeps/sweep_effects.py's `all`), and reports the true force
(mean, RMS error, fraction within the issue's 5 +- 0.5 N while sliding), the
contact losses, the CoP's error against the true pressure centre while
sliding (contacts.csv: the controller's reconstructed contact point against
the simulator's truth, from 2 s after the slide starts; mean and 95th
percentile), split into its parts along and across the edge (the ridge of
the scene's bar, in the horizontal plane: contour_check.py), the contact
line's points (edge_points.csv: what an exploration reconstructs) across the
edge (RMS) and how many the slide gives per mm, and whether the scene's
criteria pass. Writes correction.csv, correction.md and correction.png into
--out; exits 1 when a run writes no summary.
"""
import csv
import math
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sweep_effects  # noqa: E402
import tactile_sweeps as ts  # noqa: E402
from tactile_sweeps.plot import plt, save  # noqa: E402

sys.path.insert(0, ts.TOOLS)
import contour_check  # noqa: E402

PROGRAMS = ts.PROGRAMS
EXPERIMENTS = ["edge_exploration", "bent_bar"]  # registry entries (experiments.yaml): their scene and program


def program_name(experiment):
    """The experiment's program (its registry entry's), as a name of params/programs."""
    return os.path.splitext(os.path.basename(ts.registry.load()[experiment]["program"]))[0]


def scene_of(experiment):
    return ts.registry.scene_name(ts.registry.load()[experiment])


SCENES = {scene_of(e): program_name(e) for e in EXPERIMENTS}  # scene -> program name
BOUNDS = [1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 4.5]
SLIDE_PHASE = "explore"


def program_with_bound(name, bound, out):
    """The shipped program with max_correction_n set to `bound` (a copy in out)."""
    with open(os.path.join(PROGRAMS, name + ".yaml")) as f:
        text = f.read()
    new, n = re.subn(r"(\n  max_correction_n:)\s*[0-9.]+", rf"\g<1> {bound}", text)
    if n != 1:
        raise SystemExit(f"sweep_correction: {name}.yaml has no single force_estimate.max_correction_n")
    path = os.path.join(out, "programs", f"{name}_{bound}.yaml")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(new)
    return path


NO_IMAGE = {"cop": [], "along": [], "across": [], "edge": [], "per_mm": float("nan")}


def image_errors(run_dir, scene):
    """The image's errors while sliding (from 2 s after the slide phase is
    entered), against the scene's ridge (contour_check.ridges) in the
    horizontal plane and the simulator's true pressure centre:
      cop      |reconstructed contact point - true pressure centre| (m), each row of contacts.csv
      along    its part along the ridge's local tangent (m)
      across   the CoP's distance to the ridge (m)
      edge     the contact line's points' distance to the ridge (m; edge_points.csv)
      per_mm   contact-line points per mm slid."""
    t_slide = None
    with open(os.path.join(run_dir, "timeseries.csv")) as f:
        for r in csv.DictReader(f):
            if r["phase_name"] == SLIDE_PHASE:
                t_slide = float(r["time"])
                break
    out = dict(NO_IMAGE)
    if t_slide is None:
        return out
    with open(os.path.join(run_dir, "contacts.csv")) as f:
        rows = [r for r in csv.DictReader(f) if float(r["time"]) >= t_slide + 2.0]
    if not rows:
        return out
    lines = [np.c_[v[:, :2], np.zeros(len(v))] for v in contour_check.ridges(ts.scene_path(scene))]
    P = np.array([[float(r[k]) for k in "xyz"] for r in rows])
    T = np.array([[float(r["true_" + k]) for k in "xyz"] for r in rows])
    flat = np.c_[P[:, :2], np.zeros(len(P))]
    out["cop"] = list(np.linalg.norm(P - T, axis=1))
    out["across"] = list(contour_check.dist_to_polylines(flat, lines))
    # along the ridge: the error's projection on the nearest segment's tangent
    best, tang = np.full(len(P), np.inf), np.zeros((len(P), 3))
    for v in lines:
        for a, b in zip(v[:-1], v[1:]):
            ab = b - a
            t = np.clip(((flat - a) @ ab) / max(ab @ ab, 1e-300), 0.0, 1.0)
            d = np.linalg.norm(flat - (a + t[:, None] * ab), axis=1)
            closer = d < best
            best[closer] = d[closer]
            tang[closer] = ab / np.linalg.norm(ab)
    out["along"] = list(np.abs(np.sum((P - T) * tang, axis=1)))
    with open(os.path.join(run_dir, "edge_points.csv")) as f:
        E = np.array([[float(r[k]) for k in "xyz"] for r in csv.DictReader(f) if float(r["time"]) >= t_slide + 2.0])
    if len(E):
        out["edge"] = list(contour_check.dist_to_polylines(np.c_[E[:, :2], np.zeros(len(E))], lines))
    slid = float(np.sum(np.linalg.norm(np.diff(P[:, :2], axis=0), axis=1)))
    out["per_mm"] = len(E) / (slid * 1000.0) if slid > 0 else float("nan")
    return out


def p95(v):
    v = sorted(v)
    return v[int(0.95 * (len(v) - 1))] if v else float("nan")


def rms(v):
    return math.sqrt(sum(x * x for x in v) / len(v)) if v else float("nan")


def one(job):
    scene, label, program, setting, seed, out = job
    d = os.path.join(out, "runs", f"{scene}_{label}_{setting}_{seed}")
    args = ["--seed", str(seed), "--program", program]
    if setting == "all":
        args = sweep_effects.effect_args(scene, sweep_effects.ALL) + args  # the wrench error among them
    s = ts.run.run(scene, d, args + ["--set", f"metrics.force_band_n={ts.FORCE_BAND_N}"])
    e = image_errors(d, scene) if s.get("status") != "no_summary" else NO_IMAGE
    s["cop_error_mean_m"] = sum(e["cop"]) / len(e["cop"]) if e["cop"] else float("nan")
    s["cop_error_p95_m"] = p95(e["cop"])
    s["cop_along_mean_m"] = sum(e["along"]) / len(e["along"]) if e["along"] else float("nan")
    s["cop_along_p95_m"] = p95(e["along"])
    s["cop_across_rms_m"] = rms(e["across"])
    s["edge_across_rms_m"] = rms(e["edge"])
    s["edge_points_per_mm"] = e["per_mm"]
    return scene, label, setting, seed, s


def main():
    a = ts.parse_args(__doc__, "correction")
    jobs = []
    for scene, prog in SCENES.items():
        variants = [("tactile", os.path.join(PROGRAMS, prog + "_paper.yaml"))]
        variants += [(f"{b:g}N", program_with_bound(prog, b, a.out)) for b in BOUNDS]
        for label, path in variants:
            for setting in ("shipped", "all"):
                for seed in range(1, a.seeds + 1):
                    jobs.append((scene, label, path, setting, seed, a.out))
    res, failed = {}, False
    for k, n, (scene, label, setting, seed, s) in ts.pmap(one, jobs, a.jobs):
        res[(scene, label, setting, seed)] = s
        if s.get("status") == "no_summary":
            failed = True
            print(f"{scene} {label} {setting} seed {seed}: no summary: {s.get('error', '')[-300:]}", file=sys.stderr)
        print(f"[{k}/{n}] {scene} {label} {setting} seed {seed}: RMS {s.get('force_true_rms_error_n')} N, "
              f"CoP error {s.get('cop_error_mean_m')} m", flush=True)

    labels = ["tactile"] + [f"{b:g}N" for b in BOUNDS]
    rows = []
    for scene in SCENES:
        for label in labels:
            r = {"scene": scene, "bound": label}
            for setting in ("shipped", "all"):
                runs = [res[(scene, label, setting, s)] for s in range(1, a.seeds + 1)]
                for key in ("force_true_mean_n", "force_true_rms_error_n", "force_true_in_band_fraction",
                            "contact_lost_count", "cop_error_mean_m", "cop_error_p95_m", "cop_along_mean_m",
                            "cop_along_p95_m", "cop_across_rms_m", "edge_across_rms_m", "edge_points_per_mm"):
                    r[f"{setting}_{key}"] = ts.mean([x.get(key) for x in runs])
                r[f"{setting}_passed"] = sum(1 for x in runs if x.get("criteria_passed") and x.get("returncode") == 0)
            rows.append(r)
    os.makedirs(a.out, exist_ok=True)
    ts.write_csv(os.path.join(a.out, "correction.csv"), rows)

    def f2(v, scale=1.0, digits=2):  # the table's cells: means over seeds (floats)
        return ts.fmt(v, digits, scale)

    with open(os.path.join(a.out, "correction.md"), "w") as f:
        f.write(f"Means over seeds 1-{a.seeds}. `tactile`: the paper's program (Eq. 2 alone, CoP_y 0); "
                "otherwise the shipped program with force_estimate.max_correction_n = the bound. "
                "CoP error: reconstructed contact point against the true pressure centre while sliding, "
                "and its part along the edge; across: RMS distance to the true ridge (horizontal plane) of the "
                "CoP and of the contact line's points (what an exploration reconstructs); line points per mm slid. "
                f"Criteria: seeds passed of {a.seeds}, as shipped / with every effect on.\n\n")
        f.write(f"| scene | bound | true force mean (N) | RMS error (N) | within 5 +- {ts.FORCE_BAND_N:g} N | CoP error mean / p95 (mm) | "
                "along the edge mean / p95 (mm) | across: CoP / line RMS (mm) | line points per mm | "
                "contact losses | RMS error, all effects (N) | criteria shipped / all |\n")
        f.write("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n")
        for r in rows:
            f.write(f"| {r['scene']} | {r['bound']} | {f2(r['shipped_force_true_mean_n'])} | "
                    f"{f2(r['shipped_force_true_rms_error_n'])} | {f2(r['shipped_force_true_in_band_fraction'], 100, 1)} % | "
                    f"{f2(r['shipped_cop_error_mean_m'], 1000, 1)} / {f2(r['shipped_cop_error_p95_m'], 1000, 1)} | "
                    f"{f2(r['shipped_cop_along_mean_m'], 1000, 1)} / {f2(r['shipped_cop_along_p95_m'], 1000, 1)} | "
                    f"{f2(r['shipped_cop_across_rms_m'], 1000, 2)} / {f2(r['shipped_edge_across_rms_m'], 1000, 2)} | "
                    f"{f2(r['shipped_edge_points_per_mm'], 1, 1)} | "
                    f"{f2(r['shipped_contact_lost_count'], 1, 1)} | {f2(r['all_force_true_rms_error_n'])} | "
                    f"{r['shipped_passed']} / {r['all_passed']} |\n")

    # Two costs of the image against the true force, per scene: the CoP along
    # the edge (the line's ends drop out) and the contact line across it
    # (what an exploration reconstructs).
    xs = (("cop_along_mean_m", "CoP error along the edge, mean (mm)"),
          ("edge_across_rms_m", "contact line across the ridge, RMS (mm)"))
    fig, ax = plt.subplots(len(SCENES), len(xs), figsize=(6 * len(xs), 4.2 * len(SCENES)), squeeze=False)
    for i, scene in enumerate(SCENES):
        for j, (key, xlabel) in enumerate(xs):
            for setting, marker in (("shipped", "o"), ("all", "s")):
                pts = [(r[f"{setting}_{key}"] * 1000, r[f"{setting}_force_true_rms_error_n"], r["bound"])
                       for r in rows if r["scene"] == scene]
                ax[i][j].plot([p[0] for p in pts], [p[1] for p in pts], marker=marker, label=f"{setting} effects")
                for x, y, lab in pts:
                    ax[i][j].annotate(lab, (x, y), fontsize=7, xytext=(3, 3), textcoords="offset points")
            ax[i][j].axhline(ts.FORCE_RMS_MAX_N, color="grey", ls="--", lw=0.8, label=f"target RMS {ts.FORCE_RMS_MAX_N:g} N")
            ax[i][j].set_xlabel(xlabel)
            ax[i][j].set_ylabel("true force RMS error while sliding (N)")
            ax[i][j].set_title(f"{scene}: the correction bound")
            ax[i][j].grid(alpha=0.3)
            ax[i][j].legend(fontsize=8)
    save(fig, os.path.join(a.out, "correction.png"), dpi=90)
    print(f"written: {a.out}/correction.csv, correction.md, correction.png")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
