#!/usr/bin/python3
"""The simulated sensor's effects on every shipped experiment.

usage: sweep_sensor_effects.py [--sim build/bin/tactile_sim] [--out out/sensor_effects] [--jobs N]
                               [--seeds 1,2,3,4,5,6]

Runs each scene with all effects off, each sensor effect alone at its realistic
level (sim/lwr/README.md, "Sensor effects") and all of them together
(`tactile_sim run SCENE --set effects.KEY=VALUE --no-plots`), and reports per
scene its key metrics (simsweep.key_metrics), their change against off, the
run's real-time factor against off (noisy on a shared host: the cost is
measured by bench_sim's BM_SensorEffects / BM_SimSensor), and the scene's
criteria (metrics.criteria: summary.json criteria_passed / criteria_failed).
scripts/sweep_effects.py runs the sensor's and the world's effects together;
this one adds the sensor's effects together (`all`) and a seed spread.
With --seeds, the seeded effects (gain spread, calibration error, and off and
crosstalk for reference) are also run on those seeds: the range of the true
force mean and RMS error per scene (the per-taxel draws depend on the seed).
Writes sensor_effects.md and sensor_effects.json into the output folder.
"""
import argparse
import concurrent.futures
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import simsweep  # noqa: E402

ROOT = simsweep.ROOT

# effect label -> --set overrides (realistic levels, sim/lwr/README.md).
EFFECTS = {
    "off": [],
    "wts_transfer_delay_s=0.0157": ["effects.wts_transfer_delay_s=0.0157"],
    "gain_spread=0.1": ["effects.gain_spread=0.1"],
    "dead_taxels=2": ["effects.dead_taxels=2"],
    "calibration_error=0.05": ["effects.calibration_error=0.05"],
    "crosstalk=0.05": ["effects.crosstalk=0.05"],
    "creep=0.1/2s": ["effects.creep={fraction: 0.1, tau_s: 2.0}"],
    "hysteresis=0.05": ["effects.hysteresis=0.05"],
    "device_noise=true": ["effects.device_noise=true"],
}
ALL = [o for v in EFFECTS.values() for o in v]
EFFECTS["all (device noise)"] = ALL
EFFECTS["all but device noise"] = [o for o in ALL if "device_noise" not in o]


def nan(v):
    return v is None or (isinstance(v, float) and math.isnan(v))


def criteria(s):
    """The scene's own criteria (metrics.criteria, summary.json criteria_passed / criteria_failed)."""
    if s.get("status") == "no_summary":
        return ["no summary: " + s.get("error", "")[-200:]]
    return [] if s.get("criteria_passed") and s.get("returncode") == 0 else (s.get("criteria_failed") or
                                                                              ["status " + str(s.get("status"))])


def run(sim, scene, label, sets, out):
    d = os.path.join(out, "runs", scene + "_" + "".join(c if c.isalnum() else "_" for c in label))
    args = []
    for s in sets:
        args += ["--set", s]
    return simsweep.run(scene, d, args, sim=sim)


def fmt(v):
    if nan(v):
        return "null"
    return f"{v:.4g}"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sim", default=simsweep.SIM)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "sensor_effects"))
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--seeds", default="", help="comma-separated seeds for the seed spread of the seeded effects")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    scenes = {sc: simsweep.key_metrics(sc) for sc in simsweep.shipped_scenes()}
    jobs = [(sc, lb) for sc in scenes for lb in EFFECTS]
    res = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
        futs = {ex.submit(run, a.sim, sc, lb, EFFECTS[lb], a.out): (sc, lb) for sc, lb in jobs}
        for i, f in enumerate(concurrent.futures.as_completed(futs)):
            res[futs[f]] = f.result()
            sys.stderr.write(f"\r{i + 1}/{len(jobs)} runs")
    sys.stderr.write("\n")
    md = []
    for sc, keys in scenes.items():
        off = res[(sc, "off")]
        md.append(f"### {sc}\n")
        md.append("| effect | " + " | ".join(keys) + " | rtf vs off | status | criteria |")
        md.append("| --- | " + " | ".join("---" for _ in keys) + " | --- | --- | --- |")
        for lb in EFFECTS:
            s = res[(sc, lb)]
            cells = []
            for k in keys:
                v, r = s.get(k), off.get(k)
                if lb == "off" or nan(v) or nan(r):
                    cells.append(fmt(v))
                else:
                    cells.append(f"{fmt(v)} ({v - r:+.3g})")
            rtf = s.get("real_time_factor")
            ratio = rtf / off["real_time_factor"] if rtf and off.get("real_time_factor") else float("nan")
            failed = criteria(s)
            md.append(f"| {lb} | " + " | ".join(cells) + f" | {ratio:.2f} | {s.get('status')} | " +
                      ("pass" if not failed else "FAIL: " + ", ".join(failed)) + " |")
        md.append("")
    if a.seeds:
        seeds = [int(x) for x in a.seeds.split(",")]
        seeded = ["off", "gain_spread=0.1", "calibration_error=0.05", "crosstalk=0.05"]
        md.append("### seed spread (seeds " + a.seeds + ")\n")
        md.append("| scene | effect | force_true_mean_n min..max (mean) | force_true_rms_error_n min..max | "
                  "criteria failed on |")
        md.append("| --- | --- | --- | --- | --- |")
        for sc in scenes:
            for lb in seeded:
                runs = [run(a.sim, sc, f"{lb}_seed{k}", EFFECTS[lb] + [f"seed={k}"], a.out) for k in seeds]
                m = [r.get("force_true_mean_n") for r in runs]
                e = [r.get("force_true_rms_error_n") for r in runs]
                bad = [str(k) for k, r in zip(seeds, runs) if criteria(r)]
                md.append(f"| {sc} | {lb} | {min(m):.2f}..{max(m):.2f} ({sum(m) / len(m):.2f}) | "
                          f"{min(e):.2f}..{max(e):.2f} | {', '.join(bad) or '-'} |")
        md.append("")
    text = "\n".join(md) + "\n"
    open(os.path.join(a.out, "sensor_effects.md"), "w").write(text)
    json.dump({f"{sc}|{lb}": s for (sc, lb), s in res.items()}, open(os.path.join(a.out, "sensor_effects.json"), "w"),
              indent=1)
    print(text)


if __name__ == "__main__":
    main()
