#!/usr/bin/python3
"""Servo rate independence of the experiments.

usage: sweep_rates.py [--sim build/bin/tactile_sim] [--out out/rates] [--jobs N]
                      [--seeds N] [--set KEY.PATH=VALUE ...]

Runs every scene in params/scenes/ at servo rates of 50, 100, 200, 500 and 1000 Hz
(`tactile_sim run SCENE --servo-rate HZ --no-plots`) and compares each scene's
key metrics (scripts/sweeps/sweep_tradeoff.py SCENES; the others: force_true_mean_n)
with the 100 Hz run (the paper's Table 2). The servo's gains, limits and
delays are per second, so every metric should stay within 10 %. Each value
is the mean over --seeds runs (seeds 1..N: the noise realisation; with pad
friction one run's alignment time moves by +-10 % with the seed alone), and
the table gives the seeds' spread at 100 Hz beside it. --set passes scene
overrides to every run (e.g. effects.wts_transfer_delay_s=0.0157).
Writes rates.csv, rates.md and rates.png into the output folder; exits 1 when
a key metric leaves the 10 % band or a run does not end `ok`.
"""
import json
import os
import subprocess
import sys


ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts", "sweeps"))
import tactile_sweeps as ts  # noqa: E402
from tactile_sweeps.plot import plt  # noqa: E402
from sweep_tradeoff import SCENES  # noqa: E402

RATES = [50, 100, 200, 500, 1000]
REF = 100
BAND = 0.10
DEFAULT_KEYS = ["force_true_mean_n"]


def run(sim, scene_file, hz, seed, sets, out):
    scene = os.path.splitext(os.path.basename(scene_file))[0]
    d = os.path.join(out, "runs", f"{scene}_{hz}_{seed}")
    cmd = [sim, "run", scene_file, "--servo-rate", str(hz), "--seed", str(seed), "--no-plots", "--out", d]
    for kv in sets:
        cmd += ["--set", kv]
    p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        s = json.load(open(os.path.join(d, "summary.json")))
    except (OSError, ValueError):
        s = {"status": "no summary: " + p.stderr.strip()[-200:]}
    s["exit_code_process"] = p.returncode
    return s


def rel(v, ref):
    if v is None or ref is None:
        return None
    return (v - ref) / max(abs(ref), 1e-12)


