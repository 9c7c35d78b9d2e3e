#!/usr/bin/python3
"""The three controllers side by side on every scene.

usage: compare_controllers.py [--sim build/bin/tactile_sim] [--out out/compare]
                              [--scenes a,b,...] [--controllers proposed,baseline,no_rotation]
                              [--paper]

Runs `tactile_sim run SCENE --controller C` for every shipped scene
(params/scenes/*.yaml) and every controller:
  proposed     the touch-dependent J^-1 with the DZMP rows (Eq. 8);
  baseline     Li et al. (RSS 2013): constant J^-1 on CoP, force, alpha_z with
               the CoP -> rotation rows, no DZMP (tactile::liJinv);
  no_rotation  ablation: constant diag(1,1,1,0,0,1), never rotates about x_s, y_s.
Everything else (program, gains, P, safety, scene) is identical. --paper runs
each scene's program as the paper has it, the `*_paper.yaml` beside it
where there is one (Eq. 2's force alone, CoP_y at 0), instead of the shipped
program (the force estimate). Writes into
the output folder compare.csv, compare.md (the table of README.md) and
compare_<scene>.png (true force against time, the three controllers overlaid,
with the sensor's pitch), and keeps each run in <out>/<scene>/<controller>/.
A run that ends at a safety limit (exit 3 or 4) is a result, not an error:
its status is in the table. Exit code 1 when a run could not start (exit 2)
or wrote no summary.
"""
import argparse
import csv
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import tactile_sweeps as ts  # noqa: E402
from tactile_sweeps.plot import plt, save  # noqa: E402
from tactile_sweeps.report import fmt  # noqa: E402

ROOT = ts.ROOT

CONTROLLERS = ["proposed", "baseline", "no_rotation"]
LABEL = {"proposed": "proposed (DZMP, Eq. 8)", "baseline": "baseline (Li et al. 2013)",
         "no_rotation": "no_rotation (ablation)"}
COLOR = {"proposed": "tab:red", "baseline": "tab:blue", "no_rotation": "tab:gray"}
# Scene order of the table: the shipped experiments first, then the scenes
# where the DZMP rows should matter.
ORDER = ["edge_exploration", "bent_bar", "co_manipulation", "sphere_table",
         "partial_edge", "short_bar", "off_centre_load"]
# One extra key metric per scene (summary.json key, column title).
EXTRA = {"edge_exploration": ("alignment_time_s", "alignment s"),
         "bent_bar": ("slide_speed_mps", "slide m/s"),
         "co_manipulation": ("dzmp_recovery_time_s", "DZMP recovery s")}


BAND_N = ts.FORCE_BAND_N  # N: the true-force target's band, every scene


