#!/usr/bin/python3
"""ctest ros_variants_complete: every deployment has its ROS variant, and the
variant deploys the same thing.

For each deployments/<experiment>_sim_run.ops there must be
<experiment>_sim_ros.ops, for each <experiment>_robot.ops an
<experiment>_robot_ros.ops; the variant must set the same Guard properties
(servo_cpf, sim_cpf, state_machine_file, state_machine, experiment) as the
non-ROS script and run the shared ROS start (ros_sim_start.ops or
ros_robot_start.ops), which ros_sim_streams and ros_robot_streams_* run.

    check_ros_variants.py DEPLOYMENTS_DIR
"""
import glob
import os
import re
import sys

SAME = ("experiment", "servo_cpf", "sim_cpf", "state_machine_file", "state_machine")


def guard(path):
    text = open(path).read()
    return dict(re.findall(r'^Guard\.(\w+) = (.*)$', text, re.M)), text


def main():
    d = sys.argv[1]
    failures, checked = [], 0
    pairs = []
    for base in sorted(glob.glob(os.path.join(d, "*_sim_run.ops"))):
        pairs.append((base, base[: -len("_sim_run.ops")] + "_sim_ros.ops", "ros_sim_start.ops"))
    for base in sorted(glob.glob(os.path.join(d, "*_robot.ops"))):
        pairs.append((base, base[: -len("_robot.ops")] + "_robot_ros.ops", "ros_robot_start.ops"))
    for base, ros, start in pairs:
        name = os.path.basename(ros)
        if not os.path.exists(ros):
            failures.append(f"{os.path.basename(base)} has no ROS variant {name}")
            continue
        g_base, _ = guard(base)
        g_ros, text = guard(ros)
        for k in SAME:
            if g_base.get(k) != g_ros.get(k):
                failures.append(f"{name}: Guard.{k} = {g_ros.get(k)} but {os.path.basename(base)} has {g_base.get(k)}")
        if f'runScript("{start}")' not in text:
            failures.append(f"{name} does not run {start}")
        checked += 1
    for f in failures:
        print("FAIL:", f)
    print(f"check_ros_variants: {checked} ROS variants checked, {len(failures)} failures")
    return 1 if failures or checked == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
