#!/usr/bin/python3
"""What each simulated effect costs and what it changes, on every shipped scene.

usage: sweep_effects.py [--sim build/bin/tactile_sim] [--out out/effects] [--reps 3]
                        [--scenes a,b] [--effects a,b] [--seed N]

For each scene of params/scenes/ it runs
  * `none`: the scene with every effect off (`--set effects={}`),
  * each effect of EFFECTS alone, at its realistic level, on top of `none`,
  * `all`: every effect at once (the realistic simulator),
  * `shipped`: the scene as shipped (the defaults chosen from this sweep),
and reports per run: the cost (wall time per simulated second over that of
`none`, the smallest of --reps runs, since the host is shared), each key
metric (tactile_sweeps.scenes.KEY_METRICS) with its relative change against `none`, the
scene's criteria (metrics.criteria: passed or what failed) and the status.
Writes effects.csv, effects.md and effects.png into the output folder.
"""
import argparse
import csv
import os
import sys


sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import tactile_sweeps as ts  # noqa: E402
from tactile_sweeps.plot import plt  # noqa: E402

# Effect -> (tactile_sim arguments at the realistic level, where the level comes from).
# Scene-specific arguments: "{tray}" is replaced by the tray's index (the row is
# skipped on scenes without a tray).
EFFECTS = {
    "wts_delay": (["--set", "effects.wts_transfer_delay_s=0.0157"],
                  "a 181-byte WTS frame at 115200 Bd 8N1 (core/wts protocol)"),
    "krc_fri": (["--set", "effects.krc_cycle_s=0.002", "--set", "effects.fri_delay_s=0.002"],
                "FRI at 500 Hz, one cycle of transport delay"),
    "friction": (["--set", "effects.friction_mu=0.5"], "rubber on metal, low end of the usual 0.5-1"),
    "creep": (["--set", "effects.creep={fraction: 0.1, tau_s: 2.0}"], "assumed (App. A shows creep, no numbers)"),
    "hysteresis": (["--set", "effects.hysteresis=0.05"], "assumed (App. A shows hysteresis, no numbers)"),
    "gain_spread": (["--set", "effects.gain_spread=0.1"], "per-taxel sensitivity spread"),
    "dead_taxels": (["--set", "effects.dead_taxels=2"], "two dead taxels"),
    "calibration_error": (["--set", "effects.calibration_error=0.05"], "5 % per taxel"),
    "crosstalk": (["--set", "effects.crosstalk=0.05"], "5 % to each neighbour"),
    "device_noise": (["--set", "effects.device_noise=true"], "63.8 counts: the bound the 0.2 N threshold implies"),
    "wrench_error": (["--set", "effects.wrench_error={bias_n: [1.0, -1.0, 2.0], noise_n: 0.5}"],
                     "the arm's estimated wrench: an offset and 0.5 N noise per axis (as the fused scenes)"),
    "tray_dynamic": (["--set", "objects.{tray}.fidelity=dynamics"], "tray integrated in time, arm quasi-static"),
    "arm_dynamic": (["--fidelity", "dynamics"], "arm (and every body) in dynamics"),
}
# Effects that are part of `all` (the realistic simulator): every one but the
# full-dynamics arm, which is a fidelity choice, not an effect of the hardware.
ALL = [e for e in EFFECTS if e != "arm_dynamic"]


def effect_args(scene, names):
    """tactile_sim arguments for a list of effects on a scene; None when one
    does not apply (a tray effect on a scene without a tray)."""
    tray = ts.tray_index(scene)
    args = ["--set", "effects={}"]
    for n in names:
        a = EFFECTS[n][0]
        if any("{tray}" in x for x in a):
            if tray is None:
                if len(names) == 1:
                    return None
                continue
            a = [x.replace("{tray}", str(tray)) for x in a]
        args += a
    return args


def run_best(scene, out, args, reps, sim):
    """The run's summary with the smallest wall time of `reps` runs (the
    metrics are deterministic for a seed; only the time varies)."""
    best = None
    for _ in range(reps):
        d = ts.run.run(scene, out, args, sim=sim)
        if best is None or d.get("wall_time_s", 1e9) < best.get("wall_time_s", 1e9):
            best = d
    return best


