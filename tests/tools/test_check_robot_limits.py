#!/usr/bin/python3
"""scripts/tools/check_robot_limits.py: the robot experiments' programs
against the FRI bridge's rate limits. On this tree (the shipped fri.yaml and
programs) every robot experiment passes; on a fri.yaml with the former limits
(0.05 m/s, 0.25 rad/s) the speed-law program (0.12 m/s) and the 50 deg/s
programs fail, each message naming both files, both keys and both values; a
program without the keys takes the servo's defaults (0.05 m/s, 50 deg/s); an
unknown experiment exits 2. Usage: test_check_robot_limits.py REPO_ROOT"""
import os
import subprocess
import sys
import tempfile

TOOL = os.path.join(sys.argv[1], "scripts", "tools", "check_robot_limits.py")
results = []  # (what, ok), printed at the end


def run(*args):
    """(exit code, stdout, stderr) of check_robot_limits.py with ARGS."""
    done = subprocess.run([sys.executable, TOOL, *args], capture_output=True, text=True)
    return done.returncode, done.stdout, done.stderr


def check(what, ok):
    results.append((what, bool(ok)))


rc, out, _ = run()
check(f"the shipped fri.yaml covers every robot experiment's program (exit {rc})",
      rc == 0 and "FAIL" not in out and out.count("ok   ") == 2 * 9)
with tempfile.TemporaryDirectory() as d:
    fri = os.path.join(d, "fri.yaml")
    with open(fri, "w") as f:
        f.write("fri:\n  max_lin_speed: 0.05\n  max_rot_speed: 0.25\n")
    rc, out, _ = run("--fri-yaml", fri, "bent_bar_speed_law", "first_touch")
    check(f"the former limits: the speed law's 0.12 m/s refused (exit {rc})", rc == 1 and
          "FAIL bent_bar_speed_law: params/programs/bent_bar_speed_law.yaml safety.max_trans_speed = "
          f"0.12 m/s > {fri} fri.max_lin_speed = 0.05 m/s" in out)
    check("the former limits: 50 deg/s > 0.25 rad/s refused, named",
          "safety.max_rot_speed_deg = 50 deg/s (0.8727 rad/s) > " + fri + " fri.max_rot_speed = 0.25 rad/s" in out)
    check("the first touch (10 mm/s, 5 deg/s) within them",
          "ok   first_touch: params/programs/first_touch.yaml safety.max_trans_speed = 0.01 m/s" in out)
    # A registry of its own: a program without safety limits takes the servo's defaults.
    prog = os.path.join(d, "p.yaml")
    with open(prog, "w") as f:
        f.write("phases:\n  - name: hold\n")
    reg = os.path.join(d, "experiments.yaml")
    with open(reg, "w") as f:
        f.write(f"experiments:\n  bare: {{program: {prog}, robot: true}}\n")
    rc, out, _ = run("--registry", reg, "--fri-yaml", fri)
    check(f"no safety keys: the servo's 0.05 m/s and 50 deg/s (exit {rc})", rc == 1 and
          "ok   bare:" in out and "max_trans_speed = 0.05 m/s <=" in out and "max_rot_speed_deg = 50 deg/s" in out)
    rc, _, err = run("nope")
    check(f"an unknown experiment: exit 2, named ({err.strip()})", rc == 2 and "no experiment nope" in err)
for what, ok in results:
    print(("ok   " if ok else "FAIL ") + what)
failed = sum(1 for _, ok in results if not ok)
print(f"test_check_robot_limits: {failed} failed" if failed else "test_check_robot_limits: all passed")
sys.exit(1 if failed else 0)
