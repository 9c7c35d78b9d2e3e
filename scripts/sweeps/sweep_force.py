#!/usr/bin/python3
"""The true force on target: the tactile-only servo against the force estimate.

usage: sweep_force.py [--out out/force] [--jobs N] [--seeds N] [--sim PATH]

Runs each geometry of the sweep twice, with the same bar, pose, effects and
seed:
  before  the scene with the paper's program (*_paper.yaml): the servo
          regulates the tactile force (Eq. 2) alone, CoP_y at 0, whose
          taxels below the 0.2 N firing threshold read 0;
  after   the scene and program as shipped (edge_exploration, bent_bar_fused:
          bent_bar's program to the bar's end cap): the tactile force
          corrected by the arm's estimated wrench (force_estimator.hpp) with
          the correction bounded at 4.5 N (scripts/sweeps/sweep_correction.py), the
          edge on a taxel row. The estimated wrench carries the scene's
          error (a constant offset, tared in free motion, and 0.5 N of noise
          per axis).
Geometries (scene overrides only; a scene still names just its bar):
  straight bar (edge exploration, pad friction 0.5): edge radius 2, 3, 5, 8 mm;
      yaw offset of the bar in the sensor plane 10 (shipped), 20, 30 deg;
  bent bar: edge radius 2, 3, 5, 8 mm; bend up (shipped) and down; towards +y
      (shipped) and -y.
Scored on the true (simulated force-torque sensor) force while sliding, as
summary.json scores it (the phases after their transient): RMS error and the
fraction of the time within 5 +- 0.5 N (targets: <= 0.4 N, >= 95 %).
Writes force.csv, force.md (table) and force.png (before/after) into --out;
exits 1 when a run writes no summary.
"""
import copy
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import tactile_sweeps as ts  # noqa: E402
from tactile_sweeps.plot import plt, save  # noqa: E402

BAND = ts.FORCE_BAND_N  # N: the target band around the 5 N set point
TARGET_RMS = ts.FORCE_RMS_MAX_N
TARGET_IN_BAND = ts.FORCE_IN_BAND_MIN


def rotate_about(v, c, deg):
    """Rotates point v about the vertical through c by deg (in the xy plane)."""
    a = math.radians(deg)
    x, y = v[0] - c[0], v[1] - c[1]
    return [c[0] + math.cos(a) * x - math.sin(a) * y, c[1] + math.sin(a) * x + math.cos(a) * y, v[2]]


def straight_cases():
    """(label, overrides of objects[0]) for the edge exploration's bar."""
    bar = ts.load_scene("edge_exploration")["objects"][0]
    bar["vertices"] = [[float(x) for x in v] for v in bar["vertices"]]
    out = []
    for r in (0.002, 0.003, 0.005, 0.008):
        o = copy.deepcopy(bar)
        o["radius"] = r
        out.append((f"straight r={r * 1000:g} mm", o))
    # The shipped bar is 10 deg off x_s in the sensor plane; 20 and 30 deg
    # rotate it further about the point under the sensor's start position.
    v0, v1 = bar["vertices"]
    t = ((0.72 - v0[0]) * (v1[0] - v0[0]) + (0.0 - v0[1]) * (v1[1] - v0[1])) / (
        (v1[0] - v0[0]) ** 2 + (v1[1] - v0[1]) ** 2)
    c = [v0[0] + t * (v1[0] - v0[0]), v0[1] + t * (v1[1] - v0[1])]
    for extra in (10.0, 20.0):
        o = copy.deepcopy(bar)
        o["vertices"] = [rotate_about(v0, c, extra), rotate_about(v1, c, extra)]
        out.append((f"straight yaw {10 + extra:g} deg", o))
    return out


def bent_cases():
    bar = ts.load_scene("bent_bar")["objects"][0]
    bar["vertices"] = [[float(x) for x in v] for v in bar["vertices"]]  # YAML 1.1 reads 9e-05 as a string
    z0 = bar["vertices"][0][2]
    out = []
    for r in (0.002, 0.003, 0.005, 0.008):
        o = copy.deepcopy(bar)
        o["radius"] = r
        out.append((f"bent r={r * 1000:g} mm", o))
    o = copy.deepcopy(bar)
    o["vertices"] = [[v[0], v[1], z0 - (v[2] - z0)] for v in bar["vertices"]]
    out.append(("bent down", o))
    o = copy.deepcopy(bar)
    o["vertices"] = [[v[0], -v[1], v[2]] for v in bar["vertices"]]
    out.append(("bent towards -y", o))
    return out


def one(job):
    label, before_scene, after_scene, obj, seed, out = job
    res = {}
    # Both start where the shipped scene starts (its approach is longer, to tare
    # the wrench in free motion; a bar of 8 mm radius would start inside the
    # housing at the bent bar's shipped start).
    start = ts.load_scene(after_scene)["initial_flange"]
    paper = os.path.join(ts.scenes.PROGRAMS, PAPER_PROGRAM[after_scene])
    for tag, scene, extra in (("before", before_scene, ["--program", paper]), ("after", after_scene, [])):
        d = os.path.join(out, "runs", f"{label.replace(' ', '_').replace('=', '')}_{tag}_{seed}")
        args = ["--seed", str(seed), "--set", "objects=" + json.dumps([obj]),
                "--set", f"metrics.force_band_n={BAND}", "--set", "initial_flange=" + json.dumps(start)] + extra
        res[tag] = ts.run.run(scene, d, args)
    return label, seed, res


