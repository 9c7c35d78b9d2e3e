#!/usr/bin/python3
"""scripts/tools/registry.py: the experiment registry as the shell scripts
(run_experiment.sh, run_deployment.sh, run_robot.sh) read it, on a registry of
its own and on this tree's experiments.yaml. Usage: test_registry.py REPO_ROOT"""
import os
import subprocess
import sys
import tempfile

root = sys.argv[1]
tool = [sys.executable, os.path.join(root, "scripts", "tools", "registry.py")]
failures = []


def run(*args):
    p = subprocess.run(tool + list(args), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    return p.returncode, p.stdout, p.stderr


def check(what, ok):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


with tempfile.TemporaryDirectory() as d:
    reg = os.path.join(d, "experiments.yaml")
    with open(reg, "w") as f:
        f.write("experiments:\n"
                "  sim_only: {scene: params/scenes/a.yaml, program: a.yaml, controller: baseline}\n"
                "  on_arm: {scene: params/scenes/b.yaml, controller: ~, robot: true, program: p.yaml}\n")
    check("names: every entry, in the file's order", run("--file", reg, "names") == (0, "sim_only on_arm\n", ""))
    check("names --robot: only robot: true", run("--file", reg, "names", "--robot") == (0, "on_arm\n", ""))
    check("get: one field", run("--file", reg, "get", "sim_only", "controller") == (0, "baseline\n", ""))
    check("get: a null field is empty", run("--file", reg, "get", "on_arm", "controller") == (0, "\n", ""))
    check("get: an absent field is empty", run("--file", reg, "get", "sim_only", "title") == (0, "\n", ""))
    rc, out, err = run("--file", reg, "get", "nope", "scene")
    check("get: an unknown name exits 2 and names the file and the entries",
          rc == 2 and out == "" and reg in err and "'nope'" in err and "sim_only on_arm" in err)
    check("rows: NAME SCENE PROGRAM CONTROLLER, '-' for the program's own",
          run("--file", reg, "rows") == (0, "sim_only params/scenes/a.yaml a.yaml baseline\n"
                                            "on_arm params/scenes/b.yaml p.yaml -\n", ""))
    with open(os.path.join(d, "bad.yaml"), "w") as f:
        f.write("other: 1\n")
    rc, out, err = run("--file", os.path.join(d, "bad.yaml"), "names")
    check("a file without `experiments:` fails, named", rc != 0 and "bad.yaml" in err and "experiments" in err)

# This tree's registry: every name has a scene that exists.
rc, out, _ = run("names")
names = out.split()
check("this tree's registry has entries", rc == 0 and len(names) > 0)
for n in names:
    rc, out, _ = run("get", n, "scene")
    check(f"{n}: its scene exists", rc == 0 and os.path.isfile(os.path.join(root, out.strip())))
    rc, out, _ = run("get", n, "program")
    check(f"{n}: its program exists", rc == 0 and os.path.isfile(os.path.join(root, out.strip())))
sys.exit(1 if failures else 0)
