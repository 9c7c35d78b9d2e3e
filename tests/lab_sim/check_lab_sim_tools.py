#!/usr/bin/python3
"""ctest lab_sim_tools: checks of run_lab_sim_tools_test.sh's run (lab_sim on
the bring-up scene, KRC script "0:friOpen,1.0:friStart", against fri_check
holding the CMD entry pose and wts_read on lab_sim's PTY).

usage: check_lab_sim_tools.py OUT_DIR LAB_SIM_EXIT FRI_CHECK_EXIT WTS_READ_EXIT SCENE_YAML

  * packets flowed: fri_check took its 3000 packets (exit 0) and saw MON then
    CMD; lab_sim (stopped by SIGTERM: a clean exit, exit 0 = no protocol
    violation: MON echo, flags, non-finite command) had >= 2900 replies and
    applied commands in CMD;
  * frames arrived: wts_read read its 50 raw frames, each with taxels firing,
    all on the bar's row (row 3) -- the world's press, not a pattern;
  * in MON the arm did not move: the flange within 5 um of its start (the
    dynamic world settles 1.1 um from its quasi-static start balance) and the
    true force within 1 mN of its start over the whole MON second (the pad
    stays pressed: the KRC holds its own set point);
  * in CMD it followed fri_check's hold: no jump (largest step between
    applied commands <= 1 um: consecutive holds are equal up to the wire's
    float32), the first command equals the set point the KRC held
    (cmdCartPos, entry offset <= 1 um), the set point constant over the CMD
    rows and equal to the one of MON (10 um: float32 on the wire), so the pad
    stays pressed through the entry (force within 1 mN), and the flange
    stays where the impedance puts it: set point + F / K along z_g (Eq. 11,
    K = arm.k_trans) within 0.05 mm (the contact's moment couples a little
    rotation in);
  * the impedance law holds in MON too (flange = the KRC's set point + F / K).
"""
import csv
import re
import sys

import yaml

out, lab_rc, fri_rc, wts_rc, scene_file = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


scene = yaml.safe_load(open(scene_file))
k_trans = float(scene.get("arm", {}).get("k_trans", 1000.0))  # N/m, core/sim/lwr ArmParams default
BAR_ROW = 3

# --- fri_check ---------------------------------------------------------------
fc = open(f"{out}/fri_check.log").read()
check(fri_rc == 0, f"fri_check took its packets (exit {fri_rc})")
m = re.search(r"summary: cycles (\d+) received (\d+) replies (\d+) lost (\d+)", fc)
check(m is not None and int(m.group(1)) == 3000, "fri_check: 3000 packets accepted")
check(re.search(r"state MON", fc) is not None and re.search(r"state CMD", fc) is not None,
      "fri_check saw the KRC in MON, then in CMD")

# --- lab_sim -----------------------------------------------------------------
lab = open(f"{out}/lab_sim.log").read()
check(lab_rc == 0, f"lab_sim: clean exit, no protocol violation (exit {lab_rc})")
check("stopped by a signal" in lab, "lab_sim stopped on SIGTERM with its summary")
check(re.search(r"cycle \d+: friOpen -> KRC MON", lab) is not None and
      re.search(r"cycle 1000: friStart -> KRC CMD", lab) is not None, "lab_sim printed the state changes of its script")
m = re.search(r"KRC cycles (\d+) sent (\d+) replies (\d+) lost (\d+) .* applied (\d+)", lab)
s = re.search(r"max_step ([0-9.e+-]+) m ([0-9.e+-]+) rad .* max_entry_offset ([0-9.e+-]+) m ([0-9.e+-]+) rad", lab)
check(m is not None and s is not None, "lab_sim printed its statistics")
if m and s:
    cycles, sent, replies, lost, applied = (int(m.group(i)) for i in range(1, 6))
    step_m, step_rad, entry_m, entry_rad = (float(s.group(i)) for i in range(1, 5))
    check(replies >= 2900, f"replies {replies} of {sent} sent ({lost} lost)")
    check(applied >= 1500, f"commands applied in CMD: {applied}")
    check(step_m <= 1e-6 and step_rad <= 1e-5, f"no jump: largest applied step {step_m * 1e6:.3f} um {step_rad * 1e3:.4f} mrad")
    check(entry_m <= 1e-6 and entry_rad <= 1e-5,
          f"first command after entering CMD at the KRC's set point: {entry_m * 1e6:.3f} um {entry_rad * 1e3:.4f} mrad")
    print(f"measured: cycles {cycles}, replies {replies}, lost {lost}, applied {applied}")

