#!/usr/bin/python3
"""Runs the whole-contour scenes (params/scenes/ring, rounded_square, s_curve,
gap_bars: scripts/tools/make_contour_scenes.py) through the headless runner, checks
each with scripts/tools/contour_check.py and writes OUT/contours.md (the table of
docs/results.md, "Closed contours") and OUT/contours.png (the four
reconstructions over the truth).

With --sensor-effects every sensor effect is on (device noise, gain spread,
calibration error, crosstalk, creep, hysteresis, dead taxels, the WTS transfer
delay: the levels of scripts/sweeps/sweep_effects.py); --seeds N runs seeds 1..N
(the plots: seed 1). The closure is the true one (contour_check.py), the
controller's own beside it.

usage: run_contours.py [--sim build/bin/tactile_sim] [--out out/contours] [--seeds N] [--jobs N]
                       [--sensor-effects] [--scenes ring,rounded_square,s_curve,gap_bars]
Exits 1 when a run fails its checks.
"""
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import tactile_sweeps as ts  # noqa: E402

# scene, open contour, the RMS bound the check applies (m), gap crossings
SCENES = [("ring", False, 0.001, 0), ("rounded_square", False, 0.001, 0), ("s_curve", True, 0.001, 0),
          ("gap_bars", True, 0.001, 1)]
# Every sensor effect at its realistic level: scripts/sweeps/sweep_effects.py's table.
import sweep_effects  # noqa: E402

SENSOR = ["device_noise", "gain_spread", "calibration_error", "crosstalk", "creep", "hysteresis", "dead_taxels",
          "wts_delay"]
SENSOR_EFFECTS = [arg for e in SENSOR for arg in sweep_effects.EFFECTS[e][0]]


def one(job):
    """One seed of one contour: the run, then contour_check.py on it."""
    (name, is_open, rms, gaps), seed, sensor_effects, out = job
    run = os.path.join(out, name if seed == 1 else "%s_seed%d" % (name, seed))
    ts.run.run(name, run, ["--seed", str(seed)] + (SENSOR_EFFECTS if sensor_effects else []))
    cmd = [sys.executable, os.path.join(ts.TOOLS, "contour_check.py"), run, ts.scene_path(name), "--max-rms", str(rms),
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
    return r


def main():
    ap = ts.cli.parser(__doc__, "contours", jobs=1)
    ap.add_argument("--sensor-effects", action="store_true")
    ap.add_argument("--scenes", default=",".join(s[0] for s in SCENES), help="comma-separated subset")
    a = ts.cli.finish(ap.parse_args())
    chosen = [s for s in SCENES if s[0] in a.scenes.split(",")]
    jobs = [(s, seed, a.sensor_effects, a.out) for s in chosen for seed in range(1, a.seeds + 1)]
    res = [r for _, _, r in ts.pmap(one, jobs, a.jobs)]
    # The band each scene scores its true force in (its metrics.force_band_n).
    bands = sorted({ts.force_band(s[0]) for s in chosen})
    band = f"+-{bands[0]:g} N" if len(bands) == 1 else "the scene's band"
    with open(os.path.join(a.out, "contours.md"), "w") as f:
        f.write(f"| scene | seed | status | explore -> done (s) | true force mean / RMS error (N) / within {band} | "
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
    import matplotlib.image as mpimg
    from tactile_sweeps.plot import plt, save
    first = [r for r in res if r["seed"] == 1]
    fig, ax = plt.subplots(len(first), 1, figsize=(12, 5.5 * len(first)), squeeze=False)
    for k, r in enumerate(first):
        ax[k][0].imshow(mpimg.imread(os.path.join(a.out, r["scene"], "contour.png")))
        ax[k][0].axis("off")
    save(fig, os.path.join(a.out, "contours.png"), dpi=80)
    print(open(os.path.join(a.out, "contours.md")).read())
    return 0 if all(r["rc"] == 0 for r in res) else 1


if __name__ == "__main__":
    sys.exit(main())