# The paper's tactile-only program of each scene (the "before").
PAPER_PROGRAM = {"edge_exploration": "edge_exploration_paper.yaml", "bent_bar_fused": "bent_bar_paper.yaml"}


def main():
    a = ts.parse_args(__doc__, "force")
    cases = [(l, "edge_exploration", "edge_exploration", o) for l, o in straight_cases()]
    cases += [(l, "bent_bar_fused", "bent_bar_fused", o) for l, o in bent_cases()]
    jobs = [(l, b, f, o, s, a.out) for (l, b, f, o) in cases for s in range(1, a.seeds + 1)]
    results = {}
    failed = False
    for k, n, (label, seed, res) in ts.pmap(one, jobs, a.jobs):
        results[(label, seed)] = res
        for tag in ("before", "after"):
            if res[tag].get("status") == "no_summary":
                failed = True
                print(f"{label} seed {seed} {tag}: no summary: {res[tag].get('error', '')[-300:]}", file=sys.stderr)
        print(f"[{k}/{n}] {label} seed {seed}: RMS {rms(res['before'])} -> {rms(res['after'])} N", flush=True)

    def mean(label, tag, key):
        return ts.mean([results[(label, s)][tag].get(key) for s in range(1, a.seeds + 1)])

    rows = []
    for (label, _, _, _) in cases:
        r = {"case": label}
        for tag in ("before", "after"):
            for key in ("force_true_mean_n", "force_true_rms_error_n", "force_true_in_band_fraction",
                        "contact_lost_count", "path_length_m"):
                r[f"{tag}_{key}"] = mean(label, tag, key)
            r[f"{tag}_status"] = ",".join(sorted({results[(label, s)][tag].get("status", "?")
                                                  for s in range(1, a.seeds + 1)}))
        r["after_meets"] = r["after_force_true_rms_error_n"] <= TARGET_RMS and \
            r["after_force_true_in_band_fraction"] >= TARGET_IN_BAND
        rows.append(r)
    ts.write_csv(os.path.join(a.out, "force.csv"), rows)
    with open(os.path.join(a.out, "force.md"), "w") as f:
        f.write(f"True force while sliding, set point 5 N; mean over seeds 1..{a.seeds}. "
                f"before: tactile force (the paper, *_paper.yaml); after: as shipped, the force estimate bounded at 4.5 N.\n\n")
        f.write("| case | true mean (N) before / after | RMS error (N) before / after | "
                f"within +-{BAND:g} N before / after | contact losses after | path (m) after | target met |\n")
        f.write("|---|---|---|---|---|---|---|\n")
        for r in rows:
            if r["before_status"] != "ok":  # e.g. stopped by a watchdog: its force is not scored
                for key in ("force_true_mean_n", "force_true_rms_error_n", "force_true_in_band_fraction"):
                    if r[f"before_{key}"] != r[f"before_{key}"]:
                        r[f"before_{key}"] = float("nan")
                r["case"] += f" (before: {r['before_status']})"
            f.write(f"| {r['case']} | {r['before_force_true_mean_n']:.2f} / {r['after_force_true_mean_n']:.2f} | "
                    f"{r['before_force_true_rms_error_n']:.2f} / {r['after_force_true_rms_error_n']:.2f} | "
                    f"{r['before_force_true_in_band_fraction']:.3f} / {r['after_force_true_in_band_fraction']:.3f} | "
                    f"{r['after_contact_lost_count']:.1f} | {r['after_path_length_m']:.3f} | "
                    f"{'yes' if r['after_meets'] else 'no'} |\n")
    fig, ax = plt.subplots(1, 2, figsize=(13, 5))
    y = list(range(len(rows)))
    labels = [r["case"] for r in rows]
    for i, (key, title, target) in enumerate((("force_true_rms_error_n", "true-force RMS error (N)", TARGET_RMS),
                                              ("force_true_in_band_fraction", f"fraction within 5 +- {BAND:g} N",
                                               TARGET_IN_BAND))):
        ax[i].barh([v + 0.2 for v in y], [r[f"before_{key}"] for r in rows], 0.4, label="before: tactile force")
        ax[i].barh([v - 0.2 for v in y], [r[f"after_{key}"] for r in rows], 0.4, label="after: force estimate")
        ax[i].axvline(target, color="k", ls="--", lw=1, label=f"target {target:g}")
        ax[i].set_yticks(y)
        ax[i].set_yticklabels(labels if i == 0 else [])
        ax[i].invert_yaxis()
        ax[i].set_title(title)
        ax[i].grid(axis="x", alpha=0.3)
    ax[0].legend(loc="lower right", fontsize=8)
    fig.suptitle(f"True force on target: straight bar (edge exploration) and bent bar, seeds 1..{a.seeds}")
    save(fig, os.path.join(a.out, "force.png"), dpi=110)
    print(open(os.path.join(a.out, "force.md")).read())
    return 1 if failed else 0


def rms(s):
    """The run's true-force RMS error for the progress line."""
    v = s.get("force_true_rms_error_n")
    return ts.fmt(float(v) if ts.report.isnum(v) else None, 2, missing="nan")


if __name__ == "__main__":
    sys.exit(main())
