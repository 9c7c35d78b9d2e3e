#!/usr/bin/python3
"""Table and histogram of scripts/rt_latency.sh's measurements.

    scripts/rt_latency_report.py OUT_DIR

Reads OUT_DIR/<cfg>_krc.txt (one reply latency per KRC cycle, us; nan = no
reply) and OUT_DIR/<cfg>_cyclictest.hist (cyclictest -h: "latency_us count"
lines, "# Max Latencies:" comment) for cfg in fifo_idle, fifo_load,
other_idle, other_load. Prints a Markdown table (p50, p99, p99.9, max, replies
later than the 1 ms period, missed replies; cyclictest's p50, p99, max beside)
A cycle whose reply did not arrive before the KRC's next tick (stale or lost)
counts as an infinite latency in the percentiles ("miss" when a percentile
falls on one); "max" is the largest reply that did arrive in its cycle. Then
the target check of the issue (SCHED_FIFO under load: reply p99 within 2x
cyclictest's p99, max within cyclictest's max + 1 ms); writes
OUT_DIR/rt_latency.png (histograms, log scale).
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
    vals, missed = [], 0
    started = False
    with open(path) as f:
        for line in f:
            v = float(line)
            if math.isnan(v):
                if started:  # before the first reply the deployment was still starting
                    missed += 1
                    vals.append(float("inf"))
                continue
            started = True
            vals.append(v)
    return sorted(vals), missed


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
        vals, missed = read_krc(kp)
        hist, hmax = read_hist(hp) if os.path.exists(hp) else ({}, float("nan"))
        got = [v for v in vals if math.isfinite(v)]
        late = sum(1 for v in got if v > PERIOD_US)
        data[cfg] = (got, hist)
        missed_pct[cfg] = 100.0 * missed / max(1, len(vals))
        rows.append((cfg, len(vals), pct(vals, 50), pct(vals, 99), pct(vals, 99.9), got[-1] if got else float("nan"),
                     late, missed, hist_pct(hist, 50), hist_pct(hist, 99), hmax))

    def f(v):
        return "miss" if v == float("inf") else "%.0f" % v

    print("| configuration | cycles | p50 (us) | p99 (us) | p99.9 (us) | max (us) | late > 1 ms | missed "
          "| cyclictest p50 (us) | cyclictest p99 (us) | cyclictest max (us) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print("| %s | %d | %s | %s | %s | %s | %d | %d (%.1f %%) | %s | %s | %s |"
              % (r[0], r[1], f(r[2]), f(r[3]), f(r[4]), f(r[5]), r[6], r[7], 100.0 * r[7] / max(1, r[1]),
                 f(r[8]), f(r[9]), f(r[10])))
    for r in rows:
        if r[0] == "fifo_load":
            ok99 = r[3] <= 2.0 * r[9]
            okmax = r[5] <= r[10] + 1000.0 and r[7] == 0  # a missed reply is an unbounded one
            print("\nTarget (SCHED_FIFO under load): reply p99 %.0f us %s 2 x cyclictest p99 = %.0f us: %s; "
                  "reply max %.0f us (%d missed) vs cyclictest max + 1 ms = %.0f us: %s"
                  % (r[3], "<=" if ok99 else ">", 2.0 * r[9], "met" if ok99 else "NOT met",
                     r[5], r[7], r[10] + 1000.0, "met" if okmax else "NOT met"))
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
                    label="reply latency, %s (%.1f %% missed)" % (cfg.split("_")[1], missed_pct[cfg]))
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
