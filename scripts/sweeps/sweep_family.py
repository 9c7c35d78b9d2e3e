#!/usr/bin/python3
"""The family of bars (params/scenes/curved, scripts/tools/make_curved_bars.py):
per bar, fixed slide gains against the speed law (a Pareto front per bar).

usage: sweep_family.py [--out out/family] [--jobs N] [--seeds N] [--pool-seeds M] [--sim PATH]

Every bar is run with bent_bar_speed_law.yaml (the end-cap program with the
stiff force loop, K_P,z 8, K_I,z 16, the slope fed forward along z_s and the
force estimate's correction within 0.02 s and up to the whole set point;
scripts/sweeps/sweep_speed.py):
  fixed gain           the law off, the slide gain kp_per_s.x swept over
                       GAINS (25 mm x kp commanded; translation limits 0.12 m/s,
                       the law's ceiling)
  speed law            the law on, as shipped (error budget 0.5 N)
  speed law, careful   bent_bar_speed_law_careful.yaml (budget 0.35 N, the
                       speed rising at 0.005 m/s^2, no slope feed-forward,
                       the force estimate's 0.08 s)
and with bent_bar_to_end_cap.yaml as shipped (the paper's slide gain), for
reference. The careful law is also run with its speed's rise (accel_mps2)
swept over RISES: a change of the slide speed is itself a disturbance of the
force loop on a sloped or curved bar, and the rise trades the speed on the
gentle bars against the force on the waves (rise.csv, rise.md). A run meets the targets when it ends at the bar's end (status ok,
ended by `done`, the last true contact within 10 mm of the bar's end vertex)
with the true force's RMS error <= 0.5 N, >= 95 % of the slide within
5 +- 0.5 N and no contact loss. Per bar: the fastest fixed gain that meets
them (on every seed), and the law's speed (the mean over the seeds that
measured one) and whether it meets them.
Writes family.csv (per run), family_bars.csv and family.md (per bar), family.png and
rise.csv and rise.md (per rise) into --out.

On a wave, a 3-seed mean speed moves by 10-30 % with changes that leave the
loop as it was (the law with every input neutralised against the fixed gain it
caps), and the fastest of 13 gains is the luckiest of them. --pool-seeds M
(> --seeds) also runs seeds --seeds+1..M of the fixed gains and the speed law
as shipped, and compares them over all M seeds (pooled.csv, pooled.md): per
bar the fastest fixed gain that meets the targets on every seed, the law's
mean speed and its spread over the seeds, and whether the law meets the
targets on every seed and is at least as fast.
"""
import statistics
import glob
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import tactile_sweeps as ts  # noqa: E402
from tactile_sweeps.plot import plt, save  # noqa: E402

import sweep_speed  # noqa: E402  (its program writer and end distance)

GAINS = [0.4, 0.5, 0.6, 0.7, 0.8, 1.0, 1.2, 1.6, 2.0, 2.4, 3.2, 4.0, 4.8]  # 1/s: 10 .. 120 mm/s commanded at a 25 mm CoP_x error
FIXED, SHIPPED = "fixed gain", "end-cap program (paper's gain)"
# label, program, the prefix of its columns in family_bars.csv
LAWS = [("speed law", "bent_bar_speed_law", "law"), ("speed law, careful", "bent_bar_speed_law_careful", "careful")]
END_MM = sweep_speed.END_MM
RISE = "careful law, rise"
RISES = [0.002, 0.005, 0.01, 0.02, 0.05]  # m/s^2: the careful law's accel_mps2 (0.005 as shipped)
LAW_DURATION_S = 90.0  # s: a law sliding at its v_min (5 mm/s) the whole bar still reaches its end


def bars():
    """The family's scene names, relative to params/scenes."""
    d = os.path.join(ts.scenes.SCENE_DIR, "curved")
    return sorted("curved/" + os.path.basename(p)[:-5] for p in glob.glob(os.path.join(d, "*.yaml")))


def one(job):
    bar, label, program, kp, seed, out = job
    d = os.path.join(out, "runs", bar.split("/")[-1], f"{label.replace(' ', '_').replace(',', '')}_{kp:g}_{seed}")
    duration = 3.0 + 1.5 * 0.36 / (0.025 * kp) if label == FIXED else LAW_DURATION_S
    s = ts.run.run(bar, d, ["--seed", str(seed), "--program", program, "--set", f"duration={duration:.1f}"])
    s["end_distance_m"] = sweep_speed.end_distance(d, bar)
    return bar, label, kp, seed, s


