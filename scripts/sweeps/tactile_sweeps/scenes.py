"""The repository's paths and what the sweeps read from the scenes
(params/scenes/*.yaml)."""
import glob
import os

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
SCENE_DIR = os.path.join(ROOT, "params", "scenes")
PROGRAMS = os.path.join(ROOT, "params", "programs")
TOOLS = os.path.join(ROOT, "scripts", "tools")  # contour_check.py, plot_run.py, ...
SIM = os.path.join(ROOT, "build", "bin", "tactile_sim")

# The true-force targets (docs/simulator.md, "Known bias of the paper's force"): RMS error and
# the share of the scored time within +-FORCE_BAND_N of the set point. The
# sweeps that score every scene against these targets pass the band to the
# runner (--set metrics.force_band_n=FORCE_BAND_N) in place of the scene's
# own (force_band()); the others score with the scene's band.
FORCE_BAND_N = 0.5
FORCE_RMS_MAX_N = 0.4
FORCE_IN_BAND_MIN = 0.95

# The runner's band where a scene sets none (core/sim/runner/include/tactile_sim_runner/scene.hpp).
RUNNER_FORCE_BAND_N = 1.0

# Scene -> its key metrics (summary.json keys); scenes not listed use FORCE_METRICS.
KEY_METRICS = {
    "edge_exploration": ["alignment_time_s", "path_length_m", "force_true_mean_n"],
    "bent_bar": ["force_true_mean_n", "force_true_rms_error_n", "slide_speed_mps"],
    "co_manipulation": ["dzmp_recovery_time_s", "force_true_mean_n", "translation_x_m"],
    "bent_bar_fused": ["force_true_rms_error_n", "force_true_in_band_fraction", "slide_speed_mps"],
}
FORCE_METRICS = ["force_true_mean_n", "force_true_rms_error_n", "force_true_in_band_fraction"]

# Scenes that are not experiments: bar_loop is the soak's (an hour long; its
# turns come from the deployment script scripts/realtime/rt_soak_sim.sh, not
# from the program), so the sweeps leave it out.
NOT_EXPERIMENTS = {"bar_loop"}
# Scenes whose run must end with a servo stop (status) before the true force
# reaches STOP_FORCE_MAX_N, not follow the bar: the registry's tight_wave, a
# wave tighter than the rigid pad follows (docs/design.md, "Safety").
EXPECTED_STOPS = {"tight_wave": "servo_surface_too_curved"}
STOP_FORCE_MAX_N = 7.0


def scene_path(name):
    return os.path.join(SCENE_DIR, name + ".yaml")


def load_scene(name):
    with open(scene_path(name)) as f:
        return yaml.safe_load(f)


def shipped_scenes():
    """Names of the shipped experiment scenes (params/scenes/*.yaml), sorted."""
    names = (os.path.splitext(os.path.basename(p))[0] for p in glob.glob(os.path.join(SCENE_DIR, "*.yaml")))
    return sorted(n for n in names if n not in NOT_EXPERIMENTS)


def force_band(name):
    """N: the band the scene scores its true force in (metrics.force_band_n;
    the runner's 1 N where the scene sets none)."""
    return float((load_scene(name).get("metrics") or {}).get("force_band_n", RUNNER_FORCE_BAND_N))


def program_of(name):
    """The path of the program a run of the scene takes (the one the
    experiment registry binds to it: `tactile_sim binding`)."""
    import sys
    sys.path.insert(0, TOOLS)
    import program_yaml
    return program_yaml.program_of(scene_path(name))


def paper_program(name):
    """The scene's program as the paper has it: the `*_paper.yaml` beside the
    scene's program (Eq. 2's force alone, CoP_y 0), or None where there is
    none (tests/runner/scene_run.hpp's loadPaper() finds it the same way)."""
    program = program_of(name)
    paper = program[:-len(".yaml")] + "_paper.yaml"
    return paper if os.path.exists(paper) else None


def key_metrics(name):
    return KEY_METRICS.get(name, FORCE_METRICS)


def tray_index(name):
    """Index of the tray in the scene's objects list, or None."""
    for i, o in enumerate(load_scene(name).get("objects", []) or []):
        if o.get("type") == "tray":
            return i
    return None
