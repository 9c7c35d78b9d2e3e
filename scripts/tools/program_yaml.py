"""Servo phase programs (components/servo/programs/*.yaml) as the servo reads
them: a file with `base: OTHER.yaml` is OTHER (path relative to the file) with
the file's own keys merged over it, by the rules of
components/servo/include/tactile_servo/program_io.hpp ("Overlays"):

  * a mapping merges key by key, recursively;
  * a list whose elements are all mappings with a `name` (the phases) merges
    element by element by name, in the base's order;
  * a scalar, any other list or a value of another kind replaces the base's;
  * `~` (None) removes the base's key;
  * a key or a name the base does not have is an error, as is a missing base
    file and a cycle of bases;
  * `add_phases` lists whole phases appended after the base's, each with a
    name the base's phases do not have.

load(path) returns the merged program (a dict without `base`); ProgramError
names the file and the key. The YAML is read with YAML 1.2 booleans only
(true/false), as yaml-cpp does: the transitions' key `on` stays a string.
"""

import copy
import os
import re

import yaml


class Loader(yaml.SafeLoader):
    """YAML 1.2 booleans only: the programs' key `on` must stay a string (YAML 1.1 reads it as true)."""


Loader.yaml_implicit_resolvers = {k: [r for r in v if r[0] != "tag:yaml.org,2002:bool"]
                                  for k, v in yaml.SafeLoader.yaml_implicit_resolvers.items()}
Loader.add_implicit_resolver("tag:yaml.org,2002:bool", re.compile(r"^(?:true|false)$"), list("tf"))

OVERLAY_RULE = "an overlay changes its base's keys, or removes one with ~"


class ProgramError(Exception):
    """A program file that cannot be read or merged; the message names the file and the key."""


def _named_list(v):
    return isinstance(v, list) and len(v) > 0 and all(
        isinstance(e, dict) and "name" in e and not isinstance(e["name"], (dict, list)) for e in v)


def _child(where, key):
    return key if not where else f"{where}.{key}"


def merge(base, over, file, base_file, where=""):
    """`over` merged into `base` (changed in place and returned)."""
    if _named_list(base) and _named_list(over):
        seen = set()
        names = [str(e["name"]) for e in base]
        for item in over:
            name = str(item["name"])
            w = f"{where}[{name}]"
            if name in seen:
                raise ProgramError(f"{file}: {w}: given twice")
            seen.add(name)
            if name not in names:
                raise ProgramError(f"{file}: {w}: no element named '{name}' in the base {base_file} "
                                   f"(names: {', '.join(names)}; {OVERLAY_RULE})")
            merge(base[names.index(name)], item, file, base_file, w)
        return base
    for k, v in over.items():
        w = _child(where, str(k))
        if k not in base:
            raise ProgramError(f"{file}: {w}: not in the base {base_file} ({OVERLAY_RULE})")
        b = base[k]
        if v is None:
            del base[k]
        elif (isinstance(b, dict) and isinstance(v, dict)) or (_named_list(b) and _named_list(v)):
            merge(b, v, file, base_file, w)
        else:
            base[k] = copy.deepcopy(v)
    return base


def _read(path):
    try:
        with open(path) as f:
            doc = yaml.load(f, Loader=Loader)
    except OSError as e:
        raise ProgramError(f"{path}: cannot open file ({e.strerror})") from None
    except yaml.YAMLError as e:
        raise ProgramError(f"{path}: YAML error: {e}") from None
    if not isinstance(doc, dict):
        raise ProgramError(f"{path}: top level must be a mapping")
    return doc


def load(path, _chain=()):
    """The program at `path` with its `base:` chain merged (a dict without `base`)."""
    doc = _read(path)
    if "base" not in doc:
        return doc
    rel = doc.pop("base")
    if not isinstance(rel, str) or not rel:
        raise ProgramError(f"{path}: base: must be the path of another program file (relative to this file)")
    base_file = rel if os.path.isabs(rel) else os.path.join(os.path.dirname(path), rel)
    chain = _chain + (os.path.realpath(path),)
    if os.path.realpath(base_file) in chain:
        loop = chain[chain.index(os.path.realpath(base_file)):] + (os.path.realpath(base_file),)
        raise ProgramError(f"{path}: base: '{rel}' is a cycle of bases: {' -> '.join(loop)}")
    if not os.path.exists(base_file):
        raise ProgramError(f"{path}: base: '{rel}': {base_file}: cannot open file")
    added = doc.pop("add_phases", None)
    merged = merge(load(base_file, chain), doc, path, base_file)
    if added is not None:
        append_phases(merged, added, path, base_file)
    return merged


def append_phases(merged, added, file, base_file):
    """An overlay's `add_phases`: whole phases after the base's, each with a name the base lacks."""
    if not _named_list(added):
        raise ProgramError(f"{file}: add_phases: must be a list of phases, each a mapping with a name")
    phases = merged.get("phases")
    if not _named_list(phases):
        raise ProgramError(f"{file}: add_phases: the base {base_file} has no list of phases to add to")
    in_base = len(phases)
    for item in added:
        name = str(item["name"])
        names = [str(p["name"]) for p in phases]
        if name in names:
            why = (f"a phase of that name is in the base {base_file} (change it under phases)"
                   if names.index(name) < in_base else "given twice")
            raise ProgramError(f"{file}: add_phases[{name}]: {why}")
        phases.append(copy.deepcopy(item))