def rise_variant(accel, out):
    """bent_bar_speed_law_careful.yaml with speed_law.accel_mps2 = accel."""
    p = sweep_speed.program_yaml.load(os.path.join(sweep_speed.PROGRAMS, "bent_bar_speed_law_careful.yaml"))
    p["speed_law"]["accel_mps2"] = accel
    return sweep_speed.write_program(p, f"bent_bar_speed_law_careful_rise{accel:g}",
                                     f"bent_bar_speed_law_careful.yaml with speed_law.accel_mps2 = {accel}", out)


def end_note(r):
    """How a run ended, beside its status: not by the end rule, or by it short of the bar's end (a crest
    read as the end cap)."""
    if not r["ended_done"]:
        return " (not at the end)"
    return " (done before the end)" if not r["end_mm"] <= END_MM else ""


def meets(r):
    return (r["status"] == "ok" and r["ended_done"] and r["end_mm"] <= END_MM and r["rms_n"] <= 0.5
            and r["in_band"] >= 0.95 and r["losses"] == 0)


def record(bar, label, kp, seed, s):
    """One run's row of family.csv."""
    phases = [p["name"] for p in s.get("phases", [])]
    r = {"bar": bar.split("/")[-1], "controller": label, "kp_x": kp if label == FIXED else float("nan"),
         "accel_mps2": kp if label == RISE else float("nan"),
         "seed": seed, "status": s.get("status"), "ended_done": "done" in phases,
         "speed_mm_s": 1000.0 * sweep_speed.num(s.get("slide_speed_mps")),
         "rms_n": sweep_speed.num(s.get("force_true_rms_error_n")),
         "max_n": sweep_speed.num(s.get("force_true_max_n")),
         "in_band": sweep_speed.num(s.get("force_true_in_band_fraction")),
         "losses": s.get("contact_lost_count", -1), "end_mm": 1000.0 * sweep_speed.num(s.get("end_distance_m"))}
    r["met"] = "yes" if meets(r) else "no"
    return r


def setting(rows, bar, label, kp=None, accel=None):
    """One setting on one bar over its seeds in rows: it meets the targets when every seed does; its speed is the
    mean over the seeds that measured one; RMS and in band the worst seed's. None without a run."""
    g = [r for r in rows if r["bar"] == bar and r["controller"] == label
         and (kp is None or r["kp_x"] == kp) and (accel is None or r["accel_mps2"] == accel)]
    if not g:
        return None
    v = [r["speed_mm_s"] for r in g if r["speed_mm_s"] == r["speed_mm_s"]]  # seeds that measured a speed
    return {"met": all(r["met"] == "yes" for r in g), "speed": sum(v) / len(v) if v else float("nan"),
            "speeds": v, "rms": max(r["rms_n"] for r in g), "in_band": min(r["in_band"] for r in g),
            "status": ", ".join(sorted({r["status"] + end_note(r) for r in g}))}


def fastest_fixed(rows, bar):
    """(kp, setting) of the fastest fixed gain that meets the targets on every seed of the bar, or None."""
    passing = [(kp, st) for kp, st in ((kp, setting(rows, bar, FIXED, kp)) for kp in GAINS) if st and st["met"]]
    return max(passing, key=lambda p: p[1]["speed"]) if passing else None