# --- wts_read ------------------------------------------------------------------
check(wts_rc == 0, f"wts_read read its frames (exit {wts_rc})")
frames = [[float(v) for v in line.split(",")] for line in open(f"{out}/frames.csv") if line.strip()]
check(len(frames) == 50, f"50 raw frames from lab_sim's PTY ({len(frames)})")
cols = len(frames[0]) // 6 if frames else 14
firing = [[i for i, v in enumerate(f) if v > 0] for f in frames]
check(all(len(f) >= 3 for f in firing), f"taxels fire in every frame (at least {min(len(f) for f in firing) if firing else 0})")
check(all(i // cols == BAR_ROW for f in firing for i in f), f"every firing taxel on the bar's row {BAR_ROW}")

# --- the world's truth -----------------------------------------------------------
rows = list(csv.DictReader(open(f"{out}/truth.csv")))
check(len(rows) > 2000, f"truth rows at 1 ms: {len(rows)}")
mon = [r for r in rows if r["krc_state"] == "MON"]
cmd = [r for r in rows if r["krc_state"] == "CMD"]
check(len(mon) >= 900 and len(cmd) >= 1500, f"MON rows {len(mon)}, CMD rows {len(cmd)}")


def p(r, k):
    return [float(r[f"{k}_{a}"]) for a in "xyz"]


def dist(a, b):
    return sum((x - y) ** 2 for x, y in zip(a, b)) ** 0.5


if mon and cmd:
    f0 = float(mon[0]["force_true"])
    check(f0 > 1.0, f"the pad starts pressed: {f0:.3f} N")
    p0 = p(mon[0], "flange")
    move = max(dist(p(r, "flange"), p0) for r in mon)
    df = max(abs(float(r["force_true"]) - f0) for r in mon)
    check(move <= 5e-6, f"MON: the arm does not move (largest offset {move * 1e6:.3f} um)")
    check(df <= 1e-3, f"MON: the pad stays pressed (force within {df * 1e3:.3f} mN of {f0:.3f} N)")
    law_mon = max(abs(float(r["flange_z"]) - (float(r["setpoint_z"]) + float(r["force_true"]) / k_trans)) for r in mon)
    check(law_mon <= 5e-5, f"MON: flange = set point + F/K along z_g within {law_mon * 1e6:.1f} um")
    taken = [r for r in cmd if int(r["applied"]) > 1]  # rows stepped toward an applied command
    check(len(taken) >= 1000, f"CMD rows after the first command: {len(taken)}")
    if taken:
        sp_mon = p(mon[-1], "setpoint")
        sp_move = max(dist(p(r, "setpoint"), sp_mon) for r in taken)
        check(sp_move <= 1e-5, f"CMD: the set point is fri_check's hold of the KRC's set point (moves {sp_move * 1e6:.3f} um)")
        df_cmd = max(abs(float(r["force_true"]) - f0) for r in taken)
        check(df_cmd <= 1e-3, f"CMD: the pad stays pressed through the entry (force within {df_cmd * 1e3:.3f} mN)")
        law = max(abs(float(r["flange_z"]) - (float(r["setpoint_z"]) + float(r["force_true"]) / k_trans)) for r in taken)
        check(law <= 5e-5, f"CMD: the flange at the set point + F/K ({law * 1e6:.1f} um)")
        last = taken[-1]
        print(f"measured: true force {f0:.3f} N at the start, {float(last['force_true']):.3f} N at the end of CMD; "
              f"flange {dist(p(last, 'flange'), p0) * 1e6:.2f} um from its start, "
              f"{(float(last['flange_z']) - float(last['setpoint_z'])) * 1e3:.3f} mm above its set point")

print(f"lab_sim_tools: {len(failures)} check(s) failed" if failures else "lab_sim_tools: all checks passed")
sys.exit(1 if failures else 0)
