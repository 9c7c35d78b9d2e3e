"""One headless run: `tactile_sim run SCENE --out DIR --no-plots ARGS`."""
import json
import os
import subprocess

from . import scenes

SIM = scenes.SIM  # set by cli.parse_args(--sim)


def run(scene, out_dir, args=(), sim=None):
    """Runs the scene (a name of params/scenes) into out_dir; returns its
    summary.json as a dict with 'returncode' added (a run that wrote no
    summary gives {'status': 'no_summary', 'error': <stderr>, ...}). A run that
    ends at a safety limit (exit 3 or 4) is a result, not an error."""
    sim = sim or SIM  # the module value at call time (cli.parse_args may set it)
    cmd = [sim, "run", scenes.scene_path(scene), "--out", out_dir, "--no-plots", *args]
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    path = os.path.join(out_dir, "summary.json")
    if p.returncode == 2 or not os.path.exists(path):
        return {"status": "no_summary", "returncode": p.returncode, "error": p.stderr.strip(), "criteria_passed": False}
    with open(path) as f:
        d = json.load(f)
    d["returncode"] = p.returncode
    return d


def rel_err(v, ref):
    """Relative error; a metric defined on one side only (e.g. a recovery that
    never happened) counts as 100 %."""
    def bad(x):
        return x is None or (isinstance(x, float) and x != x)
    if bad(v) and bad(ref):
        return 0.0
    if bad(v) or bad(ref):
        return 1.0
    return abs(v - ref) / max(abs(ref), 1e-9)
