#!/usr/bin/env python3
"""Sensor-noise sweep: true force within 5 +- 1 N against the simulated noise.

Runs `tactile_sim run SCENE --set sensor.noise_counts=N --no-plots` for each
scene and noise level into OUT/<scene>_n<N>/, prints a markdown table of the
summaries and plots the in-band fraction against the noise (and, with
--compare, a second set of runs laid out the same way, e.g. made by an older
build) plus the true force over time at --trace-noise.

  /usr/bin/python3 scripts/sweeps/noise_sweep.py --bin build/bin/tactile_sim --out runs/noise \
      [--compare runs/noise_before --compare-label before] [--png runs/noise/noise_sweep.png]
"""
import argparse
import csv
import json
import os
import subprocess
import sys

SCENES = ["bent_bar", "edge_exploration"]
NOISE = [6, 12, 30, 60]  # counts, 1 sigma: 1x, 2x, 5x, 10x the default


def run_all(binary, out, scenes, noise, root):
    for s in scenes:
        for n in noise:
            d = os.path.join(out, "%s_n%d" % (s, n))
            cmd = [binary, "run", os.path.join(root, "sim", "scenes", s + ".yaml"), "--set",
                   "sensor.noise_counts=%g" % n, "--no-plots", "--out", d]
            subprocess.run(cmd, check=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def summary(out, s, n):
    p = os.path.join(out, "%s_n%d" % (s, n), "summary.json")
    if not os.path.exists(p):
        return None
    with open(p) as f:
        return json.load(f)


def fmt(v, f="%.3f"):
    return "-" if v is None else f % v


def table(sets, scenes, noise):
    lines = ["| scene | noise (counts, x default) | build | status | true force mean (N) | max (N) | RMS error (N) "
             "| in 5 +- 1 N | alignment (s) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for s in scenes:
        for n in noise:
            for label, out in sets:
                j = summary(out, s, n)
                if j is None:
                    continue
                lines.append("| %s | %d (%gx) | %s | %s | %s | %s | %s | %s | %s |" % (
                    s, n, n / 6.0, label, j["status"], fmt(j["force_true_mean_n"], "%.2f"),
                    fmt(j["force_true_max_n"], "%.2f"), fmt(j["force_true_rms_error_n"], "%.2f"),
                    fmt(j["force_true_in_band_fraction"]), fmt(j["alignment_time_s"], "%.2f")))
    return "\n".join(lines)


def trace(out, s, n):
    p = os.path.join(out, "%s_n%d" % (s, n), "timeseries.csv")
    t, ft, fm = [], [], []
    with open(p) as f:
        for r in csv.DictReader(f):
            t.append(float(r["time"]))
            ft.append(float(r["force_true"]))
            fm.append(float(r["force"]))
    return t, ft, fm


def plot(sets, scenes, noise, png, trace_noise):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1 + len(scenes), 1, figsize=(9, 3.2 * (1 + len(scenes))))
    ax = axes[0]
    for label, out in sets:
        for s, m in zip(scenes, ["o", "s"]):
            y = [(summary(out, s, n) or {}).get("force_true_in_band_fraction") for n in noise]
            ax.plot([n / 6.0 for n in noise], [v if v is not None else float("nan") for v in y], marker=m,
                    label="%s, %s" % (s, label))
    ax.axhline(0.95, color="k", ls=":", lw=1)
    ax.set_xscale("log")
    ax.set_xticks([n / 6.0 for n in noise])
    ax.set_xticklabels(["%gx" % (n / 6.0) for n in noise])
    ax.set_xlabel("sensor noise (x the default 6 counts, 1 sigma)")
    ax.set_ylabel("sliding time with\ntrue force in 5 +- 1 N")
    ax.set_ylim(0, 1.05)
    ax.legend(fontsize=8)
    for ax, s in zip(axes[1:], scenes):
        for label, out in sets:
            try:
                t, ft, fm = trace(out, s, trace_noise)
            except OSError:
                continue
            ax.plot(t, ft, lw=1, label="true force, %s" % label)
            ax.plot(t, fm, lw=0.5, alpha=0.5, label="measured force, %s" % label)
        ax.axhspan(4.0, 6.0, color="g", alpha=0.08)
        ax.set_title("%s, noise %d counts (%gx)" % (s, trace_noise, trace_noise / 6.0), fontsize=9)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("force (N)")
        ax.set_ylim(0, 8)
        ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/bin/tactile_sim")
    ap.add_argument("--out", required=True)
    ap.add_argument("--label", default="this build")
    ap.add_argument("--compare", help="a second run directory with the same layout")
    ap.add_argument("--compare-label", default="compare")
    ap.add_argument("--no-run", action="store_true", help="only tabulate and plot existing runs")
    ap.add_argument("--png", help="plot file (default OUT/noise_sweep.png)")
    ap.add_argument("--trace-noise", type=int, default=30)
    a = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    if not a.no_run:
        run_all(a.bin, a.out, SCENES, NOISE, root)
    sets = [(a.label, a.out)] + ([(a.compare_label, a.compare)] if a.compare else [])
    print(table(sets, SCENES, NOISE))
    plot(sets, SCENES, NOISE, a.png or os.path.join(a.out, "noise_sweep.png"), a.trace_noise)
    return 0


if __name__ == "__main__":
    sys.exit(main())
