#!/usr/bin/python3
"""Checks and report of the first day's rehearsal (scripts/rehearse_first_day.sh).

usage: rehearsal_report.py check STEP_DIR [--fri-yaml FILE] [--dry-run] [--start S] [--max-force N]
       rehearsal_report.py report OUT_DIR

check: one robot step against the simulated lab's ground truth (lab_sim's
truth.csv: the world's flange pose and the KRC's state, never seen by the
controller), the run's timeseries.csv (run_robot.sh) and lab_sim's summary
(lab_sim.log). Prints PASS/FAIL per check; exit 1 when one failed.
  * the deployment was up before friStart: the servo reported
    waiting_for_robot (the KRC in monitor mode) before it moved the arm;
  * while the arm cannot be commanded (not in CMD at quality >= OK with the
    drives on) it stays where it was: within HELD_M of the pose at the start
    of that interval;
  * within 1 s of each entry into command mode it moves again by more than
    FOLLOW_M (not in a dry run: there it never moves by more than HELD_M);
    a later entry (the link's quality dropped and came back) while the
    servo holds (the KRC's set point moves by at most FOLLOW_M in that
    second) passes when the KRC applies commands again;
  * the KRC never applied two consecutive commands further apart than one
    limited step of the bridge (fri.yaml max_lin_speed x the KRC's cycle);
  * --dry-run: the servo's commands moved away from the held arm (more than
    DRY_CMD_M): it computed as if the arm followed;
  * the KRC never stopped the arm ($STIFFNESS.MAXFORCE / CPMAXDELTA: lab_sim's
    "fault none"), and lab_sim's KRC link line (answers missed / late, the
    quality drops, the measurements at each quality) is shown;
  * --max-force: the true contact force never exceeded it.
--fri-yaml: the fri.yaml the step's bridge read (its cycle_time_s and
max_lin_speed give the largest step; default the repository's).
report: OUT_DIR/steps.txt (the shell's verdicts) -> OUT_DIR/rehearsal.md and
OUT_DIR/rehearsal.png (the experiment step: the KRC's state, the true force
and the arm's path over time).
"""
import argparse
import csv
import math
import os
import re
import sys

HELD_M = 2e-4     # m: a held arm settles on its set point by less (impedance, a pressing contact's creep)
FOLLOW_M = 5e-4   # m: 1 s of the slowest program's motion (first touch, 5 mm/s) is 5 mm
DRY_CMD_M = 1e-4  # m: a dry run's commands move at least this far from the held arm
FLOAT_M = 2e-7    # m: the wire's float positions


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def commandable(row):
    return (row["krc_open"] == "1" and row["krc_state"] == "CMD" and row["krc_quality"] in ("OK", "PERFECT")
            and row["krc_power"] == "1")


def pos(row):
    return (float(row["flange_x"]), float(row["flange_y"]), float(row["flange_z"]))


def dist(a, b):
    return math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)))


def intervals(rows):
    """(t0, t1, commandable) runs of the truth rows."""
    out = []
    for r in rows:
        c = commandable(r)
        t = float(r["t"])
        if out and out[-1][2] == c:
            out[-1][1] = t
        else:
            out.append([t, t, c])
    return out


def holding_entry(rows, t):
    """(commands applied, the set point's motion) in the 1 s after an entry into command mode at t
    that is not the first and whose applied set point moved by at most FOLLOW_M (the servo holding,
    e.g. in contact: a re-entry after the link's quality dropped); None otherwise or without the
    columns (truth.csv of lab_sim: applied, setpoint_*)."""
    if not rows or "applied" not in rows[0] or "setpoint_x" not in rows[0]:
        return None
    window = [r for r in rows if t <= float(r["t"]) <= t + 1.0]
    before = [r for r in rows if float(r["t"]) < t]
    if not window or not before or int(before[-1]["applied"]) == 0:
        return None  # the first entry: the arm must move
    sp = [(float(r["setpoint_x"]), float(r["setpoint_y"]), float(r["setpoint_z"])) for r in window]
    s_moved = max(dist(p, sp[0]) for p in sp)
    if s_moved > FOLLOW_M:
        return None
    return int(window[-1]["applied"]) - int(before[-1]["applied"]), s_moved


def fri_step_limit(fri_yaml):
    text = open(fri_yaml).read()
    v = float(re.search(r"^\s*max_lin_speed:\s*([0-9.eE+-]+)", text, re.M).group(1))
    cycle = float(re.search(r"^\s*cycle_time_s:\s*([0-9.eE+-]+)", text, re.M).group(1))
    return v * cycle + FLOAT_M