def load_series(path):
    """Time, true force, flange pitch (deg), housing force and the largest force set point of a run."""
    t, f, pitch, housing, sd = [], [], [], [], 0.0
    with open(path) as fh:
        for r in csv.DictReader(fh):
            t.append(float(r["time"]))
            f.append(float(r["force_true"]))
            pitch.append(math.degrees(float(r["act_pitch"])))
            housing.append(float(r["housing_force"]))
            sd = max(sd, float(r["sd_force"]))
    return t, f, pitch, housing, sd


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sim", default=os.path.join(ROOT, "build", "bin", "tactile_sim"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "compare"))
    ap.add_argument("--scenes", default="", help="comma-separated scene names (default: the experiment scenes of params/scenes)")
    ap.add_argument("--controllers", default=",".join(CONTROLLERS))
    ap.add_argument("--paper", action="store_true", help="the paper's programs (*_paper.yaml) where there are")
    a = ap.parse_args()

    shipped = ts.shipped_scenes()
    scenes = [s for s in a.scenes.split(",") if s] or (
        [s for s in ORDER if s in shipped] + [s for s in shipped if s not in ORDER])
    controllers = [c for c in a.controllers.split(",") if c]
    os.makedirs(a.out, exist_ok=True)

    rows, failed = [], 0
    t0 = time.time()
    for scene in scenes:
        series = {}
        extra = ["--set", f"metrics.force_band_n={BAND_N}"]
        paper = ts.paper_program(scene) if a.paper else None
        if paper:
            extra += ["--program", paper]
        for c in controllers:
            d = os.path.join(a.out, scene, c)
            s = ts.run.run(scene, d, ["--controller", c, *extra], sim=a.sim)
            if s["status"] == "no_summary":
                print(f"compare_controllers: {scene} {c}: exit {s['returncode']}: {s['error']}", file=sys.stderr)
                failed += 1
                continue
            key, _ = EXTRA.get(scene, (None, None))
            rows.append({
                "scene": scene, "controller": c, "status": s["status"], "exit_code": s["returncode"],
                "sim_time_s": s["sim_time_s"],
                "force_true_mean_n": s["force_true_mean_n"], "force_true_max_n": s["force_true_max_n"],
                "force_true_rms_error_n": s["force_true_rms_error_n"],
                "force_true_in_band_s": s.get("force_true_in_band_s"), "force_scored_s": s.get("force_scored_s"),
                "force_true_in_band_fraction": s["force_true_in_band_fraction"],
                "contact_lost_count": s["contact_lost_count"],
                "extra_key": key or "", "extra_value": s.get(key) if key else None,
            })
            series[c] = load_series(os.path.join(d, "timeseries.csv"))
            print(f"{scene:16s} {c:12s} {s['status']:18s} true force mean {fmt(s['force_true_mean_n'])} N, "
                  f"RMS error {fmt(s['force_true_rms_error_n'])} N")
        if series:
            fig, (ax, ax2) = plt.subplots(2, 1, figsize=(9, 6), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
            for c, (t, f, pitch, housing, _) in series.items():
                ax.plot(t, f, color=COLOR.get(c), label=LABEL.get(c, c), lw=1.2)
                ax2.plot(t, pitch, color=COLOR.get(c), lw=1.2)
            sd = max(v[4] for v in series.values())
            ax.axhspan(sd - BAND_N, sd + BAND_N, color="green", alpha=0.1, label=f"desired +- {BAND_N} N")
            top = max(max(v[1]) for v in series.values())
            ax.set_ylim(0, min(max(10.0, top * 1.05), 80.0))
            ax.set_ylabel("true force (N)")
            force = "the paper's force, Eq. 2" if a.paper else "the shipped force estimate"
            ax.set_title(f"{scene}: the three controllers (same program, gains, scene; {force})")
            ax.legend(loc="upper left", fontsize=8)
            ax.grid(alpha=0.3)
            ax2.set_ylabel("flange pitch (deg)")
            ax2.set_xlabel("time (s)")
            ax2.grid(alpha=0.3)
            save(fig, os.path.join(a.out, f"compare_{scene}.png"), dpi=90)

    fields = ["scene", "controller", "status", "exit_code", "sim_time_s", "force_true_mean_n", "force_true_max_n",
              "force_true_rms_error_n", "force_true_in_band_s", "force_scored_s", "force_true_in_band_fraction",
              "contact_lost_count", "extra_key", "extra_value"]
    ts.write_csv(os.path.join(a.out, "compare.csv"), rows, fields)
    with open(os.path.join(a.out, "compare.md"), "w") as fh:
        fh.write("| scene | controller | status | true force mean / max (N) | RMS error (N) | "
                 f"within +-{BAND_N:g} N (s of scored s) | contact losses | scene metric |\n")
        fh.write("| --- | --- | --- | --- | --- | --- | --- | --- |\n")
        for r in rows:
            band = (f"{fmt(r['force_true_in_band_s'], 1)} of {fmt(r['force_scored_s'], 1)} "
                    f"({fmt(100.0 * r['force_true_in_band_fraction'], 0)} %)"
                    if r["force_true_in_band_fraction"] is not None else "-")
            extra = f"{EXTRA[r['scene']][1]} {fmt(r['extra_value'], 3)}" if r["extra_key"] else ""
            fh.write(f"| {r['scene']} | {r['controller']} | {r['status']} | {fmt(r['force_true_mean_n'])} / "
                     f"{fmt(r['force_true_max_n'])} | {fmt(r['force_true_rms_error_n'])} | {band} | "
                     f"{r['contact_lost_count']} | {extra} |\n")
        fh.write("\n'-': not measured (the run never reached a scored phase, or no such event, e.g. DZMP_y never "
                 "back within 0.5 mm). Scored: the scene's metrics.force_phases after metrics.transient_s.\n")
    print(f"compare_controllers: {len(rows)} runs in {time.time() - t0:.1f} s -> {a.out}/compare.md, compare.csv, "
          f"compare_<scene>.png")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
