#!/usr/bin/python3
"""scripts/tools/deployment_to_run.py: a deployment's reporter table to the
runner's summary form, on synthetic tables whose figures are known exactly:
the whole slide beside the scored window (the runner's windows,
tests/runner/test_metrics.cpp), and a run that stopped on a fault (its status
and time). Also results_docs.py's tables from a results.json without the
slide's figures (an em dash). Usage: test_deployment_to_run.py REPO_ROOT"""
import json
import math
import os
import subprocess
import sys
import tempfile

root = sys.argv[1]
tool = [sys.executable, os.path.join(root, "scripts", "tools", "deployment_to_run.py")]
failures = []
# The table keeps what the generator writes (repr floats): sums of a few
# hundred 1 mm / 10 ms steps are exact to ~1e-12; asserted to 1e-9.
TOL = 1e-9
ROW = 0.01      # s between the reporter's rows
SPEED = 0.1     # m/s: the flange's slide along x in contact
SET_POINT = 5.0
OFF = 7.0       # N: outside the scene's 0.5 N band

PROGRAM = """controller: {c_z: 0.001}
phases:
  - {name: approach, requires_contact: false}
  - {name: explore, s_d: {force: 5.0}}
  - {name: end_check, s_d: {force: 5.0}}
  - {name: done, terminal: true, requires_contact: false}
"""
SCENE = """name: synthetic
metrics: {transient_s: 2.0, force_phases: [explore], force_band_n: 0.5}
"""
FEATURES = ("cop_x", "cop_y", "coc_x", "coc_y", "dzmp_x", "dzmp_y", "alpha_z", "force", "d_z", "lambda1", "lambda2",
            "area")
HEAD = (["TimeStamp", "Servo.phase.time_s", "Servo.phase.index", "Servo.phase.status"]
        + [f"Servo.pose_command.pose.p.Element{k}" for k in range(3)]
        + [f"Servo.pose_command.pose.q.Element{k}" for k in range(4)]
        + [f"Robot.flange_pose.p.Element{k}" for k in range(3)]
        + [f"Robot.flange_pose.q.Element{k}" for k in range(4)]
        + [f"Features.features.{k}" for k in FEATURES] + ["Features.features.contact", "Features.features.status"])


def check(what, ok):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def near(a, b, tol=TOL):
    return a is not None and b is not None and abs(a - b) <= tol


def table(segments, status_from=None):
    """Reporter lines every 10 ms from t = 0: segments (phase index, until s, force N); the flange slides
    at SPEED along x from the first row out of approach; from `status_from` (phase, t) the servo's status."""
    lines, k, x, touched = [" ".join(HEAD)], 0, 0.0, False
    for phase, until, force in segments:
        while ROW * k < until - 1e-9:
            t = ROW * k
            contact = phase != 0
            if contact:
                x += SPEED * ROW if touched else 0.0
                touched = True
            status = status_from[0] if status_from and t >= status_from[1] - 1e-9 else "ok"
            pose = [0.5 + x, 0.0, 0.4, 0.0, 0.0, 0.0, 1.0]
            feats = [0.0] * 7 + [force if contact else 0.0] + [0.0] * 4
            row = [t, 1000.0 + t, phase, status] + pose + pose + feats + ["edge" if contact else "none", "ok"]
            lines.append(" ".join(repr(v) if isinstance(v, float) else str(v) for v in row))
            k += 1
    return "\n".join(lines) + "\n"