def check(args):
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    d = args.step_dir
    fails = []

    def verdict(ok, what):
        print(f"   {'PASS' if ok else 'FAIL'}: {what}")
        if not ok:
            fails.append(what)

    rows = read_csv(os.path.join(d, "truth.csv"))
    if not rows:
        print(f"   FAIL: {d}/truth.csv has no rows")
        return 1
    runs = intervals(rows)
    by_t = [(float(r["t"]), pos(r)) for r in rows]

    def pos_at(t):
        for tt, p in by_t:
            if tt >= t - 1e-9:
                return p
        return by_t[-1][1]

    # Held while not commandable.
    worst_held = 0.0
    for t0, t1, c in runs:
        if c and not args.dry_run:
            continue
        p0 = pos_at(t0)
        worst_held = max([worst_held] + [dist(p, p0) for tt, p in by_t if t0 <= tt <= t1])
    verdict(worst_held <= HELD_M, f"the arm held while it could not be commanded: moved at most {worst_held * 1e3:.3f} mm "
            f"(<= {HELD_M * 1e3:.1f} mm)")
    # Followed within 1 s of each entry into command mode.
    if not args.dry_run:
        entries = [t0 for t0, t1, c in runs if c and t0 > 0.0]
        for t in entries:
            p0 = pos_at(t)
            moved = max([0.0] + [dist(p, p0) for tt, p in by_t if t <= tt <= t + 1.0])
            held = holding_entry(rows, t)
            if held is not None:  # a re-entry after a drop of the link, the servo holding: nothing to follow
                verdict(held[0] > 0, f"command mode at t {t:.2f} s, the servo holding (the KRC's set point moved "
                        f"{held[1] * 1e3:.2f} mm in 1 s, <= {FOLLOW_M * 1e3:.1f} mm): {held[0]} commands applied")
                continue
            verdict(moved > FOLLOW_M, f"the arm followed within 1 s of command mode at t {t:.2f} s: {moved * 1e3:.2f} mm "
                    f"(> {FOLLOW_M * 1e3:.1f} mm)")
        verdict(bool(entries), f"the KRC entered command mode ({len(entries)} time(s))")
        if args.start is not None and entries:
            # The KRC enters command mode at friStart only at PERFECT quality: a link the load
            # degraded delays the entry to the first PERFECT after the scripted time (an event,
            # not a window). Never before the script's friStart.
            e = entries[0]
            held = [r for r in rows if args.start <= float(r["t"]) < e - 0.05]
            perfect_before = [float(r["t"]) for r in held if r["krc_quality"] == "PERFECT"]
            verdict(e >= args.start - 0.05 and (e - args.start < 0.05 or not perfect_before),
                    f"the first friStart at {e:.2f} s as scripted ({args.start} s) or at the first PERFECT "
                    f"quality after it (PERFECT while still in monitor mode at: "
                    f"{', '.join('%.2f' % t for t in perfect_before[:3]) or 'never'})")
    # The KRC's largest applied step.
    log = open(os.path.join(d, "lab_sim.log")).read()
    m = re.search(r"KRC max_step ([0-9.eE+-]+) m", log)
    limit = fri_step_limit(args.fri_yaml or os.path.join(root, "params/sensors/fri.yaml"))
    verdict(m is not None and float(m.group(1)) <= limit,
            f"the KRC's largest step between applied commands {m.group(1) if m else '?'} m (<= {limit:.7f} m)")
    # The KRC's own stop and its rating of the link.
    m = re.search(r"KRC link answers missed (\d+) late (\d+).*quality drops out of CMD (\d+); (measurements[^;]*); fault (\w+)", log)
    if m:
        print(f"   KRC link: answers missed {m.group(1)}, late {m.group(2)}; quality drops out of command mode {m.group(3)}; "
              f"{m.group(4)}")
    verdict(m is not None and m.group(5) == "none",
            f"the KRC never stopped the arm ($STIFFNESS.MAXFORCE / CPMAXDELTA): fault {m.group(5) if m else '?'}")
    # The run's own table.
    ts_path = os.path.join(d, "run", "timeseries.csv")
    ts = read_csv(ts_path) if os.path.exists(ts_path) else []
    verdict(bool(ts), f"the run's table {ts_path}")
    if ts and not args.dry_run:  # (a dry run computes in monitor mode too)
        waited = sum(1 for r in ts if r["servo_status"] in ("waiting_for_robot", "8"))
        verdict(waited > 0, f"the servo waited for the robot (waiting_for_robot in {waited} rows): the deployment was up "
                "in monitor mode")
    if ts and args.dry_run:
        commanding = [r for r in ts if r["servo_status"] not in ("waiting_for_pose", "6", "not_configured", "12")]
        apart = max([0.0] + [dist((float(r["cmd_x"]), float(r["cmd_y"]), float(r["cmd_z"])),
                                  (float(r["act_x"]), float(r["act_y"]), float(r["act_z"]))) for r in commanding])
        if True:
            verdict(apart > DRY_CMD_M, f"the dry run's commands moved {apart * 1e3:.3f} mm from the held arm "
                    f"(> {DRY_CMD_M * 1e3:.1f} mm): the servo computed")
    if args.target_force is not None:
        # The true force while commandable and in contact, 3 s after the touch (align and edge control settled).
        t_touch = next((float(r["t"]) for r in rows if r["in_contact"] == "1"), None)
        f = [float(r["force_true"]) for r in rows
             if t_touch is not None and float(r["t"]) > t_touch + 3.0 and r["in_contact"] == "1" and commandable(r)]
        if f:
            mean = sum(f) / len(f)
            rms = math.sqrt(sum((x - args.target_force) ** 2 for x in f) / len(f))
            verdict(rms <= args.force_rms, f"the true force while sliding: mean {mean:.2f} N, RMS error {rms:.2f} N against "
                    f"{args.target_force} N (<= {args.force_rms} N) over {len(f)} samples")
        else:
            verdict(False, "the true force while sliding: no contact")
    if args.max_force is not None:
        fmax = max(float(r["force_true"]) for r in rows)
        verdict(fmax <= args.max_force, f"the true force at most {fmax:.2f} N (<= {args.max_force} N)")
    return 1 if fails else 0


