#!/usr/bin/python3
"""scripts/tools/lab_run_summary.py: a robot-path run's summary from lab_sim's
truth, on a run directory made here with known figures. The reporter's clock
runs 2 s behind lab_sim's (found again from the flange's 4 mm descent); the
servo explores from reporter time 1 s to 7 s, a 1 s transient, the true force
5 + 0.1 sin(2 pi t) N there, the flange sliding at 10 mm/s in contact:

  * the time offset 2 s, the scored window's true force max 5.1 N and mean
    5.0 N (the sine's), the slide's mean speed 10 mm/s, the slide 60 mm;
  * the verdict pass (state machine FINISHED, true force <= 7 N), the scene's
    criteria judged (a criterion on a figure the truth lacks: not judged);
  * a 7.5 N spike in `done`, inside the bridge's reply span: the whole run's
    maximum 7.5 N and the verdict fail, while the scored window's is unchanged;
    the same spike after the last reply (the deployment stopped): ignored;
  * deployer exit 255 (the state machine FAILED): fail.
Usage: test_lab_run_summary.py REPO_ROOT"""
import json
import math
import os
import subprocess
import sys
import tempfile

root = sys.argv[1]
tool = [sys.executable, os.path.join(root, "scripts", "tools", "lab_run_summary.py")]
failures = []
OFFSET = 2.0
# Tolerances: the rows are 10 ms apart (the windows' edges fall on a row), the
# sine is sampled at 100 Hz (its max within 0.1 N x (1 - cos(pi/100))).
TOL_T, TOL_F, TOL_V = 0.011, 1e-3, 2e-4


def check(what, ok):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def phase_at(tr):
    return "approach" if tr < 1.0 else ("explore" if tr < 7.0 else "done")


def make_run(d, spike_t=None):
    os.makedirs(os.path.join(d, "run"), exist_ok=True)
    with open(os.path.join(d, "truth.csv"), "w") as f:
        f.write("t,krc_state,krc_quality,krc_power,flange_x,flange_y,flange_z,force_true,in_contact\n")
        for k in range(1101):
            t = k * 0.01
            tr = t - OFFSET
            z = 0.400 - 0.004 * min(1.0, max(0.0, (tr - 0.2) / 0.6))
            ph = phase_at(tr)
            x = 0.5 + 0.01 * min(6.0, max(0.0, tr - 1.0))
            force = 5.0 + 0.1 * math.sin(2 * math.pi * tr) if ph == "explore" else 0.0
            if spike_t is not None and abs(t - spike_t) < 1e-9:
                force = 7.5
            f.write(f"{t:.2f},CMD,PERFECT,1,{x:.6f},0,{z:.6f},{force:.6f},{1 if ph == 'explore' else 0}\n")
    with open(os.path.join(d, "run", "report.dat"), "w") as f, open(os.path.join(d, "run", "timeseries.csv"), "w") as g:
        f.write("TimeStamp Robot.flange_pose.p.Element2\n")
        g.write("time,phase_name,sd_force\n")
        for k in range(801):
            tr = k * 0.01
            z = 0.400 - 0.004 * min(1.0, max(0.0, (tr - 0.2) / 0.6))
            f.write(f"{tr:.2f} {z:.6f}\n")
            g.write(f"{tr:.2f},{phase_at(tr)},{0.0028 if phase_at(tr) == 'explore' else 0.0}\n")
    with open(os.path.join(d, "run", "summary.json"), "w") as f:
        json.dump({"scene": "t", "status": "ok", "sim_time_s": 8.0, "dzmp_final_m": None}, f)
    with open(os.path.join(d, "lab_sim.log"), "w") as f:
        f.write("lab_sim: KRC first reply at t 2.000 s, last at t 10.000 s; between them sent 8000 lost 0\n"
                "lab_sim: KRC max_step 0.000100 m 0.000500 rad (between consecutive applied commands)\n")
    scene, prog = os.path.join(d, "scene.yaml"), os.path.join(d, "program.yaml")
    with open(scene, "w") as f:
        f.write("name: t\nmetrics:\n  transient_s: 1.0\n  force_phases: [explore]\n  force_band_n: 0.5\n"
                "  criteria:\n    force_true_max_n: {max: 6.0}\n    slide_mean_speed_mps: {min: 0.005}\n"
                "    dzmp_final_m: {max: 0.001}\n")
    with open(prog, "w") as f:
        f.write("controller: {c_z: 0.00056}\nphases:\n  - {name: approach, requires_contact: false}\n"
                "  - {name: explore, s_d: {force: 5.0}}\n  - {name: done, terminal: true}\n")
    return scene, prog


def summarize(d, exit_code=0, spike_t=None):
    scene, prog = make_run(d, spike_t)
    p = subprocess.run(tool + [d, "--scene", scene, "--program", prog, "--deployer-exit", str(exit_code)],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        print(p.stdout, p.stderr)
        return None
    return json.load(open(os.path.join(d, "summary.json")))


with tempfile.TemporaryDirectory() as tmp:
    s = summarize(os.path.join(tmp, "ok"))
    check("the tool ran", s is not None)
    if s:
        check(f"time offset {s['truth_time_offset_s']} s = {OFFSET} s", abs(s["truth_time_offset_s"] - OFFSET) <= TOL_T)
        check(f"scored true force max {s['force_true_max_n']:.4f} N = 5.1 N",
              abs(s["force_true_max_n"] - 5.1) <= TOL_F)
        check(f"scored true force mean {s['force_true_mean_n']:.4f} N = 5.0 N", abs(s["force_true_mean_n"] - 5.0) <= 0.01)
        check(f"slide mean speed {s['slide_mean_speed_mps'] * 1e3:.3f} mm/s = 10 mm/s",
              abs(s["slide_mean_speed_mps"] - 0.01) <= TOL_V)
        check(f"slide path {s['slide_path_m'] * 1e3:.2f} mm = 60 mm (+- one row)", abs(s["slide_path_m"] - 0.06) <= 1.1e-4)
        check(f"whole-run max {s['force_true_run_max_n']:.4f} N", abs(s["force_true_run_max_n"] - 5.1) <= TOL_F)
        check("verdict pass, criteria passed, dzmp_final_m not judged",
              s["robot_verdict"] == "pass" and s["criteria_passed"] and s["criteria_not_judged"] == ["dzmp_final_m"])
        check("truth.png written", os.path.getsize(os.path.join(tmp, "ok", "truth.png")) > 0)
    s = summarize(os.path.join(tmp, "spike"), spike_t=9.5)
    check("a 7.5 N spike in done within the replies: run max 7.5 N, verdict fail, scored max unchanged",
          s is not None and abs(s["force_true_run_max_n"] - 7.5) < 1e-9 and s["robot_verdict"] == "fail"
          and abs(s["force_true_max_n"] - 5.1) <= TOL_F)
    s = summarize(os.path.join(tmp, "late"), spike_t=10.5)
    check("the spike after the bridge's last reply: ignored, pass",
          s is not None and abs(s["force_true_run_max_n"] - 5.1) <= TOL_F and s["robot_verdict"] == "pass")
    s = summarize(os.path.join(tmp, "failed"), exit_code=255)
    check("deployer exit 255: fail", s is not None and s["robot_verdict"] == "fail" and s["deployer_exit"] == 255)
print(f"test_lab_run_summary: {len(failures)} failed" if failures else "test_lab_run_summary: all passed")
sys.exit(1 if failures else 0)
