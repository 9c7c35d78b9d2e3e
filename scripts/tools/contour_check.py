#!/usr/bin/python3
"""Checks a closed-contour run (tactile_sim run SCENE --out RUN) and plots it.

Reads RUN/contacts.csv (the controller's contact points: the measured flange
pose, the sensor mount and the tactile image; see core/sim/runner/src/runner.cpp)
and RUN/summary.json (phases), and the scene's geometry independently: each
`bent_bar`'s ridge, its axis polyline raised by its radius along +z_g (the
contours here lie in horizontal planes, touched from above).

  closure_m   the true closure: the distance from the simulator's true
              contact point (evaluation only) where the exploration started
              to where the run entered `done` (loop_closed fired there), else
              to the exploration's last; closure_cop_m the same from the
              logged CoP points (not the servo's loop point, servo.hpp WRIST)
  rms_m       RMS distance, in the contour's plane (x_g, y_g), of the
              reconstructed contour points in the exploring phases to the
              ridge: the contact line's points (RUN/edge_points.csv: where
              the edge crosses each taxel column; tactile_features/
              edge_line.hpp), or, for a run without that file, the
              arc-corrected CoP (reconstruct())
  rms_arc_m   the same for the arc-corrected CoP (reconstruct())
  rms_cop_m   the same for the raw CoP (inside a curve: the arc's centroid)
  rms_3d_m    the reconstruction's 3-D distance: adds the pad's indentation
              (the CoP lies on the undeformed pad surface, z_s = 0, which the
              ridge presses into by about 1 mm at 5 N)
  unwinds     entries into the `unwind*` phases, with their times
  gap_crossings  entries into the `cross_gap*` phases (a gap in the edge
              under the pad), with their times (--gap-crossings: exactly)
  coverage    per object, the share of its contour with a reconstructed point
              within COVER_M; end_distance_m: the last exploring point to the
              last object's last vertex (--open: must be <= END_M)

Writes RUN/contour.json and RUN/contour.png; exits 1 when a check fails
(--max-closure, --max-rms, --min-coverage, --max-force-rms, --min-force-band;
defaults: the targets 5 mm and 1 mm, 90 % of each contour covered, and the
true force's RMS error <= 0.4 N and >= 95 % of the time within its band), 2
on bad input.

usage: contour_check.py RUN SCENE [--max-closure M] [--max-rms M] [--min-coverage F] [--min-unwinds N]
                        [--gap-crossings N] [--no-plot]
"""
import argparse
import csv
import json
import math
import os
import sys

import numpy as np
import yaml


def ridges(scene_path):
    sc = yaml.safe_load(open(scene_path))
    out = []
    for o in sc.get("objects", []):
        if o.get("type") in ("bar", "bent_bar"):
            v = np.array(o["vertices"], dtype=float)
            v[:, 2] += float(o["radius"])
            out.append(v)
    if not out:
        raise ValueError("%s: no bar or bent_bar objects" % scene_path)
    return out


def dist_to_polylines(pts, lines):
    """Distance from each point (n x 3) to the nearest segment of any polyline."""
    best = np.full(len(pts), np.inf)
    for v in lines:
        for a, b in zip(v[:-1], v[1:]):
            ab = b - a
            t = np.clip(((pts - a) @ ab) / max(ab @ ab, 1e-300), 0.0, 1.0)
            d = np.linalg.norm(pts - (a + t[:, None] * ab), axis=1)
            best = np.minimum(best, d)
    return best


END_M = 0.025  # m: an open contour's end is reached when the CoP came this close (the pad's half length, 23.8 mm)
COVER_M = 0.003  # m: a point of the true contour is covered when a reconstructed point lies this close
WINDOW_M = 0.015  # m: the neighbourhood in which the contour's local curvature is fitted


FIT_RESIDUAL_M = 0.0002  # m: RMS residual of the circle fit up to which the curve is taken as an arc
                          # (the ring's CoP path: < 0.05 mm; a 1 cm corner under the 47.6 mm pad: mm)


def fit_circle(xy):
    """Algebraic (Kasa) circle fit: centre (2,), radius; radius inf when (nearly) straight."""
    A = np.c_[2 * xy, np.ones(len(xy))]
    b = (xy ** 2).sum(axis=1)
    sol, *_ = np.linalg.lstsq(A, b, rcond=None)
    c = sol[:2]
    r2 = sol[2] + c @ c
    if not (r2 > 0) or r2 > 1e2:
        return c, math.inf
    return c, math.sqrt(r2)