def report(args):
    out = args.out_dir
    steps = []
    with open(os.path.join(out, "steps.txt")) as f:
        for line in f:
            if line.strip():
                n, title, v, why = (line.rstrip("\n").split("|") + ["", "", "", ""])[:4]
                steps.append((n, title, v, why))
    lines = ["# First day, rehearsed against the simulated lab", "",
             "Generated by scripts/rehearse_first_day.sh (docs/bringup.md).", "",
             "| step | | result | |", "|---|---|---|---|"]
    for n, title, v, why in steps:
        lines.append(f"| {n} | {title} | {v} | {why} |")
    exp = os.path.join(out, "6_edge_exploration")
    if os.path.exists(os.path.join(exp, "truth.csv")):
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        rows = read_csv(os.path.join(exp, "truth.csv"))
        t = [float(r["t"]) for r in rows]
        fig, ax = plt.subplots(3, 1, figsize=(9, 7), sharex=True)
        for t0, t1, c in intervals(rows):
            for a in ax:
                if not c:
                    a.axvspan(t0, t1, color="0.85", lw=0)
        state = [3 if commandable(r) else (2 if r["krc_state"] == "CMD" else (1 if r["krc_state"] == "MON" else 0))
                 for r in rows]
        ax[0].step(t, state, where="post")
        ax[0].set_yticks([0, 1, 2, 3], ["closed / OFF", "MON", "CMD, quality\n< OK or drives off", "CMD, commandable"])
        ax[0].set_title("The KRC (grey: the arm cannot be commanded, the servo waits)")
        ax[1].plot(t, [float(r["force_true"]) for r in rows])
        ax[1].set_ylabel("true force (N)")
        p0 = pos(rows[0])
        ax[2].plot(t, [1e3 * dist(pos(r), p0) for r in rows])
        ax[2].set_ylabel("flange from start (mm)")
        ax[2].set_xlabel("lab time (s)")
        fig.tight_layout()
        fig.savefig(os.path.join(out, "rehearsal.png"), dpi=90)
        lines += ["", "![the experiment step](rehearsal.png)"]
    with open(os.path.join(out, "rehearsal.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    c = sub.add_parser("check")
    c.add_argument("step_dir")
    c.add_argument("--dry-run", action="store_true")
    c.add_argument("--fri-yaml", default=None)
    c.add_argument("--start", type=float, default=None)
    c.add_argument("--max-force", type=float, default=None)
    c.add_argument("--target-force", type=float, default=None)
    c.add_argument("--force-rms", type=float, default=0.5)
    r = sub.add_parser("report")
    r.add_argument("out_dir")
    a = ap.parse_args()
    return check(a) if a.cmd == "check" else report(a)


if __name__ == "__main__":
    sys.exit(main())
