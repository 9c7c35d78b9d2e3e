"""Servo phase programs (params/programs/*.yaml) as the servo reads
them, for the scripts that read or derive programs: load(path) returns the
program with its `base:` chain merged, as printed by `tactile_sim program
PATH` (the servo's own reader, core/servo/include/tactile_servo/
program_io.hpp, "Overlays"). The overlay rules live in that one place; this
module only runs the tool.

The tool is $TACTILE_SIM if set, else build/bin/tactile_sim of this
checkout. ProgramError carries the tool's message, which names the file and
the key. The YAML is read with YAML 1.2 booleans only (true/false), as
yaml-cpp does: the transitions' key `on` stays a string.
"""

import os
import re
import subprocess

import yaml


class Loader(yaml.SafeLoader):
    """YAML 1.2 booleans only: the programs' key `on` must stay a string (YAML 1.1 reads it as true)."""


Loader.yaml_implicit_resolvers = {k: [r for r in v if r[0] != "tag:yaml.org,2002:bool"]
                                  for k, v in yaml.SafeLoader.yaml_implicit_resolvers.items()}
Loader.add_implicit_resolver("tag:yaml.org,2002:bool", re.compile(r"^(?:true|false)$"), list("tf"))

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


class ProgramError(Exception):
    """A program file that cannot be read or merged; the message names the file and the key."""


def tool(sim=None):
    """The tactile_sim that reads the programs: `sim`, $TACTILE_SIM or this checkout's build."""
    return sim or os.environ.get("TACTILE_SIM") or os.path.join(ROOT, "build", "bin", "tactile_sim")


def load(path, sim=None):
    """The program at `path` with its `base:` chain merged (a dict without `base`)."""
    exe = tool(sim)
    if not os.access(exe, os.X_OK):
        raise ProgramError(f"{path}: cannot read it: {exe} is not built (scripts/setup/build.sh)")
    p = subprocess.run([exe, "program", path], capture_output=True, text=True)
    if p.returncode != 0:
        raise ProgramError(p.stderr.strip().removeprefix("tactile_sim: "))
    doc = yaml.load(p.stdout, Loader=Loader)
    if not isinstance(doc, dict):
        raise ProgramError(f"{path}: top level must be a mapping")
    return doc


def program_of(scene, sim=None):
    """The path of the program a run of the scene file takes: the one the
    experiment registry binds to it (`tactile_sim binding SCENE`)."""
    p = subprocess.run([tool(sim), "binding", scene], capture_output=True, text=True)
    if p.returncode != 0:
        raise ProgramError(p.stderr.strip() or f"tactile_sim binding {scene}: exit {p.returncode}")
    return p.stdout.strip()
