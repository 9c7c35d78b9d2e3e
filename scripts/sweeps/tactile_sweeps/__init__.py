"""The sweeps' shared pieces: run `tactile_sim run` over a grid of scenes and
settings, in parallel, and write the tables and plots.

  scenes     the repository's paths, the shipped scenes, a scene's YAML, its
             force band (metrics.force_band_n), its paper program, the key
             metrics, the true-force targets
  registry   experiments.yaml (the experiments: scene, program, controller, ...)
  run        run(scene, out_dir, args) -> summary.json as a dict; rel_err
  cli        parse_args(doc, out_name): --sim, --out, --seeds, --jobs
  parallel   pmap(fn, jobs, workers): each job's result in the jobs' order
  report     fmt() (the one number format of the tables), mean, write_csv
  plot       plt (Agg backend), save(fig, path)

A sweep imports it with its folder on sys.path (scripts/sweeps/):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import tactile_sweeps as ts
Debian's /usr/bin/python3 with python3-yaml, numpy and matplotlib; no PyPI.
"""
from . import cli, parallel, registry, report, run, scenes  # noqa: F401
from .cli import parse_args  # noqa: F401
from .parallel import pmap  # noqa: F401
from .report import fmt, mean, write_csv  # noqa: F401
from .run import rel_err  # noqa: F401
from .scenes import (EXPECTED_STOPS, STOP_FORCE_MAX_N, FORCE_BAND_N, FORCE_IN_BAND_MIN, FORCE_RMS_MAX_N, NOT_EXPERIMENTS, PROGRAMS, ROOT,  # noqa: F401
                     SCENE_DIR, TOOLS, force_band, key_metrics, load_scene, paper_program, scene_path,
                     shipped_scenes, tray_index)
