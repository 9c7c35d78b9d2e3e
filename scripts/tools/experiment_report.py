#!/usr/bin/python3
"""Print the key numbers of the main job's runs (out/<scene>/summary.json)
next to the paper's claims, and write them to out/report.md.

usage: experiment_report.py OUT_DIR
"""
import json
import os
import sys


def load(out, name):
    p = os.path.join(out, name, "summary.json")
    return json.load(open(p)) if os.path.exists(p) else None


def fmt(v, unit="", scale=1.0, nd=2):
    return "n/a" if v is None else f"{v * scale:.{nd}f}{unit}"


def truth(d, key):
    """d[key] (a ground-truth metric of the simulator); for a deployment's run
    (scripts/tools/deployment_to_run.py: no ground truth) its measured counterpart:
    force_true -> force_measured in the name, a path or a speed (path_length_m,
    slide_speed_mps, slide_path_m, ...) -> sensor_<key>."""
    if d.get(key) is not None:
        return d[key]
    if "force_true" in key:
        return d.get(key.replace("force_true", "force_measured"))
    if key.endswith(("_path_m", "path_length_m", "_speed_mps")):
        return d.get("sensor_" + key)
    return None


def slide_and_scored(d, slide_key, scored_key, unit, scale=1.0, nd=2):
    """'<whole slide> / <scored window>' of one figure (the slide's key, the
    scored window's key; summary.json, docs/formats.md)."""
    return f"{fmt(truth(d, slide_key), unit, scale, nd)} / {fmt(truth(d, scored_key), unit, scale, nd)}"


def speed_law_rows(title, d, target):
    """The slide of a speed-law run: path and mean speed, then the true force's
    RMS error and time in band, each over the whole slide / the scored window."""
    return [(title, "slid: path / mean speed, whole slide",
             f'{fmt(truth(d, "slide_path_m"), " m", 1, 3)} / {fmt(truth(d, "slide_mean_speed_mps"), " mm/s", 1000, 1)}'
             f' in {fmt(d.get("slide_duration_s"), " s", 1, 1)}', target),
            ("", "slid: path / mean speed, scored window (after the transients)",
             f'{fmt(truth(d, "path_length_m"), " m", 1, 3)} / {fmt(truth(d, "slide_speed_mps"), " mm/s", 1000, 1)}', ""),
            ("", "true force RMS error, whole slide / scored window",
             slide_and_scored(d, "slide_force_true_rms_error_n", "force_true_rms_error_n", " N"),
             "<= 0.5 N (scored window)"),
            ("", "true force within the band, whole slide / scored window",
             slide_and_scored(d, "slide_force_true_in_band_fraction", "force_true_in_band_fraction", " %", 100, 0),
             ">= 95 % (scored window)")]