def pooled(rows, n_seeds, out):
    """The fixed gains against the speed law over seeds 1..n_seeds (rows: every run of them)."""
    law_label = LAWS[0][0]
    res = []
    for bar in sorted({r["bar"] for r in rows}):
        best = fastest_fixed(rows, bar)
        fixed_v = best[1]["speed"] if best else float("nan")
        law = setting(rows, bar, law_label)
        v = law["speeds"]
        res.append({"bar": bar, "fixed_kp_x": best[0] if best else float("nan"), "fixed_speed_mm_s": fixed_v,
                    "law_speed_mm_s": law["speed"],
                    "law_speed_sd_mm_s": statistics.pstdev(v) if len(v) > 1 else float("nan"),
                    "law_met": "yes" if law["met"] else "no", "ratio": law["speed"] / fixed_v,
                    "law_not_slower": "yes" if law["met"] and best and law["speed"] >= fixed_v else "no"})
    ts.write_csv(os.path.join(out, "pooled.csv"), res)
    with_fixed = [r for r in res if r["fixed_speed_mm_s"] == r["fixed_speed_mm_s"]]
    with open(os.path.join(out, "pooled.md"), "w") as f:
        f.write(f"Seeds 1-{n_seeds}: per bar, the fastest fixed gain that meets the targets on every seed, against "
                "the speed law as shipped (its mean speed over the seeds and their spread, one standard deviation).\n\n"
                "| bar | fastest fixed gain within the targets on every seed: kp_x, speed | speed law: speed (spread) "
                "| law within the targets on every seed | law / fixed | not slower |\n|---|---|---|---|---|---|\n")
        for r in with_fixed:
            f.write(f"| {r['bar']} | {r['fixed_kp_x']:g}: {r['fixed_speed_mm_s']:.1f} mm/s | "
                    f"{r['law_speed_mm_s']:.1f} mm/s ({r['law_speed_sd_mm_s']:.1f}) | {r['law_met']} | "
                    f"{r['ratio']:.2f} | {r['law_not_slower']} |\n")
        f.write(f"\nSome fixed gain meets the targets on every seed on {len(with_fixed)} of {len(res)} bars; the law "
                f"meets them on every seed on {sum(r['law_met'] == 'yes' for r in with_fixed)} of those and is "
                f"not slower on {sum(r['law_not_slower'] == 'yes' for r in with_fixed)}.\n")
    return res