def reconstruct(P, lam1, seg):
    """The contour from the controller's own data. The CoP is the centroid of
    the load, and on an edge that curves under the straight pad with radius R
    (small angles: y = x^2 / (2 R) along the edge) it lies E[x^2] / (2 R) =
    lambda1 / (2 R) inside the curve, lambda1 being the contact's second
    moment along the edge (the features' lambda1, logged with each point). R
    and the curve's centre come from a circle fitted to the CoP path itself
    over the points within WINDOW_M of it (of the same exploring stretch
    `seg`, spread over at least 1.5 WINDOW_M along the path); the
    point is moved by lambda1 / (2 R) away from that centre, in the contour's
    plane (here horizontal: x_g, y_g). Straight stretches (R > 10 m, or too
    few points) stay as they are."""
    out = P.copy()
    xy = P[:, :2]
    for i in range(len(P)):
        m = (seg == seg[i]) & (np.linalg.norm(xy - xy[i], axis=1) <= WINDOW_M)
        if m.sum() < 20:
            continue
        q = xy[m] - xy[m].mean(axis=0)
        ext = np.ptp(q @ np.linalg.svd(q, full_matrices=False)[2][0])  # extent along the path
        if ext < 1.5 * WINDOW_M:  # the contact has not moved enough around here to show a curve
            continue
        c, R = fit_circle(P[m, :2])
        if not math.isfinite(R):
            continue
        # Only where the path is a circle (a steady curve under the pad); at a
        # corner tighter than the pad the arc model does not hold: left as is.
        if np.sqrt(np.mean((np.linalg.norm(P[m, :2] - c, axis=1) - R) ** 2)) > FIT_RESIDUAL_M:
            continue
        d = lam1[i] / (2 * R)
        v = P[i, :2] - c
        out[i, :2] = P[i, :2] + d * v / np.linalg.norm(v)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("run")
    ap.add_argument("scene")
    ap.add_argument("--max-closure", type=float, default=0.005)
    ap.add_argument("--max-rms", type=float, default=0.001)
    ap.add_argument("--min-coverage", type=float, default=0.9,
                    help="least share of each object's contour with a reconstructed point within COVER_M "
                         "(an accurate cloud must also cover the contour)")
    ap.add_argument("--min-unwinds", type=int, default=0, help="at least this many lift-off-and-unwind sequences")
    ap.add_argument("--gap-crossings", type=int, default=0,
                    help="exactly this many entries into a cross_gap phase (a gap in the edge under the pad)")
    ap.add_argument("--open", action="store_true",
                    help="an open contour: instead of the closure, the run must reach the last object's far end "
                         "(the last exploring contact point within END_M of its last vertex)")
    ap.add_argument("--max-force-rms", type=float, default=0.4,
                    help="N: the true force's RMS error against the set point while exploring (summary.json)")
    ap.add_argument("--min-force-band", type=float, default=0.95,
                    help="least share of the exploring time with the true force within the scene's band (+-0.5 N)")
    ap.add_argument("--no-plot", action="store_true")
    a = ap.parse_args()
    try:
        summ = json.load(open(os.path.join(a.run, "summary.json")))
        rows = list(csv.DictReader(open(os.path.join(a.run, "contacts.csv"))))
        lines = ridges(a.scene)
    except (OSError, ValueError, KeyError) as e:
        print("contour_check: %s" % e, file=sys.stderr)
        return 2
    phases = summ["phases"]
    # phase index -> name: contacts.csv carries the index; summary.json the entries in order.
    ts = list(csv.DictReader(open(os.path.join(a.run, "timeseries.csv"))))
    names = {}
    for r in ts:
        names[int(r["phase"])] = r["phase_name"]
    expl = [r for r in rows if names.get(int(r["phase"]), "").startswith("explore")]
    if not expl:
        print("contour_check: no contact points in an explore phase", file=sys.stderr)
        return 2
    P = np.array([[float(r["x"]), float(r["y"]), float(r["z"])] for r in expl])
    lam1 = np.array([float(r["lambda1"]) for r in expl])
    ph = np.array([int(r["phase"]) for r in expl])
    seg = np.r_[0, np.cumsum(np.diff(ph) != 0)]  # exploring stretches between re-acquisitions
    A = reconstruct(P, lam1, seg)  # the arc-corrected CoP
    # The reconstruction: the contact line's points (edge_points.csv, one per
    # taxel column that has the edge on two or three rows; edge_line.hpp), in
    # the exploring phases. A run without that file (an older runner) falls
    # back to the arc-corrected CoP.
    ep_path = os.path.join(a.run, "edge_points.csv")
    E, tE, recon = A, np.array([float(r["time"]) for r in expl]), "arc-corrected CoP"
    if os.path.exists(ep_path):
        ep = [r for r in csv.DictReader(open(ep_path)) if names.get(int(r["phase"]), "").startswith("explore")]
        if ep:
            E = np.array([[float(r["x"]), float(r["y"]), float(r["z"])] for r in ep])
            tE = np.array([float(r["time"]) for r in ep])
            recon = "edge line"
    T = np.array([[float(r["true_x"]), float(r["true_y"]), float(r["true_z"])] for r in expl])
    flat = [np.c_[v[:, :2], np.zeros(len(v))] for v in lines]
    def d2(X):  # in the contour's (horizontal) plane
        return dist_to_polylines(np.c_[X[:, :2], np.zeros(len(X))], flat)
    d_edge, d_cop, d_true, d_arc = d2(E), d2(P), d2(T), d2(A)
    d_3d = dist_to_polylines(E, lines)
    start = P[0]
    # The loop's end: the contact point where the program entered `done` (the
    # servo's loop_closed fired on it), else the exploration's last.
    done = [r for r in rows if names.get(int(r["phase"]), "") == "done"]
    last = np.array([float(done[0][k]) for k in ("x", "y", "z")]) if done else P[-1]
    closure_cop = float(np.linalg.norm(last - start))
    last_true = np.array([float(done[0]["true_" + k]) for k in ("x", "y", "z")]) if done else T[-1]
    closure = float(np.linalg.norm(last_true - T[0]))
    far = float(np.max(np.linalg.norm(P - start, axis=1)))
    unw = [p["t_enter"] for p in phases if p["name"].startswith("unwind")]
    gaps = [p["t_enter"] for p in phases if p["name"].startswith("cross_gap")]
    # Coverage: the share of each object's contour (sampled every mm) with a reconstructed point within COVER_M.
    cover = []
    for v in lines:
        smp = []
        for a0, b0 in zip(v[:-1], v[1:]):
            k = max(1, int(np.linalg.norm(b0 - a0) / 0.001))
            smp += [a0 + (b0 - a0) * j / k for j in range(k)]
        smp = np.array(smp)[:, :2]
        dmin = np.array([np.min(np.linalg.norm(E[:, :2] - q, axis=1)) for q in smp])
        cover.append(float(np.mean(dmin <= COVER_M)))
    end_dist = float(np.linalg.norm(P[-1, :2] - lines[-1][-1, :2]))
    res = {
        "scene": summ["scene"], "status": summ["status"], "sim_time_s": summ["sim_time_s"],
        "t_explore_s": next((p["t_enter"] for p in phases if p["name"] == "explore"), None),
        "t_done_s": next((p["t_enter"] for p in phases if p["name"] == "done"), None),
        "ended_by_loop_closure": phases[-1]["name"] == "done",
        "closure_m": closure, "closure_cop_m": closure_cop, "farthest_from_start_m": far,
        "rms_m": float(np.sqrt(np.mean(d_edge ** 2))), "max_m": float(np.max(d_edge)),
        "reconstruction": recon,
        "rms_cop_m": float(np.sqrt(np.mean(d_cop ** 2))),
        "rms_arc_m": float(np.sqrt(np.mean(d_arc ** 2))),
        "rms_3d_m": float(np.sqrt(np.mean(d_3d ** 2))),
        "rms_true_pressure_centre_m": float(np.sqrt(np.mean(d_true ** 2))),
        "points": int(len(E)), "coverage": cover, "end_distance_m": end_dist, "unwinds": len(unw), "unwind_times_s": unw,
        "gap_crossings": len(gaps), "gap_times_s": gaps,
        "phases": [p["name"] for p in phases],
    }
    fails = []
    if summ["status"] != "ok":
        fails.append("status %s" % summ["status"])
    if not res["ended_by_loop_closure"]:  # (an open contour: by the search past its end)
        fails.append("the run did not end in 'done'")
    if a.open:
        if not end_dist <= END_M:
            fails.append("the end not reached: last point %.4f m from it > %.3f m" % (end_dist, END_M))
    elif not closure <= a.max_closure:
        fails.append("closure %.4f m > %.4f m" % (closure, a.max_closure))
    if not far > 10 * a.max_closure:
        fails.append("never left the start (farthest %.4f m)" % far)
    if not res["rms_m"] <= a.max_rms:
        fails.append("cloud RMS %.5f m > %.5f m" % (res["rms_m"], a.max_rms))
    if not min(cover) >= a.min_coverage:
        fails.append("coverage %.3f < %.3f" % (min(cover), a.min_coverage))
    f_rms, f_band = summ.get("force_true_rms_error_n"), summ.get("force_true_in_band_fraction")
    if f_rms is None or not f_rms <= a.max_force_rms:
        fails.append("true force RMS error %s N > %.2f N" % (f_rms, a.max_force_rms))
    if f_band is None or not f_band >= a.min_force_band:
        fails.append("true force within its band %s < %.2f of the time" % (f_band, a.min_force_band))
    if len(gaps) != a.gap_crossings:
        fails.append("%d gap crossings, expected %d" % (len(gaps), a.gap_crossings))
    if not len(unw) >= a.min_unwinds:
        fails.append("%d unwinds < %d" % (len(unw), a.min_unwinds))
    res["failed"] = fails
    json.dump(res, open(os.path.join(a.run, "contour.json"), "w"), indent=1)
    if not a.no_plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(12, 5.5), gridspec_kw={"width_ratios": [1.1, 1]})
        for i, v in enumerate(lines):
            ax[0].plot(v[:, 0] * 1e3, v[:, 1] * 1e3, "k-", lw=2.5, alpha=0.35, label="true contour (ridge)" if i == 0 else None)
        ax[0].plot(P[:, 0] * 1e3, P[:, 1] * 1e3, ".", ms=1.5, color="tab:orange", label="CoP (RMS %.2f mm)" % (res["rms_cop_m"] * 1e3))
        ax[0].plot(E[:, 0] * 1e3, E[:, 1] * 1e3, ".", ms=1.5, color="tab:blue", label="%s (RMS %.2f mm)" % (recon, res["rms_m"] * 1e3))
        ax[0].plot(start[0] * 1e3, start[1] * 1e3, "g^", ms=9, label="exploration start")
        ax[0].plot(last[0] * 1e3, last[1] * 1e3, "rv", ms=9, label=("end (%.1f mm from the far end)" % (end_dist * 1e3)) if a.open else ("end (closure %.1f mm)" % (closure * 1e3)))
        t_c = np.array([float(r["time"]) for r in rows])
        for tu in unw:
            k = int(np.argmin(np.abs(t_c - tu)))
            ax[0].plot(float(rows[k]["x"]) * 1e3, float(rows[k]["y"]) * 1e3, "ms", ms=8, mfc="none")
        ax[0].plot([], [], "ms", mfc="none", label="lift off + unwind (%d)" % len(unw))
        ax[0].set_aspect("equal", adjustable="datalim")
        ax[0].set_xlabel("x_g (mm)")
        ax[0].set_ylabel("y_g (mm)")
        ax[0].legend(fontsize=8, loc="best")
        ax[0].set_title("%s: reconstructed contour over the truth (top view)" % summ["scene"])
        tt = np.array([float(r["time"]) for r in expl])
        ax[1].plot(tt, d_cop * 1e3, ".", ms=1.5, color="tab:orange", label="CoP")
        ax[1].plot(tE, d_edge * 1e3, ".", ms=1.5, color="tab:blue", label=recon)
        ax[1].axhline(a.max_rms * 1e3, color="r", ls="--", lw=1, label="RMS bound %g mm" % (a.max_rms * 1e3))
        for tu in unw:
            ax[1].axvline(tu, color="m", lw=0.8)
        ax[1].set_xlabel("time (s)")
        ax[1].set_ylabel("distance to the true contour, in its plane (mm)")
        ax[1].set_title("error along the exploration (magenta: unwinding)")
        ax[1].legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(a.run, "contour.png"), dpi=110)
    print(json.dumps({k: res[k] for k in ("scene", "status", "closure_m", "closure_cop_m", "end_distance_m", "coverage", "reconstruction", "rms_m",
                                           "rms_arc_m", "rms_cop_m", "rms_3d_m", "max_m", "points", "unwinds", "gap_crossings",
                                           "unwind_times_s", "t_done_s")}))
    for f in fails:
        print("FAIL: " + f)
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
