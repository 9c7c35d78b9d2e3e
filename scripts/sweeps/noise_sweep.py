#!/usr/bin/env python3
"""Sensor-noise sweep: the true force within the scene's band against the simulated noise.

Runs `tactile_sim run SCENE --set sensor.noise_counts=N --no-plots` for each
scene and noise level into OUT/<scene>_n<N>/, prints a markdown table of the
summaries and plots the in-band fraction against the noise (and, with
--compare, a second set of runs laid out the same way, e.g. made by an older
build) plus the true force over time at --trace-noise. The band is each
scene's own (metrics.force_band_n: the bent bar +-1 N, the edge exploration
+-0.5 N), as summary.json scores it.

  /usr/bin/python3 scripts/sweeps/noise_sweep.py --sim build/bin/tactile_sim --out runs/noise \
      [--compare runs/noise_before --compare-label before] [--png runs/noise/noise_sweep.png]
"""
import csv
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import tactile_sweeps as ts  # noqa: E402

SCENES = ["bent_bar", "edge_exploration"]
NOISE = [6, 12, 30, 60]  # counts, 1 sigma: 1x, 2x, 5x, 10x the default


def run_all(out, scenes, noise, jobs):
    def one(job):
        s, n = job
        return ts.run.run(s, os.path.join(out, "%s_n%d" % (s, n)), ["--set", "sensor.noise_counts=%g" % n])
    for _ in ts.pmap(one, [(s, n) for s in scenes for n in noise], jobs):
        pass


def summary(out, s, n):
    p = os.path.join(out, "%s_n%d" % (s, n), "summary.json")
    if not os.path.exists(p):
        return None
    with open(p) as f:
        return json.load(f)


def fmt(v, digits=3):
    return ts.fmt(None if v is None else float(v), digits)


def table(sets, scenes, noise):
    lines = ["| scene | noise (counts, x default) | build | status | true force mean (N) | max (N) | RMS error (N) "
             "| in the scene's band | alignment (s) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for s in scenes:
        band = "%s (+-%g N)" % (s, ts.force_band(s))
        for n in noise:
            for label, out in sets:
                j = summary(out, s, n)
                if j is None:
                    continue
                lines.append("| %s | %d (%gx) | %s | %s | %s | %s | %s | %s | %s |" % (
                    band, n, n / 6.0, label, j["status"], fmt(j["force_true_mean_n"], 2),
                    fmt(j["force_true_max_n"], 2), fmt(j["force_true_rms_error_n"], 2),
                    fmt(j["force_true_in_band_fraction"]), fmt(j["alignment_time_s"], 2)))
    return "\n".join(lines)


def trace(out, s, n):
    p = os.path.join(out, "%s_n%d" % (s, n), "timeseries.csv")
    t, ft, fm, sd = [], [], [], 0.0
    with open(p) as f:
        for r in csv.DictReader(f):
            t.append(float(r["time"]))
            ft.append(float(r["force_true"]))
            fm.append(float(r["force"]))
            sd = max(sd, float(r["sd_force"]))
    return t, ft, fm, sd


def plot(sets, scenes, noise, png, trace_noise):
    from tactile_sweeps.plot import plt, save
    fig, axes = plt.subplots(1 + len(scenes), 1, figsize=(9, 3.2 * (1 + len(scenes))))
    ax = axes[0]
    for label, out in sets:
        for s, m in zip(scenes, ["o", "s"]):
            y = [(summary(out, s, n) or {}).get("force_true_in_band_fraction") for n in noise]
            ax.plot([n / 6.0 for n in noise], [v if v is not None else float("nan") for v in y], marker=m,
                    label="%s (+-%g N), %s" % (s, ts.force_band(s), label))
    ax.axhline(0.95, color="k", ls=":", lw=1)
    ax.set_xscale("log")
    ax.set_xticks([n / 6.0 for n in noise])
    ax.set_xticklabels(["%gx" % (n / 6.0) for n in noise])
    ax.set_xlabel("sensor noise (x the default 6 counts, 1 sigma)")
    ax.set_ylabel("sliding time with\ntrue force in the band")
    ax.set_ylim(0, 1.05)
    ax.legend(fontsize=8)
    for ax, s in zip(axes[1:], scenes):
        sd, band = None, ts.force_band(s)
        for label, out in sets:
            try:
                t, ft, fm, sd = trace(out, s, trace_noise)
            except OSError:
                continue
            ax.plot(t, ft, lw=1, label="true force, %s" % label)
            ax.plot(t, fm, lw=0.5, alpha=0.5, label="measured force, %s" % label)
        if sd is not None:
            ax.axhspan(sd - band, sd + band, color="g", alpha=0.08, label="set point +- %g N" % band)
        ax.set_title("%s, noise %d counts (%gx)" % (s, trace_noise, trace_noise / 6.0), fontsize=9)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("force (N)")
        ax.set_ylim(0, 8)
        ax.legend(fontsize=7, loc="lower right")
    save(fig, png, dpi=110)


def main():
    ap = ts.cli.parser(__doc__, "noise", seeds=None)
    ap.add_argument("--bin", dest="sim", help="the same as --sim")
    ap.add_argument("--label", default="this build")
    ap.add_argument("--compare", help="a second run directory with the same layout")
    ap.add_argument("--compare-label", default="compare")
    ap.add_argument("--no-run", action="store_true", help="only tabulate and plot existing runs")
    ap.add_argument("--png", help="plot file (default OUT/noise_sweep.png)")
    ap.add_argument("--trace-noise", type=int, default=30)
    a = ts.cli.finish(ap.parse_args())
    if not a.no_run:
        run_all(a.out, SCENES, NOISE, a.jobs)
    sets = [(a.label, a.out)] + ([(a.compare_label, a.compare)] if a.compare else [])
    print(table(sets, SCENES, NOISE))
    plot(sets, SCENES, NOISE, a.png or os.path.join(a.out, "noise_sweep.png"), a.trace_noise)
    return 0


if __name__ == "__main__":
    sys.exit(main())