def main():
    ap = ts.cli.parser(__doc__, "family")
    ap.add_argument("--pool-seeds", type=int, default=0,
                    help="also compare the fixed gains and the speed law over seeds 1..M (pooled.md)")
    a = ts.cli.finish(ap.parse_args())
    programs = {kp: sweep_speed.variant("bent_bar_speed_law", kp, a.out) for kp in GAINS}
    rises = {r: rise_variant(r, a.out) for r in RISES}
    shipped = os.path.join(sweep_speed.PROGRAMS, "bent_bar_to_end_cap.yaml")
    jobs = []
    for bar in bars():
        for seed in range(1, a.seeds + 1):
            jobs += [(bar, FIXED, programs[kp], kp, seed, a.out) for kp in GAINS]
            jobs += [(bar, label, os.path.join(sweep_speed.PROGRAMS, prog + ".yaml"), 0.0, seed, a.out)
                     for label, prog, _ in LAWS]
            jobs.append((bar, SHIPPED, shipped, 0.0, seed, a.out))
            jobs += [(bar, RISE, rises[r], r, seed, a.out) for r in RISES]
    rows, failed = [], False
    for k, n, (bar, label, kp, seed, s) in ts.pmap(one, jobs, a.jobs):
        if s.get("status") == "no_summary":
            failed = True
            print(f"{bar} {label} {kp:g}: no summary: {s.get('error', '')[-300:]}", file=sys.stderr)
        r = record(bar, label, kp, seed, s)
        rows.append(r)
        print(f"[{k}/{n}] {r['bar']} {label} {kp:g} seed {seed}: {r['status']}, {r['speed_mm_s']:.1f} mm/s, "
              f"RMS {r['rms_n']:.2f} N, in band {r['in_band']:.3f}, met {r['met']}", flush=True)
    order = [FIXED] + [label for label, _, _ in LAWS] + [SHIPPED, RISE]
    rows.sort(key=lambda r: (r["bar"], order.index(r["controller"]), r["kp_x"] if r["kp_x"] == r["kp_x"] else 0,
                             r["accel_mps2"] if r["accel_mps2"] == r["accel_mps2"] else 0, r["seed"]))
    ts.write_csv(os.path.join(a.out, "family.csv"), rows)

    if a.pool_seeds > a.seeds:  # the fixed gains and the law over more seeds (pooled.md)
        law_label, law_prog, _ = LAWS[0]
        more = []
        for bar in bars():
            for seed in range(a.seeds + 1, a.pool_seeds + 1):
                more += [(bar, FIXED, programs[kp], kp, seed, a.out) for kp in GAINS]
                more.append((bar, law_label, os.path.join(sweep_speed.PROGRAMS, law_prog + ".yaml"), 0.0, seed, a.out))
        pool = [r for r in rows if r["controller"] in (FIXED, law_label)]
        for k, n, (bar, label, kp, seed, s) in ts.pmap(one, more, a.jobs):
            if s.get("status") == "no_summary":
                failed = True
                print(f"{bar} {label} {kp:g} seed {seed}: no summary: {s.get('error', '')[-300:]}", file=sys.stderr)
            pool.append(record(bar, label, kp, seed, s))
            if k % 500 == 0 or k == n:
                print(f"[pooled {k}/{n}]", flush=True)
        pooled(pool, a.pool_seeds, a.out)

    # Per bar, over seeds 1..--seeds (setting(), fastest_fixed()).
    def at(bar, label, kp=None, accel=None):
        return setting(rows, bar, label, kp, accel)

    per_bar = []
    for bar in sorted({r["bar"] for r in rows}):
        best = fastest_fixed(rows, bar)
        b = {"bar": bar, "best_kp": best[0] if best else None, "best": best[1] if best else None,
             "shipped": at(bar, SHIPPED), "laws": []}
        for label, _, _ in LAWS:
            lw = at(bar, label)
            lw["not_slower"] = bool(lw["met"] and (best is None or lw["speed"] >= best[1]["speed"]))
            b["laws"].append(lw)
        per_bar.append(b)

    def cell(s):
        def g(v, fmt, unit, scale=1.0):
            return f"{v * scale:{fmt}}{unit}" if v == v else "n/a"
        return (f"{g(s['speed'], '.1f', ' mm/s')}, RMS {g(s['rms'], '.2f', ' N')}, {g(s['in_band'], '.0f', ' %', 100)}"
                + ("" if s["met"] else f" ({s['status']}; targets missed)"))

    def yes(v):
        return "yes" if v else "no"

    csv_rows = []
    for b in per_bar:
        r = {"bar": b["bar"], "fixed_kp_x": b["best_kp"] if b["best"] else float("nan"),
             "fixed_speed_mm_s": b["best"]["speed"] if b["best"] else float("nan")}
        for (_, _, k), lw in zip(LAWS, b["laws"]):
            r.update({f"{k}_speed_mm_s": lw["speed"], f"{k}_rms_n": lw["rms"], f"{k}_in_band": lw["in_band"],
                      f"{k}_met": yes(lw["met"]), f"{k}_status": lw["status"], f"{k}_not_slower": yes(lw["not_slower"])})
        r.update({"shipped_speed_mm_s": b["shipped"]["speed"], "shipped_met": yes(b["shipped"]["met"])})
        csv_rows.append(r)
    ts.write_csv(os.path.join(a.out, "family_bars.csv"), csv_rows)

    with open(os.path.join(a.out, "family.md"), "w") as f:
        f.write(f"The family of bars (params/scenes/curved), seeds 1..{a.seeds}. Targets: to the bar's end, true-force "
                "RMS error <= 0.5 N, >= 95 % within 5 +- 0.5 N, no contact loss (every seed). Speeds are the "
                "seeds' mean; RMS the worst seed, in band the worst seed. 'not slower': the law meets the "
                "targets and is at least as fast as the fastest fixed gain that does.\n\n")
        f.write("| bar | fastest fixed gain within the targets | "
                + " | ".join(f"{label} | not slower" for label, _, _ in LAWS)
                + " | end-cap program (paper's gain) |\n|" + "---|" * (3 + 2 * len(LAWS)) + "\n")
        for b in per_bar:
            best = f"kp {b['best_kp']:g}: {cell(b['best'])}" if b["best"] else "none"
            f.write(f"| {b['bar']} | {best} | "
                    + " | ".join(f"{cell(lw)} | {yes(lw['not_slower'])}" for lw in b["laws"])
                    + f" | {cell(b['shipped'])} |\n")
        n_fix = sum(1 for b in per_bar if b["best"])
        f.write(f"\nSome fixed gain meets the targets on {n_fix} of {len(per_bar)} bars.")
        for i, (label, _, _) in enumerate(LAWS):
            n_law = sum(1 for b in per_bar if b["laws"][i]["met"])
            n_ok = sum(1 for b in per_bar if b["laws"][i]["not_slower"])
            f.write(f" The {label} meets them on {n_law}, and is not slower than the fastest fixed gain that "
                    f"does on {n_ok}.")
        f.write("\n")
        # One program for every bar it meets the targets on: the law against the
        # fastest single fixed gain that meets them on the same bars.
        for i, (label, _, _) in enumerate(LAWS):
            met = [b for b in per_bar if b["laws"][i]["met"]]
            if not met:
                continue
            single = [kp for kp in GAINS if all(at(b["bar"], FIXED, kp)["met"] for b in met)]
            law_v = sum(b["laws"][i]["speed"] for b in met) / len(met)
            f.write(f"\nThe {label} on the {len(met)} bars it meets the targets on: {law_v:.1f} mm/s mean. ")
            if single:
                kp = max(single)
                fix_v = sum(at(b["bar"], FIXED, kp)["speed"] for b in met) / len(met)
                f.write(f"The fastest single fixed gain that meets them on the same bars, kp {kp:g}: {fix_v:.1f} mm/s "
                        "mean.\n")
            else:
                f.write("No single fixed gain meets them on all of these bars.\n")

    # The careful law's rise: bars within the targets and its speed there, per rise.
    rise_rows = []
    for acc in RISES:
        per = [(b, at(b["bar"], RISE, accel=acc)) for b in per_bar]
        met = [(b, st) for b, st in per if st["met"]]
        fixed_bars = [b for b in per_bar if b["best"]]
        rise_rows.append({
            "accel_mps2": acc, "bars": len(per), "met": len(met),
            "met_where_a_fixed_gain_does": sum(1 for b, st in met if b["best"]), "fixed_met": len(fixed_bars),
            "speed_mm_s": ts.mean([st["speed"] for _, st in met]),
            "gentle_speed_mm_s": ts.mean([st["speed"] for b, st in met if not b["bar"].startswith("wavy")]),
            "not_slower": sum(1 for b, st in met if b["best"] is None or st["speed"] >= b["best"]["speed"])})
    ts.write_csv(os.path.join(a.out, "rise.csv"), rise_rows)
    with open(os.path.join(a.out, "rise.md"), "w") as f:
        f.write("| rise (m/s^2) | bars within the targets | of the bars some fixed gain passes | mean speed there "
                "(mm/s) | on the bars that are not waves (mm/s) | not slower than the fastest fixed gain |\n"
                "|---|---|---|---|---|---|\n")
        for r in rise_rows:
            f.write(f"| {r['accel_mps2']:g} | {r['met']} of {r['bars']} | {r['met_where_a_fixed_gain_does']} of "
                    f"{r['fixed_met']} | {r['speed_mm_s']:.1f} | {r['gentle_speed_mm_s']:.1f} | {r['not_slower']} |\n")

    cols = 5
    nrow = math.ceil(len(per_bar) / cols)
    fig, ax = plt.subplots(nrow, cols, figsize=(3.2 * cols, 2.6 * nrow), squeeze=False)
    for i, b in enumerate(per_bar):
        x = ax[i // cols][i % cols]
        fr = [at(b["bar"], FIXED, kp) for kp in GAINS]
        x.plot([s["speed"] for s in fr], [s["rms"] for s in fr], "-", color="tab:blue", lw=1)
        for s in fr:
            x.plot(s["speed"], s["rms"], "o" if s["met"] else "x", color="tab:blue", ms=5)
        for s, c in ((b["laws"][0], "k"), (b["laws"][1], "tab:red"), (b["shipped"], "tab:green")):
            x.plot(s["speed"], s["rms"], "*" if s["met"] else "X", color=c, ms=11)
        x.axhline(0.5, color="k", ls="--", lw=0.8)
        x.set_title(b["bar"], fontsize=8)
        x.tick_params(labelsize=7)
        x.grid(alpha=0.3)
    for j in range(len(per_bar), nrow * cols):
        ax[j // cols][j % cols].axis("off")
    fig.supxlabel("slide speed (mm/s)")
    fig.supylabel("true-force RMS error (N, worst seed)")
    fig.suptitle("The family of bars: fixed gains (blue line; o within the targets, x not), the speed law (black), "
                 "the careful speed law (red), the end-cap program (green); star: within the targets", fontsize=10)
    save(fig, os.path.join(a.out, "family.png"), dpi=90)
    print(open(os.path.join(a.out, "family.md")).read())
    print(open(os.path.join(a.out, "rise.md")).read())
    if a.pool_seeds > a.seeds:
        print(open(os.path.join(a.out, "pooled.md")).read())
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
