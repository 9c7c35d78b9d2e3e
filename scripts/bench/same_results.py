#!/usr/bin/python3
"""Benchmark (not a test): the evidence that a change kept the behaviour.
Runs every experiment of the registry (experiments.yaml, with its controller)
and every scene of params/scenes (with the program the registry binds to it) headless with
one tactile_sim, and writes a fingerprint: for each run the SHA-256 of its
summary.json without the wall-clock fields (wall_time_s, real_time_factor)
and of its timeseries.csv, contacts.csv and snapshots.csv. Two fingerprints,
taken with the binaries before and after a change, compare equal when every
run is bit-identical.

usage: same_results.py run --sim TACTILE_SIM --out DIR [--jobs N]   (writes DIR/fingerprint.json)
       same_results.py deployed --root CHECKOUT --out DIR   (writes DIR/fingerprint.json)
       same_results.py compare A/fingerprint.json B/fingerprint.json   (exit 1 on any difference)

`deployed` runs every experiment of CHECKOUT's registry through
CHECKOUT/scripts/run_deployment.sh (its build: the OCL deployer, simulated
time) one after the other, and fingerprints the run directories the same
way, the checkout's path in summary.json written as <root>: the reporter's
table (report.dat) carries a wall-clock TimeStamp column and is left out;
what the deployment computed is in the files made from it. Two checkouts
built before and after a change compare equal when every deployed run is
bit-identical.
"""
import argparse
import concurrent.futures
import glob
import hashlib
import json
import os
import re
import subprocess
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
WALL = re.compile(r'^\s*"(wall_time_s|real_time_factor)": .*\n', re.M)


def jobs():
    rows = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "scripts", "tools", "registry.py"), "rows"],
                          check=True, capture_output=True, text=True).stdout.split("\n")
    out = []
    for row in filter(None, rows):
        name, scene, program, controller = row.split()
        args = ["--program", os.path.join(ROOT, program)]
        out.append((name, scene, args if controller == "-" else args + ["--controller", controller]))
    for scene in sorted(glob.glob(os.path.join(ROOT, "params", "scenes", "**", "*.yaml"), recursive=True)):
        rel = os.path.relpath(scene, ROOT)
        out.append(("scene_" + rel[len("params/scenes/"):-5].replace("/", "_"), rel, []))
    return out


def digest(path, strip_wall=False, root=None):
    try:
        with open(path) as f:
            text = f.read()
    except OSError:
        return None
    if strip_wall:
        text = WALL.sub("", text)
    if root:
        text = text.replace(root, "<root>")
    return hashlib.sha256(text.encode()).hexdigest()


def fingerprint(d, returncode, root=None):
    files = {"summary.json": digest(os.path.join(d, "summary.json"), strip_wall=True, root=root)}
    for f in ("timeseries.csv", "contacts.csv", "snapshots.csv"):
        files[f] = digest(os.path.join(d, f))
    return {"exit": returncode, "files": files}


def one(sim, out, job):
    name, scene, args = job
    d = os.path.join(out, name)
    p = subprocess.run([sim, "run", os.path.join(ROOT, scene), "--out", d, "--no-plots"] + args,
                       capture_output=True, text=True)
    return name, fingerprint(d, p.returncode)


def deployed(a):
    root = os.path.realpath(a.root)
    names = subprocess.run(["/usr/bin/python3", os.path.join(root, "scripts", "tools", "registry.py"), "names"],
                           check=True, capture_output=True, text=True).stdout.split()
    out = os.path.realpath(a.out)
    os.makedirs(out, exist_ok=True)
    result = {}
    for k, name in enumerate(names, 1):
        p = subprocess.run(["bash", os.path.join(root, "scripts", "run_deployment.sh"), name],
                           env=dict(os.environ, DEPLOY_OUT=out), capture_output=True, text=True)
        result[name] = fingerprint(os.path.join(out, name), p.returncode, root=root)
        print(f"[{k}/{len(names)}] {name}: exit {p.returncode}", flush=True)
    with open(os.path.join(out, "fingerprint.json"), "w") as f:
        json.dump(result, f, indent=1, sort_keys=True)
    return 0


def run(a):
    os.makedirs(a.out, exist_ok=True)
    todo = jobs()
    result = {}
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        for k, (name, r) in enumerate(pool.map(lambda j: one(a.sim, a.out, j), todo), 1):
            result[name] = r
            print(f"[{k}/{len(todo)}] {name}: exit {r['exit']}", flush=True)
    with open(os.path.join(a.out, "fingerprint.json"), "w") as f:
        json.dump(result, f, indent=1, sort_keys=True)
    return 0


def compare(a):
    with open(a.a) as f:
        x = json.load(f)
    with open(a.b) as f:
        y = json.load(f)
    bad = [n for n in sorted(set(x) | set(y)) if x.get(n) != y.get(n)]
    for n in bad:
        print(f"differs: {n}: {x.get(n)} vs {y.get(n)}")
    print(f"same_results: {len(set(x) & set(y)) - len([n for n in bad if n in x and n in y])} of {len(set(x) | set(y))} "
          f"runs identical (summary.json without its wall-clock fields, timeseries, contacts, snapshots)")
    return 1 if bad else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("--sim", required=True)
    r.add_argument("--out", required=True)
    r.add_argument("--jobs", type=int, default=2)
    d = sub.add_parser("deployed")
    d.add_argument("--root", required=True)
    d.add_argument("--out", required=True)
    c = sub.add_parser("compare")
    c.add_argument("a")
    c.add_argument("b")
    a = ap.parse_args()
    return {"run": run, "deployed": deployed, "compare": compare}[a.cmd](a)


if __name__ == "__main__":
    sys.exit(main())
