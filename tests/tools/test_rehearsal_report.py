#!/usr/bin/python3
"""scripts/tools/rehearsal_report.py check: the first entry into command mode
against the script's friStart. The KRC enters command mode only at PERFECT
quality, so an entry after the scripted time passes when the quality stayed
below PERFECT until then, and fails when the KRC was PERFECT in monitor mode
and still did not enter; an entry before friStart fails. Each case is a
synthetic step folder (truth.csv, lab_sim.log). Then the follow check on a
re-entry into command mode. Usage: test_rehearsal_report.py REPO_ROOT"""
import os
import subprocess
import sys
import tempfile

TOOL = os.path.join(sys.argv[1], "scripts", "tools", "rehearsal_report.py")
HEADER = "t,krc_open,krc_state,krc_quality,krc_power,flange_x,flange_y,flange_z,in_contact,force_true"
results = []


def step_dir(rows):
    """A step folder whose truth.csv has one row every 10 ms: (t, state, quality)."""
    d = tempfile.mkdtemp(prefix="rehearsal_report_")
    with open(os.path.join(d, "truth.csv"), "w") as f:
        f.write(HEADER + "\n")
        for t, state, quality in rows:
            f.write(f"{t:.3f},1,{state},{quality},1,0.7,0,{0.4 - (0.001 * t if state == 'CMD' else 0):.6f},0,0\n")
    with open(os.path.join(d, "lab_sim.log"), "w") as f:
        f.write("KRC max_step 0.0001 m\n")
    return d


def timeline(entry, quality_before):
    """MON until `entry` s (quality_before from 5.5 s on), CMD at PERFECT after it, 8 s long."""
    rows = []
    for k in range(800):
        t = 0.01 * k
        if t < entry:
            rows.append((t, "MON", quality_before if t >= 5.5 else "UNACCEPTABLE"))
        else:
            rows.append((t, "CMD", "PERFECT"))
    return rows


def fri_start_line(rows):
    done = subprocess.run([sys.executable, TOOL, "check", step_dir(rows), "--start", "6"],
                          capture_output=True, text=True)
    lines = [ln for ln in done.stdout.splitlines() if "the first friStart" in ln]
    return lines[0].strip() if lines else "(no friStart line) " + done.stdout + done.stderr


for what, rows, want in [
        ("entry at the scripted 6.0 s", timeline(6.0, "PERFECT"), "PASS"),
        ("entry at 6.47 s, the quality OK (below PERFECT) until then", timeline(6.47, "OK"), "PASS"),
        ("entry at 6.47 s although PERFECT in monitor mode from 5.5 s", timeline(6.47, "PERFECT"), "FAIL"),
        ("entry at 5.5 s, before the script's friStart", timeline(5.5, "PERFECT"), "FAIL")]:
    line = fri_start_line(rows)
    results.append((f"{what}: {want} ({line})", line.startswith(want + ":")))

# The follow check on a re-entry into command mode (lab_sim's truth columns applied, setpoint_*):
# the first entry must move the arm; a later one while the servo holds passes when commands are applied.
FULL = "t,krc_open,krc_state,krc_quality,krc_power,applied,flange_x,flange_y,flange_z,setpoint_x,setpoint_y,setpoint_z"


def reentry_dir(applies_after_drop, setpoint_moves):
    """CMD from 1 s (the arm approaching 5 mm/s) to 3 s, MON 3-4 s, CMD again from 4 s."""
    d = tempfile.mkdtemp(prefix="rehearsal_report_")
    applied, z = 0, 0.4
    with open(os.path.join(d, "truth.csv"), "w") as f:
        f.write(FULL + "\n")
        for k in range(600):
            t = 0.01 * k
            cmd = 1.0 <= t < 3.0 or t >= 4.0
            if cmd and (t < 3.0 or applies_after_drop):
                applied += 1
            if 1.0 <= t < 3.0 or (t >= 4.0 and setpoint_moves and applies_after_drop):
                z -= 0.00005
            f.write(f"{t:.3f},1,{'CMD' if cmd else 'MON'},{'PERFECT' if cmd else 'OK'},1,{applied},0.7,0,{z:.6f},0.7,0,{z:.6f}\n")
    with open(os.path.join(d, "lab_sim.log"), "w") as f:
        f.write("KRC max_step 0.0001 m\n")
    return d


for what, d, want in [
        ("a re-entry while holding, commands applied", reentry_dir(True, False), "PASS"),
        ("a re-entry while holding, no command applied", reentry_dir(False, False), "FAIL"),
        ("a re-entry with the set point moving and the arm following", reentry_dir(True, True), "PASS")]:
    done = subprocess.run([sys.executable, TOOL, "check", d], capture_output=True, text=True)
    lines = [ln.strip() for ln in done.stdout.splitlines() if "at t 4.00 s" in ln]
    line = lines[0] if lines else "(no line for the entry at 4 s) " + done.stdout + done.stderr
    results.append((f"{what}: {want} ({line})", line.startswith(want + ":")))

for what, ok in results:
    print(("ok    " if ok else "FAIL  ") + what)
sys.exit(0 if all(ok for _, ok in results) else 1)
