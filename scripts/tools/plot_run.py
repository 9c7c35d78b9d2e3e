#!/usr/bin/python3
"""Plots of one tactile_sim run directory (written by `tactile_sim run`).

usage: plot_run.py RUN_DIR [--compare OTHER_RUN_DIR [OTHER_RUN_DIR ...]]

Reads RUN_DIR/timeseries.csv, summary.json, snapshots.csv and contacts.csv and
writes PNGs into RUN_DIR:
  overview.png      sensor position, forces, features, phases (every scene)
  fig10.png         edge exploration, mirroring Fig. 10 of the paper
  fig14.png         co-manipulation, mirroring Fig. 14
  snapshots.png     tactile images at the phase switches
  contacts.png      reconstructed contact-point cloud (Fig. 9f / 11b)
With --compare, also RUN_DIR/fig12.png: the true normal force of the runs
overlaid (Fig. 12: proposed vs the Li et al. baseline and the no_rotation
ablation).
Only Debian's python3-numpy and python3-matplotlib are used.
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def load_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    head, body = rows[0], rows[1:]
    cols = {}
    for i, h in enumerate(head):
        vals = [r[i] for r in body]
        try:
            cols[h] = np.array([float(v) for v in vals])
        except ValueError:
            cols[h] = np.array(vals)
    return cols


def phase_marks(ax, summary):
    for p in summary.get("phases", [])[1:]:
        ax.axvline(p["t_enter"], color="0.6", lw=0.8, ls=":")


def phase_labels(ax, summary):
    phases = summary.get("phases", [])
    for i, p in enumerate(phases):
        ax.text(p["t_enter"], 1.0, " " + p["name"], transform=ax.get_xaxis_transform(), fontsize=7,
                va="top", color="0.3", rotation=90 if len(phases) > 4 else 0)


def overview(run, ts, summary):
    t = ts["time"]
    fig, ax = plt.subplots(4, 1, figsize=(10, 11), sharex=True)
    for k, c in zip("xyz", "rbg"):
        ax[0].plot(t, ts["act_" + k] - ts["act_" + k][0], c, label=f"{k} actual")
        ax[0].plot(t, ts["cmd_" + k] - ts["act_" + k][0], c + "--", lw=0.8, label=f"{k} commanded")
    ax[0].set_ylabel("sensor position\nrel. to start (m)")
    ax[0].legend(ncol=3, fontsize=7)
    phase_labels(ax[0], summary)
    ax[1].plot(t, ts["force"], "r", label="f measured (taxels)")
    if np.any(np.isfinite(ts["force_true"])):  # a deployment's run has no ground truth
        ax[1].plot(t, ts["force_true"], "k", lw=0.8, label="f true (Nano17)")
    if "housing_force" in ts and np.any(np.isfinite(ts["housing_force"])):
        ax[1].plot(t, ts["housing_force"], "m", lw=0.8, label="housing (no signal)")
    ax[1].plot(t, ts["sd_force"], "r--", lw=0.8, label="f desired")
    ax[1].set_ylabel("force (N)")
    ax[1].legend(fontsize=7)
    for name, c in (("cop_x", "r"), ("cop_y", "b"), ("coc_x", "m"), ("coc_y", "c")):
        ax[2].plot(t, ts[name] * 1e3, c, lw=0.9, label=name)
    ax[2].plot(t, ts["dzmp_y"] * 1e3, "k", lw=0.9, label="dzmp_y")
    ax[2].set_ylabel("features (mm)")
    ax[2].legend(ncol=5, fontsize=7)
    ax[3].plot(t, np.degrees(ts["alpha_z"]), "b", label="alpha_z")
    if "tray_angle_deg" in ts and np.any(ts["tray_angle_deg"] != 0):
        ax[3].plot(t, ts["tray_angle_deg"], "k", label="tray angle")
    ax[3].plot(t, ts["contact"] * 10, "0.5", lw=0.8, label="contact type x10 (1 point, 2 edge, 3 multiple)")
    ax[3].set_ylabel("deg")
    ax[3].set_xlabel("time (s)")
    ax[3].legend(fontsize=7)
    fault = summary.get("fault_time_s")  # the fault that ended the run (summary.json), None when ok
    for a in ax:
        phase_marks(a, summary)
        if fault is not None:
            a.axvline(fault, color="r", lw=1.0, ls="--")
        a.grid(alpha=0.3)
    when = f" at {fault:.2f} s (red dashes)" if fault is not None else ""
    fig.suptitle(f"{summary['scene']} ({summary['controller']}), status {summary.get('status', '?')}{when}")
    fig.tight_layout()
    fig.savefig(os.path.join(run, "overview.png"), dpi=90)
    plt.close(fig)


def fig10(run, ts, summary):
    t = ts["time"]
    fig, ax = plt.subplots(2, 2, figsize=(12, 7), sharex=True)
    a = ax[0, 0]
    for k, c in zip("xyz", "rbg"):
        a.plot(t, ts["act_" + k], c, label=f"{k}")
        a.plot(t, ts["cmd_" + k], c + "--", lw=0.7)
    a.set_ylabel("end-effector (sensor) position (m)")
    a.set_title("(a) position: solid actual, dashed set point", fontsize=9)
    a.legend(fontsize=7)
    a = ax[0, 1]
    a.plot(t, ts["force"], "r", label="f (taxels, Eq. 2)")
    a.plot(t, ts["sd_force"], "r--", label="f desired")
    if np.any(np.isfinite(ts["force_true"])):  # the shipped programs regulate f + the wrench's correction
        a.plot(t, ts["force_true"], "k", lw=0.8, label="f true (Nano17)")
    a.legend(fontsize=7, loc="lower right")
    a2 = a.twinx()
    a2.plot(t, ts["cop_y"] * 1e3, "b", label="CoP_y")
    a2.plot(t, ts["sd_cop_y"] * 1e3, "b--", lw=0.8)
    a2.set_ylabel("CoP_y (mm)", color="b")
    a.set_ylabel("force (N)", color="r")
    a.set_title("(b) force and CoP_y: solid feedback, dashed desired", fontsize=9)
    a = ax[1, 0]
    a.plot(t, ts["coc_x"] * 1e3, "m", label="CoC_x")
    a.plot(t, ts["cop_x"] * 1e3, "r", lw=0.8, label="CoP_x")
    a.plot(t, ts["sd_cop_x"] * 1e3, "k--", lw=0.8, label="desired (pseudo-measurement in phase IV)")
    a.set_ylabel("mm")
    a.set_title("(c) CoC_x / CoP_x and desired", fontsize=9)
    a.legend(fontsize=7)
    a = ax[1, 1]
    a.plot(t, ts["dzmp_y"] * 1e3, "r", label="DZMP_y")
    a.plot(t, ts["sd_dzmp_y"] * 1e3, "g--", label="desired")
    a2 = a.twinx()
    a2.plot(t, ts["moment_y_true"] * 1e3, "b", lw=0.8, label="true moment about y_s")
    a2.set_ylabel("true moment (N mm)", color="b")
    a.set_ylabel("DZMP_y (mm)")
    a.set_title("(d) DZMP_y vs the ground-truth moment", fontsize=9)
    a.legend(fontsize=7, loc="upper left")
    for a in ax.flat:
        phase_marks(a, summary)
        a.grid(alpha=0.3)
        a.set_xlabel("time (s)")
    fig.suptitle(f"Edge exploration (cf. Fig. 10): {summary['controller']}")
    fig.tight_layout()
    fig.savefig(os.path.join(run, "fig10.png"), dpi=90)
    plt.close(fig)


def fig14(run, ts, summary, snaps):
    t = ts["time"]
    fig, ax = plt.subplots(2, 2, figsize=(12, 7))
    a = ax[0, 0]
    a.plot(t, ts["dzmp_y"] * 1e3, "k", label="DZMP_y")
    a.plot(t, ts["sd_dzmp_y"] * 1e3, "k--", lw=0.8, label="desired")
    a2 = a.twinx()
    a2.plot(t, ts["moment_y_true"] * 1e3, "b", lw=0.8)
    a2.set_ylabel("true moment about y_s (N mm)", color="b")
    a.set_ylabel("mm")
    a.set_title("(a) DZMP_y vs desired, and the true moment", fontsize=9)
    a.legend(fontsize=7)
    a = ax[0, 1]
    for k, c in zip("xyz", "rbg"):
        a.plot(t, ts["act_" + k] - ts["act_" + k][0], c, label=k)
    a.set_ylabel("sensor position rel. to start (m)")
    a.set_title("(b) end-effector x, y, z", fontsize=9)
    a.legend(fontsize=7)
    a = ax[1, 0]
    a.plot(t, np.degrees(ts["alpha_z"]), "b", label="alpha_z")
    a.plot(t, np.degrees(ts["sd_alpha_z"]), "b--", lw=0.8)
    a.plot(t, np.degrees(ts["act_yaw"] - ts["act_yaw"][0]), "r", label="sensor rotation about z")
    a.plot(t, np.degrees(ts["cmd_yaw"] - ts["act_yaw"][0]), "r--", lw=0.8)
    if "tray_angle_deg" in ts:
        a.plot(t, ts["tray_angle_deg"], "k", lw=0.8, label="tray angle")
    a.set_ylabel("deg")
    a.set_title("(c) alpha_z and the rotation about z", fontsize=9)
    a.legend(fontsize=7)
    for a in (ax[0, 0], ax[0, 1], ax[1, 0]):
        phase_marks(a, summary)
        a.grid(alpha=0.3)
        a.set_xlabel("time (s)")
    a = ax[1, 1]
    if snaps:
        worst = [x for x in snaps if x[1].startswith("largest")]
        first, last = (worst[0] if worst else snaps[0]), snaps[-1]
        tactile_pair(a, first, last)
        a.set_title(f"(d) tactile images at t={first[0]:.1f} s ({first[1]})\nand t={last[0]:.1f} s (true aspect)",
                    fontsize=9)
    else:
        a.text(0.5, 0.5, "(d) no tactile snapshots in this run", ha="center", va="center", transform=a.transAxes)
        a.axis("off")
    fig.suptitle("Co-manipulation (cf. Fig. 14)")
    fig.tight_layout()
    fig.savefig(os.path.join(run, "fig14.png"), dpi=90)
    plt.close(fig)


PITCH_MM = 3.4  # WTS0614 taxel pitch, the same along x_s and y_s


def tactile_pair(a, first, last):
    """Two tactile images stacked (one taxel row of gap) at their true aspect:
    each taxel a 3.4 mm square, axes in mm of {s} (x_s to the right)."""
    rows, cols = first[2].shape
    gap = np.full((1, cols), np.nan)
    img = np.vstack([first[2], gap, last[2]])
    vmax = max(1e-9, np.nanmax(img))
    h = img.shape[0] * PITCH_MM
    cmap = plt.get_cmap("gray_r").copy()
    cmap.set_bad("tab:blue", 0.25)  # the gap row between the two images
    im = a.imshow(img, cmap=cmap, vmin=0, vmax=vmax, interpolation="nearest",
                  extent=(0, cols * PITCH_MM, h, 0), aspect="equal")
    for (t, name, _), y0 in ((first, 0.0), (last, (rows + 1) * PITCH_MM)):
        a.text(0.5, y0 + 0.5, f"t = {t:.1f} s", va="top", ha="left", fontsize=7, color="tab:red")
    a.set_xlabel("x_s (mm)")
    a.set_ylabel("y_s (mm): two images, 3.4 mm taxels")
    a.figure.colorbar(im, ax=a, fraction=0.046, pad=0.04, label="N per taxel")


def load_snapshots(run, rows=6, cols=14):
    path = os.path.join(run, "snapshots.csv")
    if not os.path.exists(path):
        return []
    out = []
    with open(path) as f:
        r = csv.reader(f)
        next(r)
        for row in r:
            vals = np.array([float(v) for v in row[2:]])
            out.append((float(row[0]), row[1], vals.reshape(rows, cols)))
    return out


def snapshots_png(run, snaps):
    if not snaps:
        return
    n = len(snaps)
    fig, ax = plt.subplots(n, 1, figsize=(6, 1.6 * n + 0.4), squeeze=False)
    vmax = max(1e-9, max(s[2].max() for s in snaps))
    for a, (t, name, img) in zip(ax[:, 0], snaps):
        a.imshow(img, cmap="gray_r", vmin=0, vmax=vmax, interpolation="nearest")
        a.set_title(f"t = {t:.2f} s: {name}", fontsize=8)
        a.set_xticks([])
        a.set_yticks([])
    fig.suptitle("tactile images at phase switches (N per taxel; x_s to the right)", fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(run, "snapshots.png"), dpi=90)
    plt.close(fig)


def contacts_png(run):
    path = os.path.join(run, "contacts.csv")
    if not os.path.exists(path):
        return
    c = load_csv(path)
    if len(c.get("x", [])) == 0:
        return
    fig = plt.figure(figsize=(11, 4.5))
    a = fig.add_subplot(1, 3, 1, projection="3d")
    a.scatter(c["x"], c["y"], c["z"], s=2, c=c["time"], cmap="viridis")
    a.set_xlabel("x_g")
    a.set_ylabel("y_g")
    a.set_zlabel("z_g")
    a.set_title("contact points {g}", fontsize=9)
    for i, (u, v, name) in enumerate((("x", "y", "top view"), ("x", "z", "side view"))):
        b = fig.add_subplot(1, 3, 2 + i)
        b.scatter(c[u], c[v], s=2, c=c["time"], cmap="viridis")
        if "true_x" in c:
            b.plot(c["true_" + u], c["true_" + v], "r.", ms=1, alpha=0.4, label="true contact")
            b.legend(fontsize=7)
        b.set_xlabel(u + "_g (m)")
        b.set_ylabel(v + "_g (m)")
        b.set_title(name, fontsize=9)
        b.axis("equal")
        b.grid(alpha=0.3)
    fig.suptitle("reconstructed contact-point cloud (CoP mapped to {g}; cf. Fig. 9f / 11b)", fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(run, "contacts.png"), dpi=90)
    plt.close(fig)


def fig12(run, others):
    a_ts = load_csv(os.path.join(run, "timeseries.csv"))
    runs = [(a_ts, json.load(open(os.path.join(run, "summary.json"))))]
    for other in others:
        runs.append((load_csv(os.path.join(other, "timeseries.csv")), json.load(open(os.path.join(other, "summary.json")))))
    colors = {"proposed": "r", "baseline": "b", "no_rotation": "0.5"}
    fig, ax = plt.subplots(figsize=(9, 4))
    for ts, s in runs:
        c = colors.get(s["controller"], "g")
        if np.any(np.isfinite(ts["force_true"])):
            ax.plot(ts["time"], ts["force_true"], c, label=f"{s['controller']}: true normal force")
        else:  # a deployment's run (scripts/tools/deployment_to_run.py): only what the taxels measure
            ax.plot(ts["time"], ts["force"], c, label=f"{s['controller']}: measured normal force (taxels)")
    ax.plot(a_ts["time"], a_ts["sd_force"], "k--", lw=0.8, label="desired")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("force (N)")
    ax.set_title("Bent bar (cf. Fig. 12): " + " vs ".join(s["controller"] for _, s in runs)
                 + " (baseline = Li et al. 2013)")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(run, "fig12.png"), dpi=90)
    plt.close(fig)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    run = sys.argv[1]
    ts = load_csv(os.path.join(run, "timeseries.csv"))
    summary = json.load(open(os.path.join(run, "summary.json")))
    snaps = load_snapshots(run)
    overview(run, ts, summary)
    fig_kind = summary.get("figure", "")
    if fig_kind == "fig10":
        fig10(run, ts, summary)
    if fig_kind == "fig14":
        fig14(run, ts, summary, snaps)
    snapshots_png(run, snaps)
    contacts_png(run)
    if len(sys.argv) >= 4 and sys.argv[2] == "--compare":
        fig12(run, sys.argv[3:])


if __name__ == "__main__":
    main()
