#!/usr/bin/python3
"""Speed/accuracy trade of the headless simulator.

usage: sweep_tradeoff.py [--sim build/bin/tactile_sim] [--out out/tradeoff] [--quick]

Runs the three experiments, the bent bar to its end cap and the four closed
contours under a grid of settings (physics rate, sub-taxel
samples, fidelity, servo rate), and reports, per setting, the wall time per
simulated second against the error of each scene's key metrics relative to the
finest setting (dynamics, 2 kHz physics, 8x8 sub-samples, 100 Hz servo).
Writes tradeoff.csv, tradeoff.md and tradeoff.png into the output folder.
"""
import os
import sys


sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import tactile_sweeps as ts  # noqa: E402
from tactile_sweeps.plot import plt  # noqa: E402

ROOT = ts.ROOT
# Scene -> key metrics (summary.json keys) compared with the finest setting:
# the experiments', and the whole closed contours' (docs/results.md, "Closed
# contours": the true force on the contour and the path slid round it).
CONTOUR_METRICS = ["force_true_mean_n", "path_length_m"]
SCENES = dict(ts.scenes.KEY_METRICS, **{c: CONTOUR_METRICS for c in ("ring", "rounded_square", "s_curve", "gap_bars")})

FINEST = {"fidelity": "dynamics", "sim": 2000, "subsamples": 8, "servo": 100}
GRID = [
    FINEST,
    {"fidelity": "dynamics", "sim": 1000, "subsamples": 4, "servo": 100},
    {"fidelity": "quasi_static", "sim": 1000, "subsamples": 8, "servo": 100},
    {"fidelity": "quasi_static", "sim": 1000, "subsamples": 4, "servo": 100},
    {"fidelity": "quasi_static", "sim": 1000, "subsamples": 2, "servo": 100},
    {"fidelity": "quasi_static", "sim": 1000, "subsamples": 1, "servo": 100},
    {"fidelity": "quasi_static", "sim": 500, "subsamples": 4, "servo": 100},
    {"fidelity": "quasi_static", "sim": 200, "subsamples": 4, "servo": 100},
    {"fidelity": "quasi_static", "sim": 200, "subsamples": 2, "servo": 100},
    {"fidelity": "quasi_static", "sim": 1000, "subsamples": 4, "servo": 50},
]
QUICK = [FINEST, GRID[3], GRID[7]]


def label(s):
    return f'{s["fidelity"]} {s["sim"]} Hz K={s["subsamples"]} servo {s["servo"]} Hz'


def run(sim, scene, s, out):
    d = os.path.join(out, "runs", f'{scene}_{s["fidelity"]}_{s["sim"]}_{s["subsamples"]}_{s["servo"]}')
    args = ["--fidelity", s["fidelity"], "--sim-rate", str(s["sim"]), "--subsamples", str(s["subsamples"]),
            "--servo-rate", str(s["servo"])]
    if s["sim"] < 200:
        args += ["--wts-rate", str(s["sim"]), "--features-rate", str(s["sim"])]
    return ts.run.run(scene, d, args, sim=sim)


rel_err = ts.rel_err


def main():
    ap = ts.cli.parser(__doc__, "tradeoff", jobs=1, seeds=None)  # 1 job: the wall times are not shared between runs
    ap.add_argument("--quick", action="store_true", help="three settings only")
    a = ts.cli.finish(ap.parse_args())
    grid = QUICK if a.quick else GRID
    jobs = [(scene, s) for scene in SCENES for s in grid]
    results = {}
    for k, n, r in ts.pmap(lambda j: ((j[0], label(j[1])), run(a.sim, j[0], j[1], a.out)), jobs, a.jobs):
        results[r[0]] = r[1]
        sys.stderr.write(f"\r{k}/{n} runs")
    sys.stderr.write("\n")
    rows = []
    for scene, keys in SCENES.items():
        ref = results[(scene, label(FINEST))]
        for s in grid:
            r = results[(scene, label(s))]
            errs = [rel_err(r.get(k), ref.get(k)) for k in keys]
            wall_per_s = r["wall_time_s"] / max(r["sim_time_s"], 1e-9)
            rows.append((scene, label(s), wall_per_s, r["real_time_factor"], max(errs), errs, r["status"]))
    with open(os.path.join(a.out, "tradeoff.csv"), "w") as f:
        f.write("scene,setting,wall_s_per_sim_s,real_time_factor,max_rel_error,status\n")
        for sc, lb, w, rtf, e, _, st in rows:
            f.write(f"{sc},{lb},{w:.6f},{rtf:.1f},{e:.4f},{st}\n")
    md = ["| scene | setting | wall s per sim s | real-time factor | max rel. error of key metrics | status |",
          "| --- | --- | --- | --- | --- | --- |"]
    for sc, lb, w, rtf, e, errs, st in rows:
        md.append(f"| {sc} | {lb} | {w:.4f} | {rtf:.0f}x | {e * 100:.1f} % | {st} |")
    md.append("")
    md.append("Key metrics: " + "; ".join(f"{k}: {', '.join(v)}" for k, v in SCENES.items()) +
              f". Reference: {label(FINEST)}.")
    open(os.path.join(a.out, "tradeoff.md"), "w").write("\n".join(md) + "\n")
    print("\n".join(md))
    fig, ax = plt.subplots(figsize=(11, 5.5))
    marks = {sc: m for sc, m in zip(SCENES, ["o", "s", "^", "D", "v", "P", "X", "*"])}
    colors = {label(s): plt.cm.tab10(i % 10) for i, s in enumerate(grid)}
    for sc, lb, w, rtf, e, _, st in rows:
        if lb == label(FINEST):
            continue
        ax.scatter(w, max(e, 1e-4) * 100, marker=marks[sc], s=50, color=colors[lb])
    for sc, m in marks.items():
        ax.scatter([], [], marker=m, color="k", label=sc)
    for lb, c in colors.items():
        if lb != label(FINEST):
            ax.scatter([], [], marker="o", color=c, label=lb)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time per simulated second (s)")
    ax.set_ylabel("max relative error of the key metrics vs finest (%)")
    ax.set_title("Speed / accuracy trade of the headless simulator")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "tradeoff.png"), dpi=90)
    print(f"written: {a.out}/tradeoff.csv, tradeoff.md, tradeoff.png")


if __name__ == "__main__":
    main()
