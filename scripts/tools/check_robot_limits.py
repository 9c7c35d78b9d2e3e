#!/usr/bin/python3
"""The robot experiments' programs against the FRI bridge's rate limits: a
program that asks for more speed than fri.yaml lets through would be clipped
by the bridge (status limited, out.limits) and run slower on the arm than
headless, with another force and another verdict. Each robot: true entry of
the registry (experiments.yaml), or each EXPERIMENT given, is checked:

  program safety.max_trans_speed (m/s)   <= fri.max_lin_speed (m/s)
  program safety.max_rot_speed_deg (deg/s) <= fri.max_rot_speed (rad/s)

(a key the program leaves out takes the servo's default, servo_params.hpp:
0.05 m/s, 50 deg/s). A mismatch names both files, both keys and both values.

usage: check_robot_limits.py [--registry experiments.yaml] [--fri-yaml FILE] [EXPERIMENT ...]
Exit: 0 every program within the limits, 1 a program above them, 2 usage or
an unreadable file. scripts/run_robot.sh runs it before it deploys.
"""
import argparse
import math
import os
import sys

import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import program_yaml  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
# The servo's defaults for a program without the key (core/servo/include/tactile_servo/servo_params.hpp).
DEFAULT_TRANS_MPS = 0.05
DEFAULT_ROT_DEG_S = 50.0


def check(registry_file, fri_file, names):
    """[(ok, message)] for each experiment's program."""
    reg = (yaml.safe_load(open(registry_file)) or {}).get("experiments") or {}
    fri = (yaml.safe_load(open(fri_file)) or {}).get("fri") or {}
    lin, rot = float(fri["max_lin_speed"]), float(fri["max_rot_speed"])
    base = os.path.dirname(os.path.abspath(registry_file))
    out = []
    for name in names or [n for n, e in reg.items() if e.get("robot")]:
        if name not in reg:
            raise ValueError(f"{registry_file}: no experiment {name} (experiments: {', '.join(reg)})")
        rel = reg[name]["program"]
        prog = program_yaml.load(rel if os.path.isabs(rel) else os.path.join(base, rel))
        safety = prog.get("safety", {}) or {}
        trans = float(safety.get("max_trans_speed", DEFAULT_TRANS_MPS))
        rot_deg = float(safety.get("max_rot_speed_deg", DEFAULT_ROT_DEG_S))
        ok_t, ok_r = trans <= lin + 1e-12, math.radians(rot_deg) <= rot + 1e-12
        out.append((ok_t, f"{name}: {rel} safety.max_trans_speed = {trans:g} m/s "
                          f"{'<=' if ok_t else '>'} {fri_file} fri.max_lin_speed = {lin:g} m/s"))
        out.append((ok_r, f"{name}: {rel} safety.max_rot_speed_deg = {rot_deg:g} deg/s "
                          f"({math.radians(rot_deg):.4g} rad/s) {'<=' if ok_r else '>'} {fri_file} "
                          f"fri.max_rot_speed = {rot:g} rad/s"))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--registry", default=os.path.join(ROOT, "experiments.yaml"))
    ap.add_argument("--fri-yaml", default=os.path.join(ROOT, "params/sensors/fri.yaml"))
    ap.add_argument("experiments", nargs="*")
    a = ap.parse_args()
    try:
        results = check(a.registry, a.fri_yaml, a.experiments)
    except (OSError, KeyError, ValueError, yaml.YAMLError, program_yaml.ProgramError) as e:
        print(f"check_robot_limits: {e}", file=sys.stderr)
        return 2
    for ok, what in results:
        print(("ok   " if ok else "FAIL ") + what)
    bad = sum(1 for ok, _ in results if not ok)
    print(f"check_robot_limits: {bad} program limit(s) above the bridge's" if bad else
          "check_robot_limits: every program within the bridge's rate limits")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