def main():
    out = sys.argv[1]
    rows = []
    e = load(out, "edge_exploration")
    if e:
        rows.append(("Edge exploration (Fig. 10)", "alignment time (contact -> edge aligned)",
                     fmt(e["alignment_time_s"], " s"), "paper ~100 s; target < 5 s"))
        rows.append(("", "slid along the bar: whole slide / scored window (after the transient)",
                     slide_and_scored(e, "slide_path_m", "path_length_m", " m", 1, 3), ">= 0.15 m (whole slide)"))
        rows.append(("", "true force while sliding (mean / RMS error)",
                     f'{fmt(truth(e, "force_true_mean_n"), " N")} / {fmt(truth(e, "force_true_rms_error_n"), " N")}', "5 N desired"))
    p, b, n = load(out, "bent_bar"), load(out, "bent_bar_baseline"), load(out, "bent_bar_no_rotation")
    if p and b:
        rows.append(("Bent bar (Fig. 12)", "true force, proposed: mean / max / RMS error",
                     f'{fmt(truth(p, "force_true_mean_n"), " N")} / {fmt(truth(p, "force_true_max_n"), " N")} / '
                     f'{fmt(truth(p, "force_true_rms_error_n"), " N")}', "5 +- 1 N"))
        rows.append(("", "slide, proposed: mean speed, whole slide / scored window",
                     slide_and_scored(p, "slide_mean_speed_mps", "slide_speed_mps", " mm/s", 1000, 1),
                     ">= 10 mm/s (whole slide)"))
        rows.append(("", "true force, baseline (Li et al. 2013): mean / max / RMS error",
                     f'{fmt(truth(b, "force_true_mean_n"), " N")} / {fmt(truth(b, "force_true_max_n"), " N")} / '
                     f'{fmt(truth(b, "force_true_rms_error_n"), " N")} ({b["status"]})',
                     "paper: its baseline up to 50 N"))
    if p and n:
        rows.append(("", "true force, no_rotation ablation: max / RMS error",
                     f'{fmt(truth(n, "force_true_max_n"), " N")} / {fmt(truth(n, "force_true_rms_error_n"), " N")} ({n["status"]})',
                     "paper: its baseline up to 50 N"))
    sl, wl = load(out, "bent_bar_speed_law"), load(out, "wave_speed_law")
    if sl:
        rows += speed_law_rows("Bent bar, speed law", sl, ">= 40 mm/s (whole slide)")
    if wl:
        rows += speed_law_rows("Wave R 103 mm, careful speed law", wl, "")
    c = load(out, "co_manipulation")
    if c:
        rows.append(("Co-manipulation (Fig. 14)", "DZMP_y back within 0.5 mm after the move",
                     fmt(c["dzmp_recovery_time_s"], " s"), "< 5 s"))
        rows.append(("", "final DZMP_y / translation along x_s",
                     f'{fmt(c["dzmp_final_m"], " mm", 1000, 3)} / {fmt(c["translation_x_m"], " m", 1, 3)}', ""))
        rows.append(("", "true force mean / tray angle max",
                     f'{fmt(truth(c, "force_true_mean_n"), " N")} / {fmt(c["tray_angle_max_deg"], " deg")}', "6 N; bounded"))
    s = load(out, "sphere_table")
    if s:
        rows.append(("Sphere (point contact)", "true force mean / phases",
                     f'{fmt(truth(s, "force_true_mean_n"), " N")} / {[x["name"] for x in s["phases"]]}', "stays a point"))
    speed = [x for x in (e, p, b, n, sl, wl, c, s) if x]
    lines = ["| experiment | quantity | measured | paper / target |", "| --- | --- | --- | --- |"]
    lines += [f"| {a} | {q} | {m} | {t} |" for a, q, m, t in rows]
    lines.append("")
    lines.append("Whole slide: every servo cycle of the scored phases, transients included; scored window: the same "
                 "after each phase's transient (summary.json, docs/formats.md). Forces without a label: the scored "
                 "window.")
    lines.append("")
    timed = [x for x in speed if x.get("real_time_factor")]
    if timed:  # a deployment summarised by `tactile_sim summarize` has no wall time
        lines.append("Real-time factors: " + ", ".join(
            f'{x["scene"]}/{x["controller"]} {x["real_time_factor"]:.0f}x' for x in timed))
    else:
        lines.append("Runs of deployments (OCL deployer, tactile::SimClock): the runner's metrics from the "
                     "reporter's table (`tactile_sim summarize`); no wall-time figure.")
    text = "\n".join(lines)
    if any(x.get("fidelity", "").startswith("deployment") for x in speed):
        text += ("\n\nDeployment runs (deployer + OCL reporter): no ground truth; force and path are the measured "
                 "ones (taxels, the sensor's pose).")
    print(text)
    open(os.path.join(out, "report.md"), "w").write(text + "\n")
    print(f"\nplots: {out}/*/ (overview.png, fig10.png, fig12.png in bent_bar/, fig14.png, contacts.png, snapshots.png)")


if __name__ == "__main__":
    main()
