"""The experiment registry, experiments.yaml (repository root): one entry per
experiment (title, scene, program, controller, state_machine, timeout_s,
robot, metrics); paths relative to the repository root. Its `scenes:` (the
programs of the scenes no experiment runs) is read by `tactile_sim binding`."""
import os

import yaml

from .scenes import ROOT

PATH = os.path.join(ROOT, "experiments.yaml")


def load(path=PATH):
    """{name: entry} in the file's order."""
    with open(path) as f:
        d = yaml.safe_load(f) or {}
    if not isinstance(d.get("experiments"), dict):
        raise SystemExit(f"{path}: no `experiments:` mapping")
    return d["experiments"]


def experiments(path=PATH, robot=None):
    """The experiments' names in the file's order; robot=True/False: only those
    that do / do not run on the real arm."""
    return [n for n, e in load(path).items() if robot is None or bool(e.get("robot")) == robot]


def scene_name(entry):
    """The name of an entry's scene (params/scenes/<name>.yaml)."""
    return os.path.splitext(os.path.basename(entry["scene"]))[0]


def scenes(path=PATH):
    """The registry's scenes (names), each once, in the file's order."""
    out = []
    for e in load(path).values():
        n = scene_name(e)
        if n not in out:
            out.append(n)
    return out


def main(argv=None):
    """The registry for the shell scripts (scripts/tools/registry.py; run_experiment.sh, run_deployment.sh, run_robot.sh):
      registry.py names [--robot]   the names, one line, space-separated
      registry.py get NAME KEY      one field ('' when null or absent)
      registry.py rows              NAME SCENE PROGRAM CONTROLLER per line ('-': the program's own)
    An unknown name exits 2 with the names the registry has."""
    import argparse
    import sys
    ap = argparse.ArgumentParser(prog="registry.py", description=main.__doc__.splitlines()[0])
    ap.add_argument("--file", default=PATH, help="the registry (default: this tree's experiments.yaml)")
    sub = ap.add_subparsers(dest="cmd", required=True)
    n = sub.add_parser("names")
    n.add_argument("--robot", action="store_true", help="only those that run on the real arm (robot: true)")
    g = sub.add_parser("get")
    g.add_argument("name")
    g.add_argument("key")
    sub.add_parser("rows")
    a = ap.parse_args(argv)
    entries = load(a.file)
    if a.cmd == "names":
        print(" ".join(experiments(a.file, robot=True if a.robot else None)))
    elif a.cmd == "get":
        if a.name not in entries:
            sys.stderr.write(f"{a.file}: no experiment '{a.name}' (experiments: {' '.join(entries)})\n")
            return 2
        v = entries[a.name].get(a.key)
        print("" if v is None else v)
    else:
        for name, e in entries.items():
            print(name, e["scene"], e["program"], e.get("controller") or "-")
    return 0
