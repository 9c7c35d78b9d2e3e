#!/usr/bin/python3
"""ctest FirstTouch_check_detects: check_first_touch.py can fail. One run of
the shipped first touch (tactile_sim), checked against copies of the program
whose limits that run breaks; each must fail with the line that names it:

  max_trans_speed 0.004 m/s (the approach runs at 0.005)   -> FAIL commanded speed
  force_ceiling 1.5 N (the hold presses ~1.95 N)           -> FAIL true force
  workspace z max 0.395 m (the run starts at 0.40)         -> FAIL commanded flange
  the run read as the no-object case                       -> FAIL approach, no_contact
and the shipped program itself passes (exit 0).

usage: first_touch_check_detects.py TACTILE_SIM SOURCE_DIR WORK_DIR
"""
import os
import shutil
import subprocess
import sys

import yaml

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "tools"))
import program_yaml  # noqa: E402  (a program as the servo merges it: tactile_sim program)

sim, src, work = sys.argv[1:4]
check = os.path.join(src, "tests", "runner", "check_first_touch.py")
program = os.path.join(src, "params", "programs", "first_touch.yaml")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
run = os.path.join(work, "run")
subprocess.run([sim, "run", os.path.join(src, "params", "scenes", "first_touch.yaml"), "--out", run, "--no-plots"],
               check=True, stdout=subprocess.DEVNULL)
failures = []


def checker(prog, mode):
    p = subprocess.run(["/usr/bin/python3", check, run, prog, mode], stdout=subprocess.PIPE, text=True)
    return p.returncode, p.stdout


def variant(name, edit):
    doc = program_yaml.load(program)  # its base merged: a whole program
    edit(doc)
    path = os.path.join(work, name + ".yaml")
    yaml.safe_dump(doc, open(path, "w"))
    return path


rc, out = checker(program, "touch")
print(f"shipped program: exit {rc}")
if rc != 0:
    failures.append(f"the shipped program fails its own check:\n{out}")

cases = [
    ("slow", lambda d: d["safety"].update(max_trans_speed=0.004), "touch", "FAIL commanded speed"),
    ("low_ceiling", lambda d: d["safety"].update(force_ceiling=1.5), "touch", "FAIL true force"),
    ("low_box", lambda d: d["safety"]["workspace"]["max"].__setitem__(2, 0.395), "touch", "FAIL commanded flange"),
    ("as_no_object", lambda d: None, "no_object", "FAIL approach, no_contact"),
]
for name, edit, mode, expect in cases:
    rc, out = checker(variant(name, edit), mode)
    fails = [l for l in out.splitlines() if l.startswith("FAIL")]
    ok = rc == 1 and any(l.startswith(expect) for l in fails)
    print(f"{'ok  ' if ok else 'FAIL'} {name}: exit {rc}, {fails}")
    if not ok:
        failures.append(f"{name}: expected exit 1 with a line '{expect}...', got exit {rc}:\n{out}")

for f in failures:
    print("FAIL:", f)
print(f"first_touch_check_detects: {len(cases) + 1} cases, {len(failures)} failures")
sys.exit(1 if failures else 0)
