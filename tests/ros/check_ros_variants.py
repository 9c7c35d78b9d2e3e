#!/usr/bin/python3
"""ctest ros_variants_complete: every deployment entry script has its ROS
variant, and the variant deploys the same thing.

deployments/sim_run.ops has sim_ros.ops, robot.ops has robot_ros.ops; the
variant must select the experiment as the non-ROS script does (the same
Guard.select / Guard.step lines before its start: the registry's entry from
TACTILE_EXPERIMENT), set no per-experiment file itself, and run the shared ROS
start (ros_sim_start.ops or ros_robot_start.ops), which ros_sim_streams and
ros_robot_streams_* run.

    check_ros_variants.py DEPLOYMENTS_DIR
"""
import os
import re
import sys

# Per-experiment settings come from the registry (Guard.select): an entry script sets none.
PER_EXPERIMENT = ("servo_cpf", "sim_cpf", "state_machine_file", "state_machine", "program_file", "scene_file")


def selection(path):
    """The entry's lines that select the experiment (Guard.select and its checks)."""
    text = open(path).read()
    return [ln for ln in text.splitlines() if ln.startswith(("Guard.step(Guard.select", "if Guard.ok then Guard.step(Guard.robot"))], text


def main():
    d = sys.argv[1]
    failures, checked = [], 0
    pairs = [(os.path.join(d, "sim_run.ops"), os.path.join(d, "sim_ros.ops"), "ros_sim_start.ops"),
             (os.path.join(d, "robot.ops"), os.path.join(d, "robot_ros.ops"), "ros_robot_start.ops")]
    for base, ros, start in pairs:
        name = os.path.basename(ros)
        if not os.path.exists(base):
            failures.append(f"no entry script {os.path.basename(base)}")
            continue
        if not os.path.exists(ros):
            failures.append(f"{os.path.basename(base)} has no ROS variant {name}")
            continue
        sel_base, text_base = selection(base)
        sel_ros, text = selection(ros)
        if not sel_base or sel_base != sel_ros:
            failures.append(f"{name} selects {sel_ros} but {os.path.basename(base)} {sel_base}")
        for t, n in ((text_base, os.path.basename(base)), (text, name)):
            for k in re.findall(r'^Guard\.(\w+) = ', t, re.M):
                if k in PER_EXPERIMENT:
                    failures.append(f"{n} sets Guard.{k} itself (the registry's entry gives it)")
        if f'runScript("{start}")' not in text:
            failures.append(f"{name} does not run {start}")
        checked += 1
    for f in failures:
        print("FAIL:", f)
    print(f"check_ros_variants: {checked} ROS variants checked, {len(failures)} failures")
    return 1 if failures or checked == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