def convert(d, name, segments, *extra, status_from=None):
    report = os.path.join(d, name + ".dat")
    with open(report, "w") as f:
        f.write(table(segments, status_from))
    out = os.path.join(d, name)
    p = subprocess.run(tool + [report, out, "--program", os.path.join(d, "program.yaml"),
                               "--scene", os.path.join(d, "scene.yaml"), "--source", "robot"] + list(extra),
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    check(f"{name}: converted (exit {p.returncode}) {p.stderr.strip()}", p.returncode == 0)
    return json.load(open(os.path.join(out, "summary.json"))) if p.returncode == 0 else {}


with tempfile.TemporaryDirectory() as d:
    with open(os.path.join(d, "program.yaml"), "w") as f:
        f.write(PROGRAM)
    with open(os.path.join(d, "scene.yaml"), "w") as f:
        f.write(SCENE)

    # 1 s approach, 5 s explore (its first 0.5 s at 7 N), done: the slide is explore's 500 rows
    # (499 steps of 1 mm in 4.99 s, 50 rows out of the band); the scored window its last 300 rows.
    s = convert(d, "slide", [(0, 1.0, 0.0), (1, 1.5, OFF), (1, 6.0, SET_POINT), (3, 6.5, SET_POINT)])
    check("the whole slide: 0.499 m in 4.99 s at 0.1 m/s (the sensor's path)",
          near(s.get("sensor_slide_path_m"), 0.499) and near(s.get("slide_duration_s"), 4.99)
          and near(s.get("sensor_slide_mean_speed_mps"), SPEED))
    check("the whole slide's measured force: mean 5.2 N, RMS error sqrt(0.4) N, 90 % in band, max 7 N",
          near(s.get("slide_force_measured_mean_n"), 5.2) and near(s.get("slide_force_measured_rms_error_n"),
                                                                    math.sqrt(0.4))
          and near(s.get("slide_force_measured_in_band_fraction"), 0.9)
          and near(s.get("slide_force_measured_max_n"), OFF))
    check("the scored window: 0.299 m in 2.99 s at 0.1 m/s, the force on its set point",
          near(s.get("sensor_scored_path_m"), 0.299) and near(s.get("scored_duration_s"), 2.99)
          and near(s.get("sensor_scored_mean_speed_mps"), SPEED) and near(s.get("sensor_path_length_m"), 0.299)
          and near(s.get("force_measured_rms_error_n"), 0.0) and near(s.get("force_measured_in_band_fraction"), 1.0))
    check("no ground truth in a deployment: the truth keys are null",
          all(k in s and s[k] is None for k in ("slide_path_m", "slide_mean_speed_mps", "scored_path_m",
                                                 "slide_force_true_rms_error_n", "force_true_mean_n")))
    check("an ok run: status ok, no fault time", s.get("status") == "ok" and "fault_time_s" in s
          and s["fault_time_s"] is None)

    # A detour (end_check, back to explore within the transient) belongs to the slide and
    # the scored window; the final check does not (the runner's rule).
    s = convert(d, "detour", [(0, 1.0, 0.0), (1, 2.5, SET_POINT), (2, 2.6, OFF), (1, 4.0, SET_POINT),
                              (2, 4.3, OFF), (3, 4.5, SET_POINT)])
    check("a detour: the slide 0.299 m in 2.99 s with its 10 rows out of the band, the scored window 0.099 m",
          near(s.get("sensor_slide_path_m"), 0.299) and near(s.get("slide_duration_s"), 2.99)
          and near(s.get("slide_force_measured_in_band_fraction"), 290 / 300)
          and near(s.get("sensor_scored_path_m"), 0.099) and near(s.get("force_measured_in_band_fraction"), 1.0))

    # A servo watchdog from t = 4 s: the table up to the end, the fault named with its time.
    s = convert(d, "fault", [(0, 1.0, 0.0), (1, 5.0, SET_POINT)], "--deployer-exit", "255",
                "--verdict", "FAILED: the state machine X ended in FAILED", status_from=("force_mismatch", 4.0))
    check("a watchdog: status servo_force_mismatch at 4 s, the table to its end (4.99 s)",
          s.get("status") == "servo_force_mismatch" and near(s.get("fault_time_s"), 4.0)
          and near(s.get("sim_time_s"), 4.99))
    # A failed run without a servo fault (the state machine's own: no contact): experiment_failed at the
    # entry of the phase the run ended in; a failed deployment step: deployment_failed.
    segs = [(0, 1.0, 0.0), (1, 3.0, SET_POINT), (3, 3.5, SET_POINT)]
    s = convert(d, "failed_run", segs, "--deployer-exit", "255", "--verdict",
                "FAILED: the state machine X ended in FAILED")
    check("a failed run: experiment_failed at 3 s, the verdict kept",
          s.get("status") == "experiment_failed" and near(s.get("fault_time_s"), 3.0)
          and s.get("verdict", "").startswith("FAILED: the state machine"))
    s = convert(d, "failed_step", segs, "--deployer-exit", "255", "--verdict",
                "FAILED: deployment step failed: stop Reporter")
    check("a failed step: deployment_failed", s.get("status") == "deployment_failed")

# results_docs.py renders a results.json whose runs lack the slide's figures: an em dash for them.
sys.dont_write_bytecode = True
sys.path.insert(0, os.path.join(root, "scripts", "tools"))
import results_docs  # noqa: E402

res = json.load(open(os.path.join(root, "docs", "results", "results.json")))
for group in ("runs", "deploy"):
    for r in res[group].values():
        for k in list(r):
            if k.startswith("slide_") and k != "slide_speed_mps":
                del r[k]
text = results_docs.render_summary(res)
line = next((ln for ln in text.splitlines() if "slid along the bar" in ln), "")
check(f"the README's table without the slide's figures: an em dash ({line.strip()})", "| \u2014 / " in line)
res["runs"]["edge_exploration"]["slide_path_m"] = 0.1914
line = next((ln for ln in results_docs.render_summary(res).splitlines() if "slid along the bar" in ln), "")
check(f"... and the whole slide beside the scored window when it has them ({line.strip()})", "| 0.191 / " in line)
sys.exit(1 if failures else 0)