def main():
    ap = ts.cli.parser(__doc__, "rates", jobs=2, seeds=5)
    ap.add_argument("--set", action="append", default=[], dest="sets")
    a = ts.cli.finish(ap.parse_args())
    names = ts.shipped_scenes()
    scenes = [ts.scene_path(n) for n in names]
    seeds = list(range(1, a.seeds + 1))
    one = {}
    grid = [(f, n, hz, sd) for f, n in zip(scenes, names) for hz in RATES for sd in seeds]
    for k, total, r in ts.pmap(lambda j: (j[1:], run(a.sim, j[0], j[2], j[3], a.sets, a.out)), grid, a.jobs):
        one[r[0]] = r[1]
        sys.stderr.write(f"\r{k}/{total} runs")
    sys.stderr.write("\n")
    # Per (scene, rate): each metric's mean over the seeds (None when a seed
    # lacks it), the worst status, the summed contact losses.
    res, spread = {}, {}
    for n in names:
        for hz in RATES:
            runs = [one[(n, hz, sd)] for sd in seeds]
            agg = {"status": next((r.get("status") for r in runs if r.get("status") != "ok"), "ok"),
                   "contact_lost_count": sum(r.get("contact_lost_count") or 0 for r in runs)}
            for k in SCENES.get(n, DEFAULT_KEYS):
                vals = [r.get(k) for r in runs]
                agg[k] = None if any(v is None for v in vals) else sum(vals) / len(vals)
                if hz == REF and agg[k] is not None:
                    spread[(n, k)] = (min(vals), max(vals))
            res[(n, hz)] = agg

    rows, bad = [], []
    for n in names:
        ref = res[(n, REF)]
        for k in SCENES.get(n, DEFAULT_KEYS):
            for hz in RATES:
                s = res[(n, hz)]
                v, r = s.get(k), rel(s.get(k), ref.get(k))
                ok = r is not None and abs(r) <= BAND and s.get("status") == "ok"
                if not ok:
                    bad.append((n, k, hz, v, r, s.get("status")))
                rows.append((n, k, hz, v, r, s.get("status"), s.get("contact_lost_count")))

    with open(os.path.join(a.out, "rates.csv"), "w") as f:
        f.write("scene,metric,servo_hz,value,rel_to_100hz,status,contact_lost_count\n")
        for n, k, hz, v, r, st, cl in rows:
            f.write(f"{n},{k},{hz},{'' if v is None else v},{'' if r is None else f'{r:.5f}'},{st},{cl}\n")

    md = ["| scene | key metric | " + " | ".join(f"{hz} Hz" for hz in RATES) + " | max dev. | seeds at 100 Hz |",
          "| --- | --- | " + " | ".join("---" for _ in RATES) + " | --- | --- |"]
    for n in names:
        for k in SCENES.get(n, DEFAULT_KEYS):
            cells, dev = [], 0.0
            for hz in RATES:
                s = res[(n, hz)]
                v, r = s.get(k), rel(s.get(k), res[(n, REF)].get(k))
                if v is None:
                    cells.append("n/a")
                    dev = float("inf")
                    continue
                dev = max(dev, abs(r) if r is not None else float("inf"))
                mark = "" if s.get("status") == "ok" else f" ({s.get('status')})"
                cells.append(f"{v:.4g}" + ("" if hz == REF else f" ({r * 100:+.1f} %)") + mark)
            lo, hi = spread.get((n, k), (None, None))
            sp = "n/a" if lo is None else f"{lo:.4g} .. {hi:.4g}"
            md.append(f"| {n} | {k} | " + " | ".join(cells) + f" | {dev * 100:.1f} % | {sp} |")
    md.append("")
    md.append(f"Each value: the mean over seeds {seeds[0]}..{seeds[-1]}" +
              (f", with {' '.join(a.sets)}" if a.sets else "") + ".")
    md.append(f"Servo rates {', '.join(map(str, RATES))} Hz, everything else as in the scene "
              f"(physics 1 kHz, WTS 140 Hz, features 200 Hz); deviation relative to {REF} Hz; band ±{BAND * 100:.0f} %.")
    md.append(f"Contact losses (summed over the {len(seeds)} seeds): " + "; ".join(
        f"{n}: " + "/".join(str(res[(n, hz)].get("contact_lost_count")) for hz in RATES) for n in names) +
        f" (at {'/'.join(map(str, RATES))} Hz).")
    if bad:
        md.append("")
        md.append("Outside the band: " + "; ".join(f"{n} {k} at {hz} Hz ({st})" for n, k, hz, _, _, st in bad))
    open(os.path.join(a.out, "rates.md"), "w").write("\n".join(md) + "\n")

    keys = [(n, k) for n in names for k in SCENES.get(n, DEFAULT_KEYS)]
    fig, ax = plt.subplots(figsize=(11, 5))
    for n, k in keys:
        ys = [rel(res[(n, hz)].get(k), res[(n, REF)].get(k)) for hz in RATES]
        ax.plot(RATES, [100 * y if y is not None else float("nan") for y in ys], marker="o", label=f"{n}: {k}")
    ax.axhspan(-100 * BAND, 100 * BAND, color="0.9", zorder=0, label="±10 % band")
    ax.set_xscale("log")
    ax.set_xticks(RATES)
    ax.set_xticklabels([str(r) for r in RATES])
    ax.set_xlabel("servo rate (Hz)")
    ax.set_ylabel(f"key metric relative to {REF} Hz (%)")
    ax.set_title("Servo rate independence (gains, limits and delays per second)")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_ylim(-15, 15)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "rates.png"), dpi=110)
    print("\n".join(md))
    print(f"wrote {a.out}/rates.csv, rates.md, rates.png")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
