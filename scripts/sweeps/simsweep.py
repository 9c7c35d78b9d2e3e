"""Shared helpers of the sweep scripts (sweep_tradeoff.py, sweep_effects.py):
run `tactile_sim run` on a scene with overrides and read its summary.json.

Debian's /usr/bin/python3 with python3-yaml; no PyPI.
"""
import argparse
import glob
import json
import os
import subprocess

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SIM = os.path.join(ROOT, "build", "bin", "tactile_sim")
SCENE_DIR = os.path.join(ROOT, "sim", "scenes")

# Scene -> its key metrics (summary.json keys); scenes not listed use FORCE_METRICS.
KEY_METRICS = {
    "edge_exploration": ["alignment_time_s", "path_length_m", "force_true_mean_n"],
    "bent_bar": ["force_true_mean_n", "force_true_rms_error_n", "slide_speed_mps"],
    "co_manipulation": ["dzmp_recovery_time_s", "force_true_mean_n", "translation_x_m"],
    "bent_bar_fused": ["force_true_rms_error_n", "force_true_in_band_fraction", "slide_speed_mps"],
}
FORCE_METRICS = ["force_true_mean_n", "force_true_rms_error_n", "force_true_in_band_fraction"]


def scene_path(name):
    return os.path.join(SCENE_DIR, name + ".yaml")


# Scenes that are not experiments: bar_loop is the soak's (an hour long; its
# turns come from the deployment script scripts/realtime/rt_soak_sim.sh, not from the
# program), so the sweeps leave it out.
NOT_EXPERIMENTS = {"bar_loop"}


def shipped_scenes():
    """Names of the shipped experiment scenes (sim/scenes/*.yaml), sorted."""
    names = (os.path.splitext(os.path.basename(p))[0] for p in glob.glob(os.path.join(SCENE_DIR, "*.yaml")))
    return sorted(n for n in names if n not in NOT_EXPERIMENTS)


# The true-force targets (README "The true force on target"): RMS error and
# the share of the scored time within +-FORCE_BAND_N of the set point.
FORCE_BAND_N = 0.5
FORCE_RMS_MAX_N = 0.4
FORCE_IN_BAND_MIN = 0.95


def paper_program(scene):
    """The scene's program as the paper has it: the `*_paper.yaml` beside
    the scene's program (Eq. 2's force alone, CoP_y 0), or None where there is
    none (tests/runner/scene_run.hpp's loadPaper() finds it the same way)."""
    program = os.path.normpath(os.path.join(SCENE_DIR, load_scene(scene)["program"]))
    paper = program[:-len(".yaml")] + "_paper.yaml"
    return paper if os.path.exists(paper) else None


def key_metrics(scene):
    return KEY_METRICS.get(scene, FORCE_METRICS)


def load_scene(scene):
    with open(scene_path(scene)) as f:
        return yaml.safe_load(f)


def tray_index(scene):
    """Index of the tray in the scene's objects list, or None."""
    for i, o in enumerate(load_scene(scene).get("objects", []) or []):
        if o.get("type") == "tray":
            return i
    return None


def run(scene, out_dir, args=(), sim=None):
    """Runs `tactile_sim run SCENE --out OUT_DIR --no-plots ARGS`; returns the
    summary dict with 'returncode' added (a run that wrote no summary gives
    {'status': 'no_summary', ...} and the tool's stderr)."""
    sim = sim or SIM  # the module value at call time (parse_sweep_args may set it)
    cmd = [sim, "run", scene_path(scene), "--out", out_dir, "--no-plots", *args]
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


def parse_sweep_args(doc, out_name):
    """The common command line of the scene sweeps (sweep_force.py,
    sweep_speed.py): --out (made absolute and created), --jobs, --seeds, --sim
    (sets SIM for run())."""
    global SIM
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", out_name))
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--seeds", type=int, default=1)
    ap.add_argument("--sim", default=SIM)
    a = ap.parse_args()
    SIM = a.sim
    a.out = os.path.abspath(a.out)  # paths given to tactile_sim are read relative to the scene otherwise
    os.makedirs(a.out, exist_ok=True)
    return a