def wall_per_sim(d):
    return d.get("wall_time_s", float("nan")) / max(d.get("sim_time_s", 0.0) or 1e-9, 1e-9)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sim", default=ts.run.SIM)
    ap.add_argument("--out", default=os.path.join(ts.ROOT, "out", "effects"))
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--scenes", default="", help="comma-separated (default: every shipped scene)")
    ap.add_argument("--effects", default="", help="comma-separated (default: every effect)")
    ap.add_argument("--seed", type=int, default=None, help="the runs' seed (default: each scene's)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    scenes = a.scenes.split(",") if a.scenes else ts.shipped_scenes()
    effects = a.effects.split(",") if a.effects else list(EFFECTS)
    settings = [("none", [])] + [(e, [e]) for e in effects] + [("all", ALL), ("shipped", None)]
    rows = []
    total = len(scenes) * len(settings)
    k = 0
    for scene in scenes:
        ref = None
        for name, names in settings:
            k += 1
            sys.stderr.write(f"\r[{k}/{total}] {scene}: {name}{' ' * 20}")
            sys.stderr.flush()
            args = [] if names is None else effect_args(scene, names)
            if args is None:
                continue
            if a.seed is not None:
                args = args + ["--seed", str(a.seed)]
            d = run_best(scene, os.path.join(a.out, "runs", f"{scene}_{name}"), args, a.reps, a.sim)
            if name == "none":
                ref = d
            metrics = ts.key_metrics(scene)
            rows.append({
                "scene": scene, "setting": name, "status": d.get("status"), "returncode": d.get("returncode"),
                "cost": wall_per_sim(d) / wall_per_sim(ref) if ref else float("nan"),
                "rtf": d.get("real_time_factor", float("nan")),
                "metrics": {m: d.get(m) for m in metrics},
                "change": {m: ts.rel_err(d.get(m), ref.get(m)) for m in metrics} if ref else {},
                "criteria": "passed" if d.get("criteria_passed") else "; ".join(d.get("criteria_failed", [])) or
                            d.get("error", "failed"),
                "passed": bool(d.get("criteria_passed")) and d.get("returncode") == 0,
            })
    sys.stderr.write("\n")

    with open(os.path.join(a.out, "effects.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["scene", "setting", "cost_vs_none", "real_time_factor", "metric", "value", "rel_change_vs_none",
                    "criteria", "status", "exit_code"])
        for r in rows:
            for m, v in r["metrics"].items():
                w.writerow([r["scene"], r["setting"], f'{r["cost"]:.3f}', f'{r["rtf"]:.0f}', m, v,
                            f'{r["change"].get(m, float("nan")):.4f}', r["criteria"], r["status"], r["returncode"]])

    def fmt(v):
        return ts.fmt(v, spec=".4g", missing="n/a")

    md = ["# Effects: cost and outcome", "",
          "Cost = wall time per simulated second relative to `none` (smallest of "
          f"{a.reps} runs). Each metric: value (change vs `none`).", ""]
    for scene in scenes:
        metrics = ts.key_metrics(scene)
        md += [f"## {scene}", "", "| setting | cost | " + " | ".join(metrics) + " | criteria | status |",
               "| --- | --- | " + " | ".join("---" for _ in metrics) + " | --- | --- |"]
        for r in rows:
            if r["scene"] != scene:
                continue
            cells = [f'{fmt(r["metrics"][m])} ({r["change"].get(m, 0) * 100:+.0f} %)' if r["setting"] != "none"
                     else fmt(r["metrics"][m]) for m in metrics]
            md.append(f'| {r["setting"]} | {r["cost"]:.2f}x | ' + " | ".join(cells) +
                      f' | {r["criteria"]} | {r["status"]} |')
        md.append("")
    md.append("Levels: " + "; ".join(f"{e}: {' '.join(EFFECTS[e][0])} ({EFFECTS[e][1]})" for e in effects) + ".")
    open(os.path.join(a.out, "effects.md"), "w").write("\n".join(md) + "\n")
    print("\n".join(md))

    names = [s for s, _ in settings if s != "none"]
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(12, 8), sharex=True)
    width = 0.8 / max(len(scenes), 1)
    for i, scene in enumerate(scenes):
        by = {r["setting"]: r for r in rows if r["scene"] == scene}
        xs = [j + i * width for j, n in enumerate(names) if n in by]
        ax1.bar(xs, [by[n]["cost"] for n in names if n in by], width, label=scene)
        ax2.bar(xs, [max(max(by[n]["change"].values(), default=0), 1e-4) * 100 for n in names if n in by], width,
                label=scene, hatch=None)
        for x, n in zip(xs, [n for n in names if n in by]):
            if not by[n]["passed"]:
                ax2.text(x, 1.2e-2, "x", ha="center", color="red", fontsize=9, fontweight="bold")
    ax1.axhline(1.0, color="k", lw=0.8)
    ax1.set_ylabel("cost (wall time vs none)")
    ax1.set_title("Simulated effects: cost and change of the key metrics (red x: criteria failed)")
    ax1.legend(fontsize=8)
    ax1.grid(alpha=0.3, axis="y")
    ax2.set_yscale("log")
    ax2.set_ylabel("largest change of a key metric (%)")
    ax2.set_xticks([j + 0.4 - width / 2 for j in range(len(names))])
    ax2.set_xticklabels(names, rotation=30, ha="right")
    ax2.grid(alpha=0.3, axis="y", which="both")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "effects.png"), dpi=90)
    print(f"written: {a.out}/effects.csv, effects.md, effects.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
