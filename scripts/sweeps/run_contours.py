#!/usr/bin/python3
"""Runs the whole-contour scenes (sim/scenes/ring, rounded_square, s_curve,
gap_bars: scripts/tools/make_contour_scenes.py) through the headless runner, checks
each with scripts/tools/contour_check.py and writes OUT/contours.md (the table of
the README's "Whole closed contours") and OUT/contours.png (the four
reconstructions over the truth).

With --sensor-effects every sensor effect is on (device noise, gain spread,
calibration error, crosstalk, creep, hysteresis, dead taxels, the WTS transfer
delay: the levels of scripts/sweeps/sweep_effects.py); --seeds N runs seeds 1..N
(the plots: seed 1). The closure is the true one (contour_check.py), the
controller's own beside it.

usage: run_contours.py [--sim build/bin/tactile_sim] [--out out/contours] [--seeds N] [--sensor-effects]
                       [--scenes ring,rounded_square,s_curve,gap_bars]
Exits 1 when a run fails its checks.
"""
import argparse
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
# scene, open contour, the RMS bound the check applies (m), gap crossings
SCENES = [("ring", False, 0.001, 0), ("rounded_square", False, 0.001, 0), ("s_curve", True, 0.001, 0),
          ("gap_bars", True, 0.001, 1)]
# Every sensor effect at its realistic level: scripts/sweeps/sweep_effects.py's table.
sys.path.insert(0, HERE)
import sweep_effects  # noqa: E402

SENSOR = ["device_noise", "gain_spread", "calibration_error", "crosstalk", "creep", "hysteresis", "dead_taxels",
          "wts_delay"]
SENSOR_EFFECTS = [arg for e in SENSOR for arg in sweep_effects.EFFECTS[e][0]]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sim", default=os.path.join(ROOT, "build", "bin", "tactile_sim"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "contours"))
    ap.add_argument("--seeds", type=int, default=1)
    ap.add_argument("--sensor-effects", action="store_true")
    ap.add_argument("--scenes", default=",".join(s[0] for s in SCENES), help="comma-separated subset")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    res = []
    for name, is_open, rms, gaps in (s for s in SCENES if s[0] in a.scenes.split(",")):
        scene = os.path.join(ROOT, "sim", "scenes", name + ".yaml")
        for seed in range(1, a.seeds + 1):
            run = os.path.join(a.out, name if seed == 1 else "%s_seed%d" % (name, seed))
            subprocess.run([a.sim, "run", scene, "--out", run, "--no-plots", "--seed", str(seed)]
                           + (SENSOR_EFFECTS if a.sensor_effects else []), check=False, stdout=subprocess.DEVNULL)
            cmd = [sys.executable, os.path.join(ROOT, "scripts", "tools", "contour_check.py"), run, scene, "--max-rms", str(rms),
                   "--gap-crossings", str(gaps)]
            if is_open:
                cmd.append("--open")
            if seed != 1:
                cmd.append("--no-plot")
            rc = subprocess.run(cmd, stdout=subprocess.DEVNULL).returncode
            r = json.load(open(os.path.join(run, "contour.json")))
            r["open"], r["rc"], r["bound"], r["seed"] = is_open, rc, rms, seed
            sm = json.load(open(os.path.join(run, "summary.json")))
            r["force"] = (sm.get("force_true_mean_n"), sm.get("force_true_rms_error_n"), sm.get("force_true_in_band_fraction"))
            res.append(r)
    with open(os.path.join(a.out, "contours.md"), "w") as f:
        f.write("| scene | seed | status | explore -> done (s) | true force mean / RMS error (N) / within +-0.5 N | "
                "closure (true, mm) or end (mm) | cloud RMS (mm) | coverage | "
                "arc-corrected CoP RMS (mm) | raw CoP RMS (mm) | 3-D RMS (mm) | max (mm) | unwinds (at s) | gap crossings (at s) | check |\n"
                "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n")
        for r in res:
            ce = ("end %.1f" % (r["end_distance_m"] * 1e3)) if r["open"] else ("%.1f" % (r["closure_m"] * 1e3))
            fm, fe, fb = (float("nan") if v is None else v for v in r["force"])
            f.write("| %s | %d | %s | %.1f -> %.1f | %.2f / %.2f / %.0f %% | %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.1f | %d (%s) | %d (%s) | %s |\n" % (
                r["scene"], r["seed"], r["status"], r["t_explore_s"], r["t_done_s"] or float("nan"), fm, fe, 100 * fb, ce,
                r["rms_m"] * 1e3,
                min(r["coverage"]), r["rms_arc_m"] * 1e3, r["rms_cop_m"] * 1e3, r["rms_3d_m"] * 1e3, r["max_m"] * 1e3,
                r["unwinds"],
                ", ".join("%.1f" % t for t in r["unwind_times_s"]) or "-", r["gap_crossings"],
                ", ".join("%.1f" % t for t in r["gap_times_s"]) or "-",
                "pass" if r["rc"] == 0 else "FAIL: " + "; ".join(r["failed"])))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image as mpimg
    import matplotlib.pyplot as plt
    first = [r for r in res if r["seed"] == 1]
    fig, ax = plt.subplots(len(first), 1, figsize=(12, 5.5 * len(first)), squeeze=False)
    for k, r in enumerate(first):
        ax[k][0].imshow(mpimg.imread(os.path.join(a.out, r["scene"], "contour.png")))
        ax[k][0].axis("off")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "contours.png"), dpi=80)
    print(open(os.path.join(a.out, "contours.md")).read())
    return 0 if all(r["rc"] == 0 for r in res) else 1


if __name__ == "__main__":
    sys.exit(main())
