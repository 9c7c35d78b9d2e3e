#!/usr/bin/python3
"""Table and histogram of scripts/realtime/rt_latency.sh's measurements.

    scripts/realtime/rt_latency_report.py OUT_DIR

Reads OUT_DIR/<cfg>_krc.txt (one line per KRC cycle: "LATENCY_US ON_TIME";
the latency from the measurement's departure to its reply's arrival, also for
a reply that came after the KRC's next tick and was ignored as stale,
ON_TIME 0; "nan 0" when no reply ever came) and OUT_DIR/<cfg>_cyclictest.hist
(cyclictest -h: "latency_us count" lines, "# Max Latencies:" comment) for cfg
in fifo_idle, fifo_load, other_idle, other_load. Prints a Markdown table: p50,
p99, p99.9 and max of the reply latency (a cycle never answered counts as an
infinite latency, "none" where a percentile falls on one), replies later than
the 1 ms period, replies that missed their tick (late or never: the KRC held
the last command for that cycle), replies that never came; cyclictest's p50,
p99, max beside. Cycles before the first reply (the deployment still
starting) are left out. Then the target check of the issue (SCHED_FIFO under
load: reply p99 within 2x cyclictest's p99, max within cyclictest's max +
1 ms); writes OUT_DIR/rt_latency.png (histograms, log scale).
"""
import math
import os
import sys

CFGS = ["fifo_idle", "fifo_load", "other_idle", "other_load"]
PERIOD_US = 1000.0


def pct(sorted_vals, p):
    if not sorted_vals:
        return float("nan")
    k = min(len(sorted_vals) - 1, max(0, int(math.ceil(p / 100.0 * len(sorted_vals))) - 1))
    return sorted_vals[k]


def read_krc(path):
    """(sorted latencies with inf for never answered, missed ticks, never answered)."""
    vals, missed, never = [], 0, 0
    started = False
    with open(path) as f:
        for line in f:
            a = line.split()
            if not a:
                continue
            v, on_time = float(a[0]), len(a) > 1 and a[1] == "1"
            if not started and math.isnan(v):
                continue  # before the first reply the deployment was still starting
            started = True
            if not on_time:
                missed += 1
            if math.isnan(v):
                never += 1
                v = float("inf")
            vals.append(v)
    return sorted(vals), missed, never


def read_hist(path):
    hist, mx = {}, float("nan")
    with open(path) as f:
        for line in f:
            if line.startswith("# Max Latencies:"):
                mx = float(line.split(":")[1].split()[0])
            elif line.strip() and not line.startswith("#"):
                a = line.split()
                if len(a) >= 2:
                    hist[int(a[0])] = hist.get(int(a[0]), 0) + int(a[1])
    return hist, mx


def hist_pct(hist, p):
    n = sum(hist.values())
    if n == 0:
        return float("nan")
    need, acc = p / 100.0 * n, 0
    for k in sorted(hist):
        acc += hist[k]
        if acc >= need:
            return float(k)
    return float(max(hist))


def main():
    out = sys.argv[1]
    rows, data, missed_pct = [], {}, {}
    for cfg in CFGS:
        kp, hp = os.path.join(out, cfg + "_krc.txt"), os.path.join(out, cfg + "_cyclictest.hist")
        if not os.path.exists(kp):
            continue
        vals, missed, never = read_krc(kp)
        hist, hmax = read_hist(hp) if os.path.exists(hp) else ({}, float("nan"))
        got = [v for v in vals if math.isfinite(v)]
        late = sum(1 for v in got if v > PERIOD_US)
        data[cfg] = (got, hist)
        missed_pct[cfg] = 100.0 * missed / max(1, len(vals))
        rows.append((cfg, len(vals), pct(vals, 50), pct(vals, 99), pct(vals, 99.9), vals[-1] if vals else float("nan"),
                     late, missed, hist_pct(hist, 50), hist_pct(hist, 99), hmax, never))

    def f(v):
        return "none" if v == float("inf") else "%.0f" % v

    print("| configuration | cycles | p50 (us) | p99 (us) | p99.9 (us) | max (us) | late > 1 ms | missed tick "
          "| never answered | cyclictest p50 (us) | cyclictest p99 (us) | cyclictest max (us) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print("| %s | %d | %s | %s | %s | %s | %d | %d (%.2f %%) | %d | %s | %s | %s |"
              % (r[0], r[1], f(r[2]), f(r[3]), f(r[4]), f(r[5]), r[6], r[7], 100.0 * r[7] / max(1, r[1]), r[11],
                 f(r[8]), f(r[9]), f(r[10])))
    for r in rows:
        if r[0] == "fifo_load":
            ok99 = r[3] <= 2.0 * r[9]
            okmax = r[5] <= r[10] + 1000.0  # a reply that never came is an infinite latency
            print("\nTarget (SCHED_FIFO under load): reply p99 %s us %s 2 x cyclictest p99 = %.0f us: %s; "
                  "reply max %s us vs cyclictest max + 1 ms = %.0f us: %s (%d replies missed their tick, %d never came)"
                  % (f(r[3]), "<=" if ok99 else ">", 2.0 * r[9], "met" if ok99 else "NOT met",
                     f(r[5]), r[10] + 1000.0, "met" if okmax else "NOT met", r[7], r[11]))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("\n(matplotlib missing: no plot)")
        return
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5), sharey=True)
    bins = [10 ** (1 + 0.05 * i) for i in range(61)]  # 10 us .. 10 ms, log spaced
    for ax, sched in zip(axes, ["fifo", "other"]):
        for cfg, style in [(sched + "_idle", "-"), (sched + "_load", "--")]:
            if cfg not in data:
                continue
            vals, hist = data[cfg]
            ax.hist([max(v, 10.0) for v in vals], bins=bins, histtype="step", linestyle=style, linewidth=1.5,
                    label="reply latency, %s (%.2f %% missed the tick)" % (cfg.split("_")[1], missed_pct[cfg]))
            if hist:
                ks = sorted(hist)
                ax.hist([max(k, 10) for k in ks], bins=bins, weights=[hist[k] for k in ks], histtype="step",
                        linestyle=style, linewidth=1.0, color="grey",
                        label="cyclictest, " + cfg.split("_")[1])
        ax.axvline(PERIOD_US, color="red", linewidth=0.8, label="1 ms period")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("latency (us)")
        ax.set_title("SCHED_FIFO (deployment priorities)" if sched == "fifo" else "SCHED_OTHER (no real-time rights)")
        ax.legend(fontsize=8)
    axes[0].set_ylabel("packets / wake-ups")
    fig.suptitle("FRI reply latency (simulated KRC, loopback, 1 kHz) vs cyclictest")
    fig.tight_layout()
    png = os.path.join(out, "rt_latency.png")
    fig.savefig(png, dpi=110)
    print("\nplot: " + png)


if __name__ == "__main__":
    main()
