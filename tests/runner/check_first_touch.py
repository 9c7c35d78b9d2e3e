#!/usr/bin/python3
"""ctests FirstTouch_*: a `tactile_sim run` of params/scenes/first_touch.yaml
(params/programs/first_touch.yaml) against what the first touch on
the real arm promises (docs/bringup.md, step 5).

usage: check_first_touch.py RUN_DIR PROGRAM_YAML touch|no_object

Every run (from RUN_DIR/summary.json and timeseries.csv, one row per servo cycle):
  * the commanded translation speed of the pad never above the program's
    safety.max_trans_speed, its rotation speed never above max_rot_speed_deg
    (consecutive commands; the servo limits the step at the sensor origin);
  * the commanded and the measured flange position never outside the
    program's safety.workspace box;
  * the true contact force (the simulator's) never above safety.force_ceiling;
  * the run ended by the program (status ok, the last phase terminal).
touch: the phases approach, hold, done (touched, held, ended in done
holding), the scene's criteria passed (2 +- 0.5 N while holding), and the
pad still pressing at the end (held, not backed off).
no_object: the phases approach, no_contact, no force at all, and the
approach stopped at the workspace box's floor (the flange's lowest point
within 1 mm of it) rather than running on.

Tolerances: the CSV holds 9 significant digits (1e-9 m at 1 m), so positions
compare within 1e-8 m and speeds within 1e-8 m per 10 ms step (1e-6 m/s);
rotations within 1e-7 rad per step (the rpy angles' rounding); the box
within 1e-6 m (the servo clips the flange there exactly; the sensor pose is
logged and the flange recomputed through the 30 mm mount).
"""
import csv
import json
import math
import sys

import numpy as np
import yaml
import os

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "tools"))
import program_yaml  # noqa: E402  (a program as the servo merges it: tactile_sim program)

run_dir, program_file, mode = sys.argv[1:4]
summary = json.load(open(f"{run_dir}/summary.json"))
rows = list(csv.DictReader(open(f"{run_dir}/timeseries.csv")))
prog = program_yaml.load(program_file)
safety = prog["safety"]
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def col(name):
    return np.array([float(r[name]) for r in rows])


def rpy_matrix(r, p, y):
    """{g}R from roll, pitch, yaw (KDL's RPY: Rz(y) Ry(p) Rx(r))."""
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


t = col("time")
check(len(rows) > 100, f"{len(rows)} servo cycles logged")
phases = [p["name"] for p in summary["phases"]]
terminal = {p["name"] for p in prog["phases"] if p.get("terminal")}
check(summary["status"] == "ok", f"status ok ({summary['status']}, exit code {summary['exit_code']})")
check(bool(phases) and phases[-1] in terminal, f"ended in a terminal phase ({phases})")

# Speeds of the commanded pad pose, cycle to cycle.
cmd = np.stack([col("cmd_x"), col("cmd_y"), col("cmd_z")], axis=1)
rpy = np.stack([col("cmd_roll"), col("cmd_pitch"), col("cmd_yaw")], axis=1)
dt = np.diff(t)
check(bool(np.all(dt > 0)), f"time increases (servo period {np.median(dt):.4f} s)")
step = np.linalg.norm(np.diff(cmd, axis=0), axis=1)
v_max = float(safety["max_trans_speed"])
worst = float(np.max(step - v_max * dt))
check(worst <= 1e-8, f"commanded speed <= {v_max} m/s: largest {float(np.max(step / dt)):.6f} m/s "
      f"(largest step beyond the limit {worst:.2e} m)")
R = [rpy_matrix(*a) for a in rpy]
ang = np.array([math.acos(max(-1.0, min(1.0, (np.trace(R[k].T @ R[k + 1]) - 1.0) / 2.0))) for k in range(len(R) - 1)])
w_max = math.radians(float(safety["max_rot_speed_deg"]))
check(float(np.max(ang - w_max * dt)) <= 1e-7,
      f"commanded rotation speed <= {safety['max_rot_speed_deg']} deg/s: largest {math.degrees(float(np.max(ang / dt))):.4f} deg/s")

# The flange (commanded and measured) inside the box: {g}p{e} = {g}p{s} - {g}R{s} {e}p{s}
# (the mount is a pure offset along z: sensor_mount rpy 0).
mount = prog["controller"]["sensor_mount"]
assert all(abs(a) < 1e-12 for a in mount["rpy_deg"]), "the check assumes a mount without rotation"
off = np.array(mount["xyz"], dtype=float)
lo = np.array(safety["workspace"]["min"], dtype=float)
hi = np.array(safety["workspace"]["max"], dtype=float)
act = np.stack([col("act_x"), col("act_y"), col("act_z")], axis=1)
act_rpy = np.stack([col("act_roll"), col("act_pitch"), col("act_yaw")], axis=1)
flange_cmd = np.array([p - R[k] @ off for k, p in enumerate(cmd)])
flange_act = np.array([p - rpy_matrix(*act_rpy[k]) @ off for k, p in enumerate(act)])
for name, f in (("commanded", flange_cmd), ("measured", flange_act)):
    out = np.maximum(lo - f, f - hi).max()
    check(out <= 1e-6, f"{name} flange inside the workspace box {lo.tolist()} .. {hi.tolist()} "
          f"(largest excursion {out * 1000:.4f} mm; z range {f[:, 2].min():.4f} .. {f[:, 2].max():.4f} m)")

f_true = col("force_true")
ceiling = float(safety["force_ceiling"])
check(float(f_true.max()) <= ceiling, f"true force <= the {ceiling} N ceiling (max {f_true.max():.3f} N)")

if mode == "touch":
    check(phases == ["approach", "hold", "done"], f"approach, hold, done ({phases})")
    check(summary["criteria_passed"], f"the scene's criteria ({summary['criteria_failed']})")
    check(float(f_true.max()) > 0.5, f"touched: the true force reached {f_true.max():.3f} N")
    names = [r["phase_name"] for r in rows]
    last = [k for k, n in enumerate(names) if n == "done"]
    check(bool(last) and f_true[last[-1]] > 1.0,
          f"holding at the end: true force {f_true[last[-1]] if last else float('nan'):.3f} N in done")
    tin = [p["t_enter"] for p in summary["phases"]]
    num = {k: float("nan") if summary[k] is None else summary[k]
           for k in ("force_true_mean_n", "force_true_max_n", "force_true_rms_error_n")}
    print(f"     phases entered at {tin} s; true force while holding (after the transient): "
          f"mean {num['force_true_mean_n']:.3f} N, max {num['force_true_max_n']:.3f} N, "
          f"RMS error {num['force_true_rms_error_n']:.3f} N")
elif mode == "no_object":
    check(phases == ["approach", "no_contact"], f"approach, no_contact ({phases})")
    check(float(np.abs(f_true).max()) == 0.0, f"no force at all (max {np.abs(f_true).max():.3g} N)")
    check(abs(float(flange_act[:, 2].min()) - lo[2]) <= 1e-3,
          f"the approach stopped at the box's floor z {lo[2]} m (lowest measured flange z {flange_act[:, 2].min():.5f} m)")
else:
    sys.exit(f"check_first_touch.py: mode must be touch or no_object, not {mode}")

print(f"check_first_touch: {len(failures)} failed")
sys.exit(1 if failures else 0)
