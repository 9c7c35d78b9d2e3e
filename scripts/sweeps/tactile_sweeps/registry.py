"""The experiment registry, experiments.yaml (repository root): one entry per
experiment (title, scene, program, controller, state_machine, timeout_s,
robot, metrics); paths relative to the repository root."""
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
    """The name of an entry's scene (sim/scenes/<name>.yaml)."""
    return os.path.splitext(os.path.basename(entry["scene"]))[0]


def scenes(path=PATH):
    """The registry's scenes (names), each once, in the file's order."""
    out = []
    for e in load(path).values():
        n = scene_name(e)
        if n not in out:
            out.append(n)
    return out
