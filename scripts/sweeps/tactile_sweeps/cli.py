"""The sweeps' common command line."""
import argparse
import os

from . import run, scenes


def parser(doc, out_name, jobs=None, seeds=1):
    """--out (default out/<out_name>), --jobs (default: the cores), --seeds
    (runs seeds 1..N; seeds=None: a sweep without seeds), --sim (the
    tactile_sim binary); add the sweep's own arguments, then call finish()."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(scenes.ROOT, "out", out_name))
    ap.add_argument("--jobs", type=int, default=jobs or os.cpu_count() or 1)
    if seeds is not None:
        ap.add_argument("--seeds", type=int, default=seeds)
    ap.add_argument("--sim", default=run.SIM)
    return ap


def finish(a):
    """Sets the binary for run.run(), makes --out absolute (tactile_sim reads
    relative paths against the scene) and creates it."""
    run.SIM = a.sim = a.sim or run.SIM
    a.out = os.path.abspath(a.out)
    os.makedirs(a.out, exist_ok=True)
    return a


def parse_args(doc, out_name, jobs=None, seeds=1):
    """parser() and finish() for a sweep with only the common arguments."""
    return finish(parser(doc, out_name, jobs, seeds).parse_args())
